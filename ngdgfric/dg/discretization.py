"""The discrete problem (3.1)/(3.3) on one mesh: its spaces and the matrices of its linear part.

The contact part (multiplier space, contact Gauss points, traces, forms) is :class:`ngdgfric.Contact`,
built beside it.
"""

import time
from numbers import Integral, Real

import ngsolve as ngs
import numpy as np

from ..checks import MEMORY_BUDGET, check_data, check_size
from ..contact.boundary import contact_edges
from ..meshes import check_mesh, curve
from ..problem import ContactProblem
from ..threads import threads
from .forms import FormsContext, dg_terms, edge_length, load_terms, penalty_length
from .liftings import lifting_terms
from .material import Lame, Material, largest
from .methods import check_locking, check_penalty, get_method, penalty

__all__ = ["Discretization", "dg_space", "conforming_space", "space", "polynomial_degrees", "edge_orders",
           "check_order", "MAX_DEGREE", "order_function", "most_common_degree"]


def dg_space(mesh, order, dgjumps=True):
    """V_h: discontinuous vector polynomials of degree ``order`` (Section 2.1).

    ``order``: p, or an integer array with the degree p_T of every element (hp).
    ``dgjumps=False`` gives the same space and numbering without the facet couplings in the
    matrix pattern; mixed forms with the multiplier space need it (NGSolve 6.2.2608 crashes
    assembling a mixed skeleton form whose test space has ``dgjumps=True``).
    """
    if np.ndim(order) == 0:
        return ngs.L2(mesh, order=int(order), dgjumps=dgjumps) ** 2
    order = np.asarray(order)
    base = most_common_degree(order)
    scalar = ngs.L2(mesh, order=base, dgjumps=dgjumps)
    for nr in np.flatnonzero(order != base):  # only scalar L2 has SetOrder: build Q**2 from it
        scalar.SetOrder(ngs.NodeId(ngs.ELEMENT, int(nr)), int(order[nr]))
    scalar.Update()
    return scalar**2


def most_common_degree(orders):
    """The most common of the element degrees ``orders`` (non-negative integers; of equally common ones the smallest).

    Spaces of variable order are made with this degree, and SetOrder (one Python call per node) is called only on
    the nodes of other degrees: the same space with the fewest calls (:ref:`decisions-discretization`).
    """
    return int(np.bincount(np.asarray(orders, dtype=np.int64)).argmax())


def element_edges(mesh):
    """The three edge numbers of every element, an (ne, 3) integer array."""
    return np.array([[edge.nr for edge in element.edges] for element in mesh.Elements(ngs.VOL)], dtype=np.int64)


def edge_orders(mesh, orders, raised=()):
    """The degree of every edge of the conforming space of element degrees ``orders``: the larger of its
    elements' (the maximum rule: every element keeps all polynomials of its degree); the edges numbered in
    ``raised`` get the largest degree of all (:func:`conforming_space`)."""
    result = np.zeros(mesh.nedge, dtype=np.int64)
    orders = np.asarray(orders, dtype=np.int64)
    np.maximum.at(result, element_edges(mesh).ravel(), np.repeat(orders, 3))
    result[list(raised)] = orders.max()
    return result


def polynomial_degrees(disc):
    """The largest polynomial degree of u_h on every element of a :class:`Discretization`: p_T for the DG
    methods, for the conforming baseline the largest degree of the element and its edges (:func:`edge_orders`)."""
    orders, mesh = disc.orders, disc.mesh
    if not disc.method.conforming or np.all(orders == orders[0]):
        return orders
    edges = edge_orders(mesh, orders, contact_edges(disc.problem, mesh))
    return np.maximum(orders, edges[element_edges(mesh)].max(axis=1))


def conforming_space(mesh, order, raised=()):
    """The conforming baseline's V_h (:data:`ngdgfric.dg.methods.METHODS` ``"cg"``): continuous vector polynomials,
    H^1 elements of degree ``order`` (p, or an integer array of p_T, one per element), each edge of the degree of
    :func:`edge_orders`.  ``raised``: edges that get the largest degree whatever their elements' (the edges on
    Gamma_C, so that the traces there are of degree p on every edge and the contact Gauss points, p per edge,
    independent: :attr:`ngdgfric.Contact.order`)."""
    if np.ndim(order) == 0:
        return ngs.VectorH1(mesh, order=int(order))
    order = np.asarray(order)
    base = most_common_degree(order)
    scalar = ngs.H1(mesh, order=base)
    for nr in np.flatnonzero(order != base):
        scalar.SetOrder(ngs.NodeId(ngs.ELEMENT, int(nr)), int(order[nr]))
    edges = edge_orders(mesh, order, raised)
    for nr in np.flatnonzero(edges != base):
        scalar.SetOrder(ngs.NodeId(ngs.EDGE, int(nr)), int(edges[nr]))
    scalar.Update()
    return scalar**2


def space(problem, mesh, order, method, dgjumps=True):
    """V_h of ``method`` (a :class:`~ngdgfric.dg.methods.Method`): :func:`conforming_space` (its edges on Gamma_C
    raised) for the conforming baseline, else :func:`dg_space` (``dgjumps``: see there)."""
    if method.conforming:
        return conforming_space(mesh, order, contact_edges(problem, mesh) if np.ndim(order) else ())
    return dg_space(mesh, order, dgjumps)


MAX_DEGREE = 30
"""The largest polynomial degree of an element: degree 30 assembles (Example 6.1 at h = 1/2, 7,936 DOFs, 6.8 s),
degree 33 overflows NGSolve's local heap in the assembly (PyPI wheel 6.2.2608)."""


def check_order(order, mesh=None):
    """``order`` validated: an int 1 <= p <= :data:`MAX_DEGREE`, or (with ``mesh``) an integer array of such p_T, one
    per element."""
    if np.ndim(order) == 0:
        if not isinstance(order, Integral) or isinstance(order, bool) or not 1 <= order <= MAX_DEGREE:
            raise ValueError(f"order must be an integer in 1..{MAX_DEGREE}, got {order!r}")
        return int(order)
    orders = np.asarray(order)
    if (mesh is None or orders.shape != (mesh.ne,) or not np.issubdtype(orders.dtype, np.integer)
            or not 1 <= orders.min() <= orders.max() <= MAX_DEGREE):
        raise ValueError(f"order must be an integer in 1..{MAX_DEGREE} or an integer array of such orders, one per "
                         f"element{'' if mesh is None else f' ({mesh.ne})'}, got shape {orders.shape}, dtype "
                         f"{orders.dtype}, values {orders.min(initial=0)}..{orders.max(initial=0)}")
    return orders.astype(np.int64)


def order_function(mesh, order):
    """p_T as a piecewise constant GridFunction (``order`` itself if it is a number)."""
    if np.ndim(order) == 0:
        return order
    p = ngs.GridFunction(ngs.L2(mesh, order=0))
    p.vec.FV().NumPy()[:] = order
    return p


def _check_eta(eta):
    if isinstance(eta, ngs.CoefficientFunction):
        return eta
    if not isinstance(eta, Real) or isinstance(eta, bool) or not np.isfinite(eta) or eta <= 0:
        raise ValueError(f"eta must be a positive number, got {eta!r}")
    return float(eta)


class Discretization:
    r"""Everything of (3.3) that does not depend on the solution, built once per mesh.

    The spaces, the matrix of :math:`B_h` and the load vector; :func:`ngdgfric.solve` builds one and keeps it as
    ``Solution.discretization``.  Before assembly: the mesh must fit the problem (:func:`ngdgfric.check_mesh`),
    the DOFs the size limit ``max_ndof`` (None: the memory limit ``max_bytes``, ``check_size`` of
    :mod:`ngdgfric.checks`) and the data be valid pointwise (:mod:`ngdgfric.checks`).  On a domain with curved
    sides the mesh is curved to the largest order (``curve`` of :mod:`ngdgfric.meshes`; the solution's own copy
    of the mesh, :func:`ngdgfric.solve`).

    Parameters
    ----------
    problem : ContactProblem
        The contact problem.
    mesh : ngsolve.Mesh
        A mesh of the problem's domain.
    method : str, optional
        A name of :data:`ngdgfric.METHODS` (case-insensitive).  Default ``"sipg"``.
    order : int or array_like of int, optional
        The polynomial degree :math:`1 \le p \le 30` (``MAX_DEGREE``), or an integer array with the degree
        :math:`p_T` of every element (hp).  Default ``1``.
    eta : float, CoefficientFunction or None, optional
        The penalty parameter.  Default ``None``: the method's default (:meth:`ngdgfric.Method.default`;
        :math:`30 \mu`, Section 6), for a varying material the harmonic mean of the two neighbours' defaults on
        interior edges.
    penalty_check : str, optional
        What to do when ``eta`` is at or below the method's coercivity threshold: ``"warn"`` (default, a
        :class:`~ngdgfric.PenaltyWarning`), ``"raise"`` (ValueError) or ``"ignore"``.
    max_ndof : int or None, optional
        Refuse (ValueError, before assembly) above this many DOFs.  Default ``None``: refuse above an estimated
        ``max_bytes`` of memory.
    max_bytes : float, optional
        The memory budget in bytes when ``max_ndof`` is ``None``.  Default ``MEMORY_BUDGET`` (``8e9``, 8 GB).
    curved : bool, optional
        The mesh's elements are curved already, to the largest order (a mesh read back by
        :func:`ngdgfric.load_solution`): they are kept, not computed again (which moves them in round-off).
        Default ``False``.

    Attributes
    ----------
    problem
        The given problem with its data per region and per side made CoefficientFunctions on the mesh
        (:meth:`~ngdgfric.ContactProblem.on`).
    mesh
        The mesh.
    method
        The method's row of :data:`ngdgfric.METHODS`, a :class:`~ngdgfric.Method`.
    V
        The space :math:`V_h`: the DG space, or :math:`H^1` for the conforming baseline (``space``).
    A
        The matrix of :math:`B_h` (an NGSolve matrix).
    F
        The load vector of :math:`(f, v)` (an NGSolve vector).
    h_e
        The edge length :math:`|e|`, a CoefficientFunction.
    h_penalty
        The penalty's length (``penalty_length`` of :mod:`ngdgfric.dg.forms`).
    forms
        What the form builders of :mod:`ngdgfric.dg.forms` share (``FormsContext``).
    timings
        Seconds of ``"assemble"`` and ``"setup"``, a dict.
    orders
        :math:`p_T` per element, an integer array.
    order
        The largest :math:`p_T`, which sets the lifting space.
    degrees
        The polynomial degree of :math:`u_h` on every element, an integer array (``polynomial_degrees``):
        :math:`p_T`, for the conforming baseline the largest degree of the element and its edges.
    p
        :math:`p_T` as a number or a GridFunction, for the penalty and the estimator weights.
    material
        The Lamé parameters element by element (``Material`` of :mod:`ngdgfric.dg.material`).
    eta
        The penalty parameter: the number given or the default, an ``EdgeCoefficient`` of
        :mod:`ngdgfric.dg.material` for a varying material.
    penalty
        :math:`\eta` on every edge, an ``EdgeCoefficient``.
    V_plain
        The test space of the mixed contact forms (``V`` without the facet couplings).

    Raises
    ------
    ValueError
        If ``problem`` is not a :class:`~ngdgfric.ContactProblem`, the mesh does not fit it, ``order`` or ``eta``
        is invalid, the size limit is exceeded, or ``penalty_check="raise"`` and ``eta`` is too small.
    DataError
        If a datum is invalid at a point where the forms evaluate it (:class:`~ngdgfric.DataError`).

    Warns
    -----
    PenaltyWarning
        ``eta`` at or below the coercivity threshold (``penalty_check="warn"``).
    LockingWarning
        Where the method locks at the largest :math:`\nu` on the mesh with the lowest element degree (measured:
        the results page *Volumetric locking*; cg and SIPG at :math:`p = 1`-3 from :math:`\nu = 0.49` and
        0.497, LDG from 0.4997-0.4999 at every :math:`p`).
    MaterialWarning
        Where :math:`E` or :math:`\nu` vary inside elements more than the polynomials follow.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> disc = ndf.Discretization(problem, ndf.uniform_mesh(problem, 0.5), method="nipg", order=2)
    >>> disc.V.ndof, disc.symmetric
    (96, False)
    """

    def __init__(self, problem, mesh, method="sipg", order=1, eta=None, penalty_check="warn", max_ndof=None,
                 max_bytes=MEMORY_BUDGET, curved=False):
        if not isinstance(problem, ContactProblem):
            raise ValueError(f"problem must be a ContactProblem, got {problem!r}")
        check_mesh(problem, mesh)
        self.method = get_method(method)
        order = check_order(order, mesh)
        if not curved:
            curve(problem, mesh, int(np.max(order)))
        self.problem, self.mesh = problem.on(mesh), mesh
        problem = self.problem
        self.orders = np.full(mesh.ne, order) if np.ndim(order) == 0 else order
        check_size(self.orders, max_ndof, max_bytes=max_bytes)
        check_data(problem, mesh, int(self.orders.max()))
        self.order = int(self.orders.max())
        # p_T of the penalty and the estimator weights: the degree of the element's polynomials (for the conforming
        # baseline with the degrees of its edges, which the inverse trace inequality of Nitsche's terms must see)
        self.degrees = polynomial_degrees(self)
        self.p = self.order if np.all(self.degrees == self.order) else order_function(mesh, self.degrees)
        lowest = int(self.orders.min())  # the lowest order has the highest SIPG threshold
        self.material = Material(problem, mesh, self.order)
        eta = None if eta is None else _check_eta(eta)
        self.penalty = penalty(self.method, self.material, eta, lowest)
        varying_default = eta is None and not self.material.constant and self.method.penalty == "edge"
        self.eta = self.penalty if varying_default else self.penalty.boundary
        check_penalty(self.problem if eta is None else self._largest_law(), self.method, self.eta, lowest,
                      penalty_check)
        check_locking(largest(problem.nu, mesh), self.method, lowest)
        self.timings = {}
        start = time.perf_counter()
        self.V = space(problem, mesh, order, self.method)
        self.h_e = edge_length(mesh)
        self.h_penalty = penalty_length(mesh)
        self.forms = FormsContext(problem, mesh, self.material, self.method, self.penalty, self.p, self.h_penalty)
        self.A, self.F = self._assemble()
        self.timings["assemble"] = time.perf_counter() - start
        # the test space of the mixed contact forms (H^1 has no facet couplings to leave out)
        self.V_plain = self.V if self.method.conforming else dg_space(mesh, order, dgjumps=False)
        self.timings["setup"] = time.perf_counter() - start

    def _largest_law(self):
        """The Lame parameters a given eta is checked with: the problem's, or the largest on the mesh."""
        if self.material.constant:
            return self.problem
        return Lame(*(self.material.largest(lambda law, name=name: getattr(law, name), self.mesh)
                      for name in ("mu", "lam")))

    def _assemble(self):
        """The matrix A of B_h (with the lifting terms of Bassi, Brezzi, LDG) and the load vector F."""
        u, v = self.V.TnT()
        with threads(self.V.ndof):
            a = ngs.BilinearForm(self.V)
            for term in dg_terms(self.forms, u, v):
                a += term
            a.Assemble()
            A, lifted_load = lifting_terms(self.forms, self.V, self.orders, a.mat)
            f = ngs.LinearForm(self.V)
            for term in load_terms(self.forms, v):
                f += term
            f.Assemble()
            if lifted_load is not None:
                f.vec.FV().NumPy()[:] += lifted_load
        return A, f.vec

    @property
    def symmetric(self):
        """Whether :math:`B_h` is symmetric: for every method but NIPG."""
        return self.method.symmetry == 1
