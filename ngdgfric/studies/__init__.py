r"""Study helpers for the scripts and the tests, outside the numerical core.

:mod:`~ngdgfric.studies.uniform`: uniform meshes :math:`h = 2^{-k}` and consecutive differences (Tables 6.1, 6.2);
:mod:`~ngdgfric.studies.strategies`: uniform, h- and hp-refinement measured against a reference;
:mod:`~ngdgfric.studies.measures`: observed rates, slopes and relative differences;
:mod:`~ngdgfric.studies.cases`: single cases of the stability study, run through
:mod:`~ngdgfric.studies.runner` (dask.distributed, cached on disk);
:mod:`~ngdgfric.studies.manufactured`: manufactured solutions; :mod:`~ngdgfric.studies.paper`: the
paper's printed tables; :mod:`~ngdgfric.studies.curved` (curved boundaries) and :mod:`~ngdgfric.studies.scenes`
(everyday scenes with exact or reference solutions): the scenes beyond the paper's rectangles.
"""

from .measures import max_rel_diff, rates, slope
from .strategies import STRATEGIES, strategy_run
from .uniform import consecutive_differences, difference_norms, uniform_study

__all__ = ["uniform_study", "difference_norms", "consecutive_differences", "strategy_run", "STRATEGIES", "rates",
           "slope", "max_rel_diff"]
