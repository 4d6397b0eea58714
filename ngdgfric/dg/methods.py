"""The five DG methods of Section 3 and a conforming baseline as data rows, and what their penalty
parameter eta means.

All five DG methods share the volume and consistency terms of B_h (:mod:`ngdgfric.dg.forms`) and differ in a
sign, a penalty and a lifting term:

    method   s    penalty on E_h^o                  global lifting   eta          default eta     stable for
    sipg    +1    eta p^2 / h_e [u]:[v]             -                a stress     30 mu (*)       eta > t_p (2 mu + lam)
    nipg    -1    eta p^2 / h_e [u]:[v]             -                a stress     30 mu           eta > 0
    bassi   +1    sum_e eta (C r_e[u], r_e[v])      -                1            6               eta > 3
    brezzi  +1    sum_e eta (C r_e[u], r_e[v])      (C r_0, r_0)     1            1               eta > 0
    ldg     +1    eta p^2 / h_e [u]:[v]             (C r_0, r_0)     a stress     30 mu           eta > 0
    cg      +1    on supports only (Nitsche)        -                a stress     30 mu (*)       eta > t_p (2 mu + lam)

``cg`` is the conforming baseline of issue 28: u_h continuous (H^1 elements of degree p_T, edges of the larger
neighbouring degree), so that every interior jump [u_h] vanishes and with it every term of B_h on E_h^i; what
remains is the volume term and SIPG's terms on the supported sides (Nitsche's method for u = u_D and for the
symmetry sides), the same contact terms, solver, estimator (eta_3 only on the supports) and hp machinery.  On a
mesh and order it is the DG solution restricted to conforming functions: fewer DOFs (about p^2 / 2 per component and
element on large meshes against (p + 1)(p + 2) / 2), no skeleton assembly; it locks like any conforming P_p element
for nu -> 1/2 at low p and needs data jumps on mesh edges as every method does.

30 mu is the paper's choice (Section 6).  (*) For SIPG the default is raised to 1.5 times the
threshold where 30 mu is not above it (nearly incompressible materials: the threshold grows like
2 mu + lam); both examples of the paper keep 30 mu.  Where the material varies, mu and lam are those
of each element (:mod:`ngdgfric.dg.material`) and an edge's default eta is the harmonic mean of the two
neighbours' defaults (:func:`penalty`).  t_p is :data:`SIPG_THRESHOLD`, measured.
Bassi et al.: eta > 3, the number of edges of a triangle (Arnold, Brezzi, Cockburn, Marini 2002,
for liftings into a space containing eps_h(V_h)); sufficient, the measured threshold is lower.
Brezzi et al.: any eta > 0 is stable, the global lifting term adds stability.

Volumetric locking (:data:`LOCKING`, measured by ``scripts/locking.py``, results/locking.md): on a divergence-free
contact solution cg and SIPG lock at p = 1, 2, 3 (from nu = 0.49 and 0.497: SIPG through its raised penalty), LDG at
every p from nu = 0.4997-0.4999; NIPG, Bassi et al. and Brezzi et al. do not (error growth at most x1.17 up to
nu = 0.49999), nor cg and SIPG at p = 4.  :class:`~ngdgfric.Discretization` warns (:class:`LockingWarning`,
:func:`check_locking`) where the chosen method locks at the problem's largest nu and the lowest element degree.
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
"""Smallest coercive SIPG penalty as eta / (2 mu + lam), per order (p > 4: the p = 4 value).

Measured by ``scripts/stability.py`` (results/stability.md): the smallest eigenvalue of
B_h(v, v) / |||v|||_h^2 changes sign at eta / (2 mu + lam) = 3.3-4.0 (p = 1), 1.85-2.15 (p = 2),
1.5-1.74 (p = 3), 1.35-1.52 (p = 4) for nu = 0 ... 0.49 on the structured meshes of Examples
6.1 and 6.2, independently of h; the table takes the largest, rounded up."""


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
"""Where each method locks, per degree p = 1, 2, 3, 4 (None: not up to nu = 0.49999; p > 4: the p = 4 entry), with
its default penalty: a :class:`Locking` or None.

Measured by ``scripts/locking.py`` (results/locking.md) on the divergence-free contact solution of
:func:`ngdgfric.studies.manufactured.incompressible_contact_manufactured` (E = 1000), uniform meshes h = 1/4 ... 1/32
(P1, P2) and 1/4 ... 1/16 (P3, P4), nu = 0.3, 0.45, 0.47, 0.49, 0.497, 0.499, 0.4997, 0.4999, 0.49999: a method locks
from the first nu of that grid from which on its error grows more than twice its value at nu = 0.3 on some mesh or
its rate falls below p - 1/2.  cg and SIPG at p = 1-3 (their rates fall to p - 1 at nu = 0.49999) and LDG (rates
intact, errors 6.6-8.8 times larger) lock; NIPG, Bassi et al. and Brezzi et al. grow by at most 1.17 times, cg and
SIPG at p = 4 by 1.84 and 1.94 times with the rate 3.96 (bounded growth, no locking)."""


@dataclass(frozen=True)
class Method:
    """One row of the table in the module docstring.

    symmetry: s in -s <[u], {sigma(v)}>; penalty: "edge" (eta p^2/h_e [u]:[v], eta a stress) or
    "lift" (sum_e eta (C r_e[u], r_e[v]), eta dimensionless); global_lift: adds (C r_0[u], r_0[v]);
    default_eta: the default eta in units of :meth:`eta_scale`; thresholds: the smallest stable eta
    per order p = 1, 2, ... (the last one for higher p) in units of :meth:`threshold_scale`, empty
    if any eta > 0 is stable; conforming: u_h in H^1 (no terms on interior edges); locking: where it locks as
    nu -> 1/2, one :class:`Locking` or None per order p = 1, 2, ... (the last one for higher p; :data:`LOCKING`).
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
        """The unit of eta: mu for the edge penalties (eta is a stress), 1 for the liftings (``law``: anything
        with Lame parameters ``mu``, ``lam``: a problem, or one side's :class:`~ngdgfric.dg.material.Lame`)."""
        return law.mu if self.penalty == "edge" else 1.0

    def threshold_scale(self, law):
        """The unit of the coercivity thresholds: 2 mu + lam for the edge penalties, 1 for the liftings."""
        return 2 * law.mu + law.lam if self.penalty == "edge" else 1.0

    def threshold(self, law, order):
        """The smallest stable eta for degree ``order`` (None: any eta > 0 is stable)."""
        if not self.thresholds:
            return None
        return self.thresholds[min(int(order), len(self.thresholds)) - 1] * self.threshold_scale(law)

    def default(self, law, order=1):
        """The default eta (table above): ``default_eta`` times :meth:`eta_scale`, raised to 1.5 times the
        threshold where it is not above it (pointwise, ``IfPos``, for Lame parameters that vary)."""
        eta = self.default_eta * self.eta_scale(law)
        threshold = self.threshold(law, order)
        if threshold is None:
            return eta
        if isinstance(threshold, ngs.CoefficientFunction) or isinstance(eta, ngs.CoefficientFunction):
            return ngs.IfPos(eta - threshold, eta, 1.5 * threshold)
        return 1.5 * threshold if eta <= threshold else eta

    def locking_at(self, order):
        """The :class:`Locking` of degree ``order`` (the last entry for higher degrees), None if it does not lock."""
        return self.locking[min(int(order), len(self.locking)) - 1] if self.locking else None

    def locks(self, nu, order=None):
        """Whether this method locks at Poisson's ratio ``nu`` with elements of degree ``order`` (None: of some
        degree), by :data:`LOCKING`."""
        found = self.locking if order is None else (self.locking_at(order),)
        return any(entry is not None and nu >= entry.nu for entry in found)

    def jump_weight(self, material, penalty):
        """The factor of p^2 / h_e ||[u]||_e^2 that the penalty amounts to (estimator term eta_3,
        coercivity), an :class:`~ngdgfric.dg.material.EdgeCoefficient`: the penalty itself for the edge
        penalties; (C r_e, r_e) ~ 2 mu / h_e ||[u]||^2 for the liftings, so 2 mu_e eta there (mu_e the
        harmonic mean across the edge)."""
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
"""The five DG methods of Section 3 (:data:`METHODS` without the conforming baseline)."""


def get_method(name):
    """The :class:`Method` called ``name`` (case-insensitive); ValueError for an unknown name."""
    key = str(name).lower()
    if key not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {name!r}")
    return METHODS[key]


class PenaltyWarning(UserWarning):
    """The penalty parameter is at or below the method's coercivity threshold."""


def check_penalty(law, method, eta, order, action="warn"):
    """Warn (``action="warn"``), raise ValueError (``"raise"``) or do nothing (``"ignore"``) when
    eta is at or below :meth:`Method.threshold` (``law``: a problem, or Lame parameters of numbers: for a
    varying material the largest, :meth:`ngdgfric.dg.material.Material.largest`)."""
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
    """The chosen method locks at the problem's Poisson's ratio with the lowest element degree (:data:`LOCKING`,
    measured in results/locking.md): its error is several times what a method that does not lock gives; the message
    names what to use instead.  Silence it with the warning filters (``warnings.simplefilter("ignore",
    ndf.LockingWarning)``)."""


def check_locking(nu, method, order):
    """Warn (:class:`LockingWarning`) where ``method`` locks at Poisson's ratio ``nu`` (the largest on the mesh)
    with elements of degree ``order`` (the lowest), by :meth:`Method.locks`; the message names the measured
    consequence (:class:`Locking`), the methods that do not lock at degree ``order`` at all (up to nu = 0.49999)
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
