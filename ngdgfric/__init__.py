"""ngdgfric: DG methods for frictional contact with normal compliance on NGSolve.

Porwal & Tanvi, "Unified analysis of DG methods for frictional contact problem with normal
compliance": model (1.1)-(1.10), DG forms of Section 3, Uzawa solver of Section 6.

The entry points (solve, finish, estimate, adapt) limit OpenBLAS to NGDGFRIC_BLAS_THREADS threads
(default 1) while they run (:func:`ngdgfric.linalg.blas_threads`); importing changes nothing.
"""

from .adaptivity import Adaptation, adapt, dorfler_mark, minimum_angle, refine
from .contact import contact_state, kkt_residuals
from .discretization import Discretization
from .domain import Domain, Loop
from .errors import SolverError, TimeLimitError
from .estimator import Estimate, estimate
from .examples import example, example_6_1, example_6_2
from .forces import ForceBalance, force_balance
from .hp import HPState, hp_refine
from .material import MaterialWarning
from .meshes import check_mesh, netgen_mesh, uniform_mesh
from .methods import DG_METHODS, METHODS
from .problem import ContactProblem, Polygon
from .problem_file import example_file, load_problem
from .reference import Reference, energy_error, energy_norm, load_reference, save_reference
from .solution import Solution, finish, solve
from .transfer import WarmStart

__all__ = ["ContactProblem", "Polygon", "Domain", "Loop", "example", "example_6_1", "example_6_2", "load_problem",
           "example_file",
           "uniform_mesh", "netgen_mesh", "check_mesh", "Discretization", "METHODS", "DG_METHODS",
           "solve", "finish", "Solution", "WarmStart", "SolverError", "TimeLimitError", "MaterialWarning",
           "contact_state", "kkt_residuals", "force_balance", "ForceBalance",
           "estimate", "Estimate", "dorfler_mark", "refine", "adapt", "Adaptation", "minimum_angle",
           "HPState", "hp_refine",
           "energy_norm", "Reference", "energy_error", "load_reference", "save_reference"]
