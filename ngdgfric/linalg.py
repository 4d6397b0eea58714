"""``ngdgfric.linalg`` of release 0.1, split into :mod:`ngdgfric.sparse` and :mod:`ngdgfric.threads` in 0.2.

A stub kept for one release (it goes in 0.3): importing it warns (DeprecationWarning, at the importing line), and
its attributes are the names of those two modules (``from ngdgfric.linalg import BlockSum, limited_blas``).
"""

from . import sparse as _sparse
from . import threads as _threads
from .errors import warn as _warn

_warn(f"{__name__} moved to ngdgfric.sparse and ngdgfric.threads in ngdgfric 0.2; the old path goes in 0.3",
      DeprecationWarning)


def __getattr__(name):
    """The attribute ``name`` of :mod:`ngdgfric.sparse`, else of :mod:`ngdgfric.threads`."""
    for module in (_sparse, _threads):
        if hasattr(module, name):
            return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
