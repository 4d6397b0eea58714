"""The import path ``ngdgfric.nonlinear`` of release 0.1, now :mod:`ngdgfric.solvers.nonlinear`.

Kept for one release (it goes in 0.3): importing it warns (a DeprecationWarning at the importing line) and gives
the module at its new place, to which this stub rebinds its name in ``sys.modules``.
"""

import sys

from .errors import warn
from .solvers import nonlinear as _new

warn(f"{__name__} moved to {_new.__name__} in ngdgfric 0.2; the old path goes in 0.3", DeprecationWarning)
sys.modules[__name__] = _new
