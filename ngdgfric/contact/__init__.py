r"""Contact on :math:`\Gamma_C`: normal compliance (1.8) and friction (1.9)-(1.10), in one package.

- :mod:`~ngdgfric.contact.laws`: the laws, each once, as CoefficientFunctions and as numpy functions side by side;
- :mod:`~ngdgfric.contact.boundary`: the edges of a boundary part, the contact Gauss rule and points, the
  multiplier space and multiplier values at the points;
- :mod:`~ngdgfric.contact.traces`: the traces :math:`B` of :math:`V_h` at the Gauss points and the laws' data there;
- :mod:`~ngdgfric.contact.curves`: a pair's sides as curves and the closest-point search on them;
- :mod:`~ngdgfric.contact.pairing`: two bodies in contact (:class:`~ngdgfric.ContactPair`): the closest-point map
  from one side onto the other and the pair's points on the common refinement of the two sides' edges;
- :mod:`~ngdgfric.contact.pair_traces`: the rows of :math:`B` at those points, for :math:`[u] = u^1 - u^2 \circ \pi`;
- :mod:`~ngdgfric.contact.pair_residuals`: the pairs' terms of the residual estimator on both sides;
- :mod:`~ngdgfric.contact.discrete`: :class:`~ngdgfric.Contact`, the contact data of one mesh, built beside the
  :class:`~ngdgfric.dg.discretization.Discretization`;
- :mod:`~ngdgfric.contact.forms`: the contact forms of (3.1), the residual of (3.3), the estimator's contact
  residuals;
- :mod:`~ngdgfric.contact.state`: a solution's state on :math:`\Gamma_C` and its KKT residuals;
- :mod:`~ngdgfric.contact.pair_state`: a solution's state at the pairs' points (the jump, the forces, the
  multiplier);
- :mod:`~ngdgfric.contact.forces`: contact resultants and the contact, stick and slip zones per side;
- :mod:`~ngdgfric.contact.pair_zones`: the same on both sides of each contact pair.

Nothing here imports :mod:`ngdgfric.dg` or :mod:`ngdgfric.solvers`.
"""

from .discrete import Contact
from .pair_state import pair_state
from .state import contact_state, kkt_residuals, rounding_residual, transitions

__all__ = ["Contact", "contact_state", "pair_state", "kkt_residuals", "rounding_residual", "transitions"]
