"""``python -m ngdgfric``: the command line of :mod:`ngdgfric.cli`."""

import sys

from .cli import main

sys.exit(main())
