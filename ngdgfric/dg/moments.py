r"""The lifting operators of :mod:`ngdgfric.dg.liftings` in moment form, from a few small NGSolve forms.

The matrix of the jumps' moments on the edges and the kernels :math:`S_T` of every element (a ``Liftings``):
:math:`m_e[u] = (\int_e [\![u]\!]_c \psi_a \, ds)` for the tensor components :math:`c = xx, yy, xy` and a basis
:math:`\psi_a` of the polynomials of degree :math:`p` on :math:`e` (an NGSolve facet space: Legendre on straight
edges, so that :math:`N_e` is diagonal there), assembled from element-boundary integrals of
:math:`\operatorname{sym}(u \otimes n)` (both sides of an interior edge adding up to the jump);
:math:`S_T = (E_T N^{-1})^T M_T^{-1} M_T^C M_T^{-1} (E_T N^{-1})` from :math:`E_T = (\int_e w_T \phi_k \psi_a)`,
the Gram matrices :math:`N_e` of the facet basis and the mass matrices of :math:`\Sigma_h(T)`, unweighted and
weighted by :math:`2 \mu` and :math:`\lambda` (by the element's value when the material is constant on it).
"""


from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..meshes import facet_indicator
from ..problem import coefficient
from ..threads import threads
from .blocks import ElementBlocks
from .forms import has_dirichlet_data, normal_part

__all__ = ["Liftings", "liftings", "csr"]


@dataclass
class Liftings:
    """The lifting operators of one discretisation in moment form (module docstring).

    ``moments``: the NGSolve matrix B of u -> m[u] (rows: component c, facet, a; a facet space of degree ``q - 1``,
    components xx, yy, xy one after the other); ``facets``: the facet-space index of every element's three edges
    (ne, 3); ``mu_kernel``, ``lam_kernel``: S_T of 2 mu and of lam, (ne, 3 q, 3 q) over (local edge, a), zero on
    the edges of Gamma_F and Gamma_C (not in E_h^o); ``data``: m[u_D] on the Dirichlet edges, (3, facets, q), None
    if u_D = 0; ``blocks``: the element blocks of V_h (:class:`~ngdgfric.dg.blocks.ElementBlocks`)."""

    moments: object
    facets: np.ndarray
    mu_kernel: np.ndarray
    lam_kernel: np.ndarray
    data: object
    blocks: ElementBlocks
    q: int

    def kernel(self, local=0.0, total=1.0):
        """The tensor kernels, (ne, 9 q, 9 q) with rows and columns (component, local edge, a): ``total`` times the
        kernel of r_0 plus ``local`` times its diagonal edge blocks (those of the r_e); from the scalar kernels by
        (C r, r) = 2 mu r : r + lam tr(r)^2, r : r = r_xx^2 + r_yy^2 + 2 r_xy^2, tr r = r_xx + r_yy."""
        ne, q = len(self.facets), self.q
        mu, lam = (total * k + local * (k.reshape(ne, 3, q, 3, q) * np.eye(3)[None, :, None, :, None]).reshape(k.shape)
                   for k in (self.mu_kernel, self.lam_kernel))
        tensor = np.zeros((ne, 3, 3 * q, 3, 3 * q))
        tensor[:, 0, :, 0], tensor[:, 1, :, 1], tensor[:, 2, :, 2] = mu + lam, mu + lam, 2 * mu
        tensor[:, 0, :, 1] = tensor[:, 1, :, 0] = lam
        return tensor.reshape(ne, 9 * q, 9 * q)

    def moments_of(self, vector):
        """m[u] of a coefficient vector of V_h (numpy), as (3, facets, q)."""
        x = self.moments.CreateRowVector()
        x.FV().NumPy()[:] = vector
        y = self.moments.CreateColVector()
        y.data = self.moments * x
        return y.FV().NumPy().reshape(3, -1, self.q).copy()

    def per_element(self, moments):
        """Moments (3, facets, q) gathered on every element's three edges: (ne, 9 q), rows (component, local edge,
        a) as those of :meth:`kernel`."""
        ne = len(self.facets)
        return moments[:, self.facets].transpose(1, 0, 2, 3).reshape(ne, 9 * self.q)

    @property
    def edge_rows(self):
        """(3, 3 q): the rows (component, a) of :meth:`kernel` that belong to each local edge."""
        return _edge_rows(self.q)


def liftings(problem, material, mesh, V, orders):
    """The ``Liftings`` of V_h (``V``: its space, element degrees ``orders``; Sigma_h of the largest) on
    ``mesh``."""
    order = int(np.max(orders))
    q = order + 1
    facet_space = ngs.FacetFESpace(mesh, order=order)
    cells = ngs.L2(mesh, order=order)  # the scalar space of Sigma_h (one component)
    parts = {part: facet_indicator(mesh, problem.where(part)) for part in ("dirichlet", "symmetry", "traction",
                                                                          "contact", "pair")}
    boundary = sum(parts.values())
    with threads(V.ndof):
        moments = _moment_matrix(mesh, V, facet_space, parts["symmetry"] if problem.sides("symmetry") else None)
        weighted, facets = _element_facets(material, cells, facet_space, boundary, q)
        gram = _facet_blocks(facet_space, boundary, q)
        unused = sum(parts[part].vec.FV().NumPy() for part in ("traction", "contact", "pair")) > 0.5
        mu_kernel, lam_kernel = _kernels(material, cells, weighted, gram, facets, unused, q)
        data = _dirichlet_moments(problem, mesh, facet_space, parts["dirichlet"], q)
    return Liftings(moments, facets, mu_kernel, lam_kernel, data, ElementBlocks.of(orders, V.ndof), q)


def _tensor(w, n):
    """The components (xx, yy, xy) of sym(w (x) n)."""
    return w[0] * n[0], w[1] * n[1], 0.5 * (w[0] * n[1] + w[1] * n[0])


def _moment_matrix(mesh, V, facet_space, symmetry):
    """B: u -> m[u] (module docstring) as an NGSolve matrix from V_h to the facet space, components xx, yy, xy: the
    moments of sym(u (x) n) from every element's side of every edge (both sides of an interior edge add up to
    sym([u] (x) n); the rows of Gamma_F and Gamma_C are left out by the kernels, :func:`_kernels`), on the symmetry
    sides (``symmetry``: their facet indicator, None if there are none) those of sym((u . n) n (x) n).  An
    indicator in the integrand doubles the assembly's cost, so the symmetry sides get a form of their own."""
    u, n = V.TrialFunction(), ngs.specialcf.normal(2)
    space = facet_space**3
    jumps = [_tensor(u, n)] if symmetry is None else [_tensor(u, n), _tensor(symmetry * (normal_part(u, n) - u), n)]
    forms = []
    for jump in jumps:
        form = ngs.BilinearForm(trialspace=V, testspace=space)
        form += sum(j * psi for j, psi in zip(jump, space.TestFunction(), strict=True)) * ngs.dx(element_boundary=True)
        form.Assemble()
        forms.append(form)
    if len(forms) > 1:
        forms[0].mat.AsVector().data += forms[1].mat.AsVector()  # the same pattern
    return forms[0].mat


def _element_facets(material, cells, facet_space, boundary, q):
    """(E_T as (ne, n_S, 3 q), the facet-space index of each element's three edges (ne, 3)): E_T = (int_e w_T
    phi_k psi_a) with w_T the weight of T's side in {tau} (1 on boundary edges)."""
    psi, phi = facet_space.TrialFunction(), cells.TestFunction()
    form = ngs.BilinearForm(trialspace=facet_space, testspace=cells)
    weight = _side_weight(material, facet_space, boundary)
    form += weight * psi * phi * ngs.dx(element_boundary=True)
    form.Assemble()
    ne, size = cells.mesh.ne, cells.ndof // cells.mesh.ne
    values, cols, _ = csr(form.mat, ne * size * 3 * q, "E")
    return values.reshape(ne, size, 3 * q), cols.reshape(ne, size, 3 * q)[:, 0, ::q] // q


def _side_weight(material, facet_space, boundary):
    """w_T = k_other / (k_T + k_other) on interior edges (k = 2 mu + lam; 1/2 for a constant material), 1 on boundary
    edges, for element-boundary integrals: k_T + k_other is the facet function whose moments are those of both
    sides' traces (exact: the traces of k are polynomials of the facet space's degree), so that no neighbour's
    value is needed (NGSolve cannot evaluate ``Other()`` in a mixed element-boundary form)."""
    if material.constant:
        return 0.5 * (1 - boundary) + boundary
    k = material.own.stiffness
    total = ngs.GridFunction(facet_space)
    traces = ngs.LinearForm(facet_space)
    traces += k * facet_space.TestFunction() * ngs.dx(element_boundary=True)
    traces.Assemble()
    psi, chi = facet_space.TnT()
    gram = ngs.BilinearForm(facet_space)
    gram += (0.5 * (1 - boundary) + boundary) * psi * chi * ngs.dx(element_boundary=True)  # each edge once
    gram.Assemble()
    total.vec.data = gram.mat.Inverse(inverse="sparsecholesky") * traces.vec
    return (1 - boundary) * (total - k) / total + boundary


def _facet_blocks(facet_space, boundary, q):
    """N_e^-1 of every facet, (facets, q, q): the inverse Gram matrices of the facet basis (diagonal on straight
    edges)."""
    psi, chi = facet_space.TnT()
    form = ngs.BilinearForm(facet_space)
    form += (0.5 * (1 - boundary) + boundary) * psi * chi * ngs.dx(element_boundary=True)  # each edge once
    form.Assemble()
    values, cols, rowptr = csr(form.mat, None, "N")
    rows = np.repeat(np.arange(form.mat.height), np.diff(rowptr))
    own = cols // q == rows // q
    if np.count_nonzero(own) != facet_space.ndof * q:
        raise RuntimeError("the facet space's Gram matrix has no full block per facet")
    return np.linalg.inv(values[own].reshape(-1, q, q))


def _kernels(material, cells, weighted, gram, facets, unused, q):
    """S_T of 2 mu and of lam (module docstring), (ne, 3 q, 3 q) each, without the edges ``unused`` (Gamma_F,
    Gamma_C: bool per facet; their rows and columns are zero)."""
    ne = len(facets)
    inverse_gram = gram[facets] * ~unused[facets][:, :, None, None]  # (ne, 3, q, q)
    lifted = (weighted.reshape(ne, -1, 3, q).transpose(0, 2, 1, 3) @ inverse_gram).transpose(0, 2, 1, 3)
    lifted = lifted.reshape(ne, -1, 3 * q)
    mass = _element_mass(cells, 1.0)
    projected = np.linalg.solve(mass, lifted)  # M_T^-1 E_T N^-1
    kernel = np.swapaxes(lifted, 1, 2) @ projected  # the kernel of a unit factor
    return tuple(kernel * _element_values(factor)[:, None, None] if _element_values(factor) is not None
                 else np.swapaxes(projected, 1, 2) @ (_element_mass(cells, factor) @ projected)
                 for factor in (2 * material.mu, material.lam))


def _element_values(factor):
    """A factor constant on every element as one value per element (a number, or an order-0 L2 GridFunction of the
    material), None if it varies inside elements (its weighted mass matrix is then assembled)."""
    if isinstance(factor, ngs.GridFunction) and factor.space.globalorder == 0:
        return factor.vec.FV().NumPy()
    if isinstance(factor, ngs.CoefficientFunction):
        return None
    return np.full(1, float(factor))


def _element_mass(cells, factor):
    """The element blocks of the mass matrix of ``cells`` weighted by ``factor``, (ne, n_S, n_S)."""
    phi, chi = cells.TnT()
    form = ngs.BilinearForm(cells)
    form += factor * phi * chi * ngs.dx
    form.Assemble()
    ne = cells.mesh.ne
    size = cells.ndof // ne
    values, _, _ = csr(form.mat, ne * size * size, "M")
    return values.reshape(ne, size, size)


def _dirichlet_moments(problem, mesh, facet_space, dirichlet, q):
    """m[u_D]: the moments of sym(u_D (x) n) on the Dirichlet edges, (3, facets, q); None if u_D = 0."""
    if not has_dirichlet_data(problem):
        return None
    n, u_D = ngs.specialcf.normal(2), coefficient(problem.u_D)
    space = facet_space**3
    form = ngs.LinearForm(space)
    jump = (u_D[0] * n[0], u_D[1] * n[1], 0.5 * (u_D[0] * n[1] + u_D[1] * n[0]))
    form += dirichlet * sum(j * psi for j, psi in zip(jump, space.TestFunction(), strict=True)) * \
        ngs.dx(element_boundary=True, bonus_intorder=2)
    form.Assemble()
    return form.vec.FV().NumPy().reshape(3, -1, q).copy()


def csr(mat, expected=None, name=""):
    """(values, cols, rowptr) of an NGSolve sparse matrix as numpy arrays; RuntimeError if it does not have the
    ``expected`` number of entries (the full element or facet blocks the reshapes take)."""
    values, cols, rowptr = mat.CSR()  # views of the matrix's memory: copied, the matrix may go
    values, cols = np.array(values), np.array(cols, dtype=np.int64)
    if expected is not None and len(values) != expected:
        raise RuntimeError(f"the matrix {name} has {len(values)} entries, not the {expected} of full blocks")
    return values, cols, np.asarray(rowptr, dtype=np.int64)




def _edge_rows(q):
    """(3, 3 q): the kernel rows (component, local edge, a) of each local edge, in the order (component, a)."""
    c, a = np.meshgrid(np.arange(3), np.arange(q), indexing="ij")
    return np.array([(c * 3 * q + j * q + a).ravel() for j in range(3)])
