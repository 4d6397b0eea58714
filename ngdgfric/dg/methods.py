r"""The five DG methods of Section 3 and a conforming baseline as data rows, and what their penalty
parameter eta means.

All five DG methods share the volume and consistency terms of :math:`B_h` (:mod:`ngdgfric.dg.forms`) and differ
in a sign :math:`s` (the consistency term :math:`-s \langle [u], \{\sigma(v)\} \rangle`), a penalty and a
lifting term:

.. list-table:: The methods (:data:`ngdgfric.METHODS`)
   :header-rows: 1

   * - method
     - :math:`s`
     - penalty on :math:`\mathcal{E}_h^o`
     - global lifting
     - unit of :math:`\eta`
     - default :math:`\eta`
     - stable for
   * - ``sipg``
     - :math:`+1`
     - :math:`\eta\, p^2 / h_e \, [u] : [v]`
     - none
     - a stress
     - :math:`30 \mu` (*)
     - :math:`\eta > t_p (2 \mu + \lambda)`
   * - ``nipg``
     - :math:`-1`
     - :math:`\eta\, p^2 / h_e \, [u] : [v]`
     - none
     - a stress
     - :math:`30 \mu`
     - :math:`\eta > 0`
   * - ``bassi``
     - :math:`+1`
     - :math:`\sum_e \eta\, (C r_e([u]), r_e([v]))`
     - none
     - 1
     - 6
     - :math:`\eta > 3`
   * - ``brezzi``
     - :math:`+1`
     - :math:`\sum_e \eta\, (C r_e([u]), r_e([v]))`
     - :math:`(C r_0([u]), r_0([v]))`
     - 1
     - 1
     - :math:`\eta > 0`
   * - ``ldg``
     - :math:`+1`
     - :math:`\eta\, p^2 / h_e \, [u] : [v]`
     - :math:`(C r_0([u]), r_0([v]))`
     - a stress
     - :math:`30 \mu`
     - :math:`\eta > 0`
   * - ``cg``
     - :math:`+1`
     - on supports only (Nitsche)
     - none
     - a stress
     - :math:`30 \mu` (*)
     - :math:`\eta > t_p (2 \mu + \lambda)`

``cg`` is the conforming baseline: :math:`u_h` continuous (:math:`H^1` elements of degree :math:`p_T`, edges of
the larger neighbouring degree), so that every interior jump :math:`[u_h]` vanishes and with it every term of
:math:`B_h` on :math:`\mathcal{E}_h^i`; what remains is the volume term and SIPG's terms on the supported sides
(Nitsche's method for :math:`u = u_D` and for the symmetry sides), the same contact terms, solver, estimator
(:math:`\eta_3` only on the supports) and hp machinery.  On a mesh and order it is the DG solution restricted to
conforming functions: fewer DOFs (about :math:`p^2 / 2` per component and element on large meshes against
:math:`(p + 1)(p + 2) / 2`), no skeleton assembly; it locks like any conforming :math:`P_p` element for
:math:`\nu \to 1/2` at low :math:`p` and needs data jumps on mesh edges as every method does.

:math:`30 \mu` is the paper's choice (Section 6).  (*) For SIPG the default is raised to 1.5 times the
threshold where :math:`30 \mu` is not above it (nearly incompressible materials: the threshold grows like
:math:`2 \mu + \lambda`); both examples of the paper keep :math:`30 \mu`.  Where the material varies, :math:`\mu`
and :math:`\lambda` are those of each element (:mod:`ngdgfric.dg.material`) and an edge's default :math:`\eta` is
the harmonic mean of the two neighbours' defaults (``penalty``).  :math:`t_p` is ``SIPG_THRESHOLD``, measured:
4.0, 2.2, 1.75, 1.55 for :math:`p = 1, 2, 3, 4` (:math:`p > 4`: the :math:`p = 4` value).
Bassi et al.: :math:`\eta > 3`, the number of edges of a triangle (Arnold, Brezzi, Cockburn, Marini 2002,
for liftings into a space containing :math:`\epsilon_h(V_h)`); sufficient, the measured threshold is lower.
Brezzi et al.: any :math:`\eta > 0` is stable, the global lifting term adds stability.

Volumetric locking (``LOCKING``, measured by ``scripts/locking.py``, the results page *Volumetric locking*): on a
divergence-free contact solution cg and SIPG lock at :math:`p = 1, 2, 3` (from :math:`\nu = 0.49` and
:math:`0.497`: SIPG through its raised penalty), LDG at every :math:`p` from :math:`\nu = 0.4997`-:math:`0.4999`;
NIPG, Bassi et al. and Brezzi et al. do not (error growth at most :math:`\times 1.17` up to :math:`\nu = 0.49999`),
nor cg and SIPG at :math:`p = 4`.  :class:`~ngdgfric.Discretization` warns (:class:`~ngdgfric.LockingWarning`,
``check_locking``) where the chosen method locks at the problem's largest :math:`\nu` and the lowest element
degree.
"""

from dataclasses import dataclass
from numbers import Real
from types import MappingProxyType

import ngsolve as ngs

from ..errors import warn
from .material import EdgeCoefficient

__all__ = ["Method", "METHODS", "DG_METHODS", "get_method", "SIPG_THRESHOLD", "PenaltyWarning", "check_penalty",
           "penalty", "Locking", "LOCKING", "LockingWarning", "check_locking"]

SIPG_THRESHOLD = {1: 4.0, 2: 2.2, 3: 1.75, 4: 1.55}
r"""Smallest coercive SIPG penalty as :math:`\eta / (2 \mu + \lambda)`, per order (:math:`p > 4`: the :math:`p = 4`
value).

Measured by ``scripts/stability.py`` (the results page *Stability*): the smallest eigenvalue of
:math:`B_h(v, v) / \|v\|_h^2` changes sign at :math:`\eta / (2 \mu + \lambda)` = 3.3-4.0 (:math:`p = 1`),
1.85-2.15 (:math:`p = 2`), 1.5-1.74 (:math:`p = 3`), 1.35-1.52 (:math:`p = 4`) for :math:`\nu = 0, \dots, 0.49` on
the structured meshes of Examples 6.1 and 6.2, independently of :math:`h`; the table takes the largest, rounded
up."""


@dataclass(frozen=True)
class Locking:
    """Where a method locks at one degree p (an entry of :data:`LOCKING`): from Poisson's ratio ``nu`` on (the first
    such nu of the measured grid) its relative energy error on a divergence-free contact solution is more than twice
    its value at nu = 0.3 or converges at a rate below p - 1/2; ``growth``: that ratio at ``nu``, ``worst``: at
    nu = 0.49999 (each the largest over the meshes measured)."""

    nu: float
    growth: float
    worst: float


LOCKING = MappingProxyType({
    "sipg": (Locking(0.497, 2.35, 12.6), Locking(0.497, 2.45, 10.0), Locking(0.497, 2.34, 6.18), None),
    "nipg": (None, None, None, None),
    "bassi": (None, None, None, None),
    "brezzi": (None, None, None, None),
    "ldg": (Locking(0.4999, 2.29, 6.61), Locking(0.4997, 2.06, 7.69), Locking(0.4999, 2.99, 8.82),
            Locking(0.4999, 2.62, 7.46)),
    "cg": (Locking(0.49, 2.34, 11.3), Locking(0.49, 2.38, 9.45), Locking(0.49, 2.28, 5.82), None),
})
r"""Where each method locks, per degree :math:`p = 1, 2, 3, 4` (None: not up to :math:`\nu = 0.49999`; :math:`p > 4`:
the :math:`p = 4` entry), with its default penalty: a ``Locking`` or None.

Measured by ``scripts/locking.py`` (the results page *Volumetric locking*) on the divergence-free contact solution
of ``incompressible_contact_manufactured`` of :mod:`ngdgfric.studies.manufactured` (:math:`E = 1000`), uniform
meshes :math:`h = 1/4, \dots, 1/32` (P1, P2) and :math:`1/4, \dots, 1/16` (P3, P4), :math:`\nu` = 0.3, 0.45, 0.47,
0.49, 0.497, 0.499, 0.4997, 0.4999, 0.49999: a method locks from the first :math:`\nu` of that grid from which on
its error grows more than twice its value at :math:`\nu = 0.3` on some mesh or its rate falls below
:math:`p - 1/2`.  cg and SIPG at :math:`p = 1`-3 (their rates fall to :math:`p - 1` at :math:`\nu = 0.49999`) and
LDG (rates intact, errors 6.6-8.8 times larger) lock; NIPG, Bassi et al. and Brezzi et al. grow by at most 1.17
times, cg and SIPG at :math:`p = 4` by 1.84 and 1.94 times with the rate 3.96 (bounded growth, no locking)."""


@dataclass(frozen=True)
class Method:
    r"""One DG method (or the conforming baseline): a row of the table of :mod:`ngdgfric.dg.methods`.

    The rows are the values of :data:`ngdgfric.METHODS`; :func:`ngdgfric.solve` takes a method by its name.

    Parameters
    ----------
    name : str
        The name: ``"sipg"``, ``"nipg"``, ``"bassi"``, ``"brezzi"``, ``"ldg"`` or ``"cg"``.
    symmetry : int
        :math:`s` in the consistency term :math:`-s \langle [u], \{\sigma(v)\} \rangle`: :math:`+1` or
        :math:`-1` (NIPG).
    penalty : str
        ``"edge"`` (:math:`\eta\, p^2 / h_e \, [u] : [v]`, :math:`\eta` a stress) or ``"lift"``
        (:math:`\sum_e \eta\, (C r_e([u]), r_e([v]))`, :math:`\eta` dimensionless).
    global_lift : bool
        Whether :math:`B_h` has the global lifting term :math:`(C r_0([u]), r_0([v]))` (Brezzi et al., LDG).
    default_eta : float
        The default :math:`\eta` in units of :meth:`~ngdgfric.Method.eta_scale`.
    thresholds : tuple of float
        The smallest stable :math:`\eta` per order :math:`p = 1, 2, \dots` (the last one for higher :math:`p`)
        in units of :meth:`~ngdgfric.Method.threshold_scale`; empty if any :math:`\eta > 0` is stable.
    reference : str
        The method's name in the paper, ``"B_h^(1), SIPG"``, ...
    conforming : bool, optional
        :math:`u_h \in H^1` (no terms on interior edges).  Default ``False``.
    locking : tuple, optional
        Where it locks as :math:`\nu \to 1/2`: one ``Locking`` (the Poisson's ratio from which on it locks,
        ``nu``, and the measured error growth there, ``growth``, and at :math:`\nu = 0.49999`, ``worst``) or
        None per order :math:`p = 1, 2, \dots` (the last one for higher :math:`p`; measured, ``LOCKING``).
        Default ``()``: it does not lock.

    Examples
    --------
    >>> sipg = ndf.METHODS["sipg"]
    >>> sipg.symmetry, sipg.penalty, sipg.default_eta
    (1, 'edge', 30.0)
    >>> print(f"{sipg.default(ndf.example('6.1')):.1f}")
    21428.6
    """

    name: str
    symmetry: int
    penalty: str
    global_lift: bool
    default_eta: float
    thresholds: tuple
    reference: str
    conforming: bool = False
    locking: tuple = ()

    def eta_scale(self, law):
        r"""The unit of :math:`\eta`: :math:`\mu` for the edge penalties (:math:`\eta` is a stress), 1 for the liftings.

        Parameters
        ----------
        law : ContactProblem
            Anything with Lamé parameters ``mu``, ``lam``: a problem, or one side's ``Lame`` of
            :mod:`ngdgfric.dg.material`.

        Returns
        -------
        float or CoefficientFunction
            :math:`\mu` or 1.
        """
        return law.mu if self.penalty == "edge" else 1.0

    def threshold_scale(self, law):
        r"""The unit of the coercivity thresholds: :math:`2 \mu + \lambda` for the edge penalties, 1 for the liftings.

        Parameters
        ----------
        law : ContactProblem
            Anything with Lamé parameters ``mu``, ``lam``.

        Returns
        -------
        float or CoefficientFunction
            :math:`2 \mu + \lambda` or 1.
        """
        return 2 * law.mu + law.lam if self.penalty == "edge" else 1.0

    def threshold(self, law, order):
        r"""The smallest stable :math:`\eta` for degree ``order`` (None: any :math:`\eta > 0` is stable).

        Parameters
        ----------
        law : ContactProblem
            Anything with Lamé parameters ``mu``, ``lam``.
        order : int
            The polynomial degree :math:`p`.

        Returns
        -------
        float, CoefficientFunction or None
            The threshold, in the units of :math:`\eta`.
        """
        if not self.thresholds:
            return None
        return self.thresholds[min(int(order), len(self.thresholds)) - 1] * self.threshold_scale(law)

    def default(self, law, order=1):
        r"""The default :math:`\eta` (the table of :mod:`ngdgfric.dg.methods`).

        ``default_eta`` times :meth:`~ngdgfric.Method.eta_scale`, raised to 1.5 times the threshold where it is not
        above it (pointwise, ``IfPos``, for Lamé parameters that vary).

        Parameters
        ----------
        law : ContactProblem
            Anything with Lamé parameters ``mu``, ``lam``.
        order : int, optional
            The polynomial degree :math:`p`.  Default ``1``.

        Returns
        -------
        float or CoefficientFunction
            The default penalty.
        """
        eta = self.default_eta * self.eta_scale(law)
        threshold = self.threshold(law, order)
        if threshold is None:
            return eta
        if isinstance(threshold, ngs.CoefficientFunction) or isinstance(eta, ngs.CoefficientFunction):
            return ngs.IfPos(eta - threshold, eta, 1.5 * threshold)
        return 1.5 * threshold if eta <= threshold else eta

    def locking_at(self, order):
        """The ``Locking`` entry of degree ``order`` (the last entry for higher degrees), None if it does not lock."""
        return self.locking[min(int(order), len(self.locking)) - 1] if self.locking else None

    def locks(self, nu, order=None):
        """Whether this method locks at Poisson's ratio ``nu`` with elements of degree ``order``.

        Parameters
        ----------
        nu : float
            Poisson's ratio.
        order : int or None, optional
            The element degree; None: of some degree.  Default ``None``.

        Returns
        -------
        bool
            Whether it locks, by the measured table ``LOCKING``.
        """
        found = self.locking if order is None else (self.locking_at(order),)
        return any(entry is not None and nu >= entry.nu for entry in found)

    def jump_weight(self, material, penalty):
        r"""The factor of :math:`p^2 / h_e \|[u]\|_e^2` that the penalty amounts to (estimator term :math:`\eta_3`,
        coercivity).

        The penalty itself for the edge penalties; :math:`(C r_e, r_e) \sim 2 \mu / h_e \|[u]\|^2` for the
        liftings, so :math:`2 \mu_e \eta` there (:math:`\mu_e` the harmonic mean across the edge).

        Parameters
        ----------
        material : Material
            The ``Material`` of :mod:`ngdgfric.dg.material`.
        penalty : EdgeCoefficient
            The penalty on every edge (``Discretization.penalty``).

        Returns
        -------
        EdgeCoefficient
            The weight, an ``EdgeCoefficient`` of :mod:`ngdgfric.dg.material`.
        """
        if self.penalty == "edge":
            return penalty
        return material.harmonic(lambda law: 2 * law.mu, "2 mu").scaled(penalty.boundary, "2 mu eta")


METHODS = MappingProxyType({
    "sipg": Method("sipg", +1, "edge", False, 30.0, tuple(SIPG_THRESHOLD.values()), "B_h^(1), SIPG",
                   locking=LOCKING["sipg"]),
    "nipg": Method("nipg", -1, "edge", False, 30.0, (), "B_h^(2), NIPG", locking=LOCKING["nipg"]),
    "bassi": Method("bassi", +1, "lift", False, 6.0, (3.0,), "B_h^(3), Bassi et al.", locking=LOCKING["bassi"]),
    "brezzi": Method("brezzi", +1, "lift", True, 1.0, (), "B_h^(4), Brezzi et al.", locking=LOCKING["brezzi"]),
    "ldg": Method("ldg", +1, "edge", True, 30.0, (), "B_h^(5), LDG", locking=LOCKING["ldg"]),
    "cg": Method("cg", +1, "edge", False, 30.0, tuple(SIPG_THRESHOLD.values()), "conforming H^1, Nitsche on supports",
                 conforming=True, locking=LOCKING["cg"]),
})
"""Every method by name (read-only): the five DG methods of Section 3 and the conforming baseline ``cg``."""
DG_METHODS = tuple(name for name, method in METHODS.items() if not method.conforming)
"""The five DG methods of Section 3 (:data:`ngdgfric.METHODS` without the conforming baseline)."""


def get_method(name):
    """The :class:`Method` called ``name`` (case-insensitive); ValueError for an unknown name."""
    key = str(name).lower()
    if key not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {name!r}")
    return METHODS[key]


class PenaltyWarning(UserWarning):
    r"""The penalty parameter is at or below the method's coercivity threshold.

    Issued by :func:`ngdgfric.solve` and :class:`~ngdgfric.Discretization` (``penalty_check="warn"``, the
    default) when a given :math:`\eta` is at or below :meth:`~ngdgfric.Method.threshold`: :math:`B_h` may not be
    coercive and the solution may be meaningless.  ``penalty_check="raise"`` makes it a ValueError,
    ``"ignore"`` silences it.
    """


def check_penalty(law, method, eta, order, action="warn"):
    """Warn (``action="warn"``), raise ValueError (``"raise"``) or do nothing (``"ignore"``) when
    eta is at or below :meth:`ngdgfric.Method.threshold` (``law``: a problem, or Lame parameters of numbers: for a
    varying material the largest, ``Material.largest``)."""
    if action not in ("warn", "raise", "ignore"):
        raise ValueError(f"penalty_check must be 'warn', 'raise' or 'ignore', got {action!r}")
    threshold = method.threshold(law, order)
    if action == "ignore" or threshold is None or not isinstance(eta, Real) or eta > threshold:
        return
    message = (f"eta = {eta:g} is at or below the coercivity threshold {threshold:g} of {method.name} "
               f"for order {order}: B_h may not be coercive and the solution may be meaningless")
    if action == "raise":
        raise ValueError(message)
    warn(message, PenaltyWarning)


class LockingWarning(UserWarning):
    """The chosen method locks at the problem's Poisson's ratio with the lowest element degree.

    Issued by :class:`~ngdgfric.Discretization` (so by :func:`ngdgfric.solve` too) by the measured table of
    :mod:`ngdgfric.dg.methods` (the results page *Volumetric locking*): the method's error is several times what a
    method that does not lock gives; the message names what to use instead.  Silence it with the warning filters
    (``warnings.simplefilter("ignore", ndf.LockingWarning)``).
    """


def check_locking(nu, method, order):
    """Warn (:class:`LockingWarning`) where ``method`` locks at Poisson's ratio ``nu`` (the largest on the mesh)
    with elements of degree ``order`` (the lowest), by :meth:`ngdgfric.Method.locks`; the message names the measured
    consequence (``Locking``), the methods that do not lock at degree ``order`` at all (up to nu = 0.49999)
    and the lowest degree at which ``method`` does not lock at ``nu``, if any."""
    order = int(order)
    if not method.locks(nu, order):
        return
    found = method.locking_at(order)
    instead = [m.name for m in sorted(METHODS.values(), key=lambda m: m.symmetry != 1) if m.locking_at(order) is None]
    higher = next((q for q in range(order + 1, len(method.locking) + 1) if not method.locks(nu, q)), None)
    names = [f"'{name}'" for name in instead]
    use = [f"method={names[0] if len(names) == 1 else ', '.join(names[:-1]) + ' or ' + names[-1]} "
           f"({'it does' if len(names) == 1 else 'they do'} not lock up to nu = 0.49999)"] if names else []
    use += [f"order >= {higher}"] if higher is not None else []
    warn(f"{method.name} with elements of degree {order} locks at nu = {nu:.6g}: on a divergence-free contact "
         f"solution its energy error grows to {found.growth:.3g} times its value at nu = 0.3 at nu = {found.nu:g} and "
         f"to {found.worst:.3g} times at nu = 0.49999 (results/locking.md)."
         + (f"  Use {', or '.join(use)}." if use else ""), LockingWarning)


def penalty(method, material, eta, order):
    """eta as the :class:`~ngdgfric.dg.material.EdgeCoefficient` of the forms: a given number (or
    CoefficientFunction) on every edge; by default :meth:`Method.default` of each side's material, the
    harmonic mean of the two neighbours' values on interior edges (a number for a constant material)."""
    if eta is not None:
        return EdgeCoefficient(eta, eta, f"{eta:g}" if isinstance(eta, Real) else "eta")
    if method.penalty == "lift" or material.constant:
        value = method.default(material.own, order)
        return EdgeCoefficient(value, value, f"{value:g}")
    raised = " (raised to 1.5 x the coercivity threshold where that is larger)" if method.thresholds else ""
    return material.harmonic(lambda law: method.default(law, order),
                             f"{method.default_eta:g} mu{raised}, harmonic mean of the neighbours' values")
