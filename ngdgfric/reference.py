"""Reference solutions: a very accurate u_h stored in a small file, and true errors against it.

A reference is one ``.npz`` file: the mesh (vertices, triangles, labelled boundary segments),
the order of every element, the coefficient vector of u_h, and its estimator eta_h.  The error
of another solution u_h (on any mesh of the same domain) is

    |||u_ref - u_h|||_h^2 = sum_T int_T C eps(u_ref - u_h) : eps(u_ref - u_h) dx
                            + sum_{e in E_h^o} h_e^-1 ||[u_h]||_e^2,

the volume part by a Gauss rule of degree 2 p + 4 on u_h's elements, with u_ref evaluated at
those points by point search in its mesh; the jump part is exact for the exact solution u (it
is continuous and zero on Gamma_D, so [u - u_h] = -[u_h]) and so uses u_h alone.
"""

from dataclasses import dataclass
from pathlib import Path

import ngsolve as ngs
import numpy as np

from .discretization import dg_space
from .forms import strain
from .meshes import mesh_arrays, mesh_from_arrays
from .norms import energy_norm_squared_parts

__all__ = ["Reference", "save_reference", "load_reference", "energy_error", "reference_errors"]


@dataclass
class Reference:
    """A stored reference solution: ``u`` (GridFunction on ``mesh``), ``eta`` (its eta_h)."""

    problem: object
    mesh: object
    u: object
    orders: np.ndarray
    eta: float
    description: str


def save_reference(sol, path, eta, description=""):
    """Write Solution ``sol`` with its estimator value ``eta`` to ``path`` (.npz)."""
    points, triangles, segments, labels = mesh_arrays(sol.mesh)
    np.savez_compressed(Path(path), points=points, triangles=triangles, segments=segments, labels=labels,
                        orders=sol.discretization.orders, u=sol.u.vec.FV().NumPy(), eta=eta,
                        method=sol.method, description=description)


def load_reference(path, problem):
    """The :class:`Reference` stored at ``path`` for ``problem`` (the same problem it was made for)."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no reference solution at {path}: run scripts/reference.py to make it")
    data = np.load(path)
    mesh = mesh_from_arrays(problem, data["points"], data["triangles"], data["segments"], data["labels"])
    u = ngs.GridFunction(dg_space(mesh, data["orders"]))
    if u.space.ndof != data["u"].size:
        raise ValueError(f"{path}: {data['u'].size} coefficients for a space of dimension {u.space.ndof}")
    u.vec.FV().NumPy()[:] = data["u"]
    return Reference(problem, mesh, u, data["orders"], float(data["eta"]), str(data["description"]))


def energy_error(sol, reference):
    """|||u_ref - u_h|||_h of a Solution (or a :class:`Reference`: anything with ``problem``,
    ``mesh`` and ``u``) against a :class:`Reference` (module docstring)."""
    return reference_errors(sol, reference)["energy"]


def reference_errors(sol, reference):
    """Norms of u_ref - u_h for a Solution against a :class:`Reference` (module docstring).

    Returns a dict: ``energy`` = |||u_ref - u_h|||_h with its parts ``energy_volume`` and
    ``energy_jumps``, ``relative`` = energy / (int C eps(u_ref) : eps(u_ref))^(1/2), ``h1`` (broken
    H1 seminorm), ``l2``; all volume integrals by the same Gauss rule on u_h's elements (degree
    2 p + 4; exact when u_ref is a polynomial of degree <= p + 3 there, else a quadrature of a
    function as smooth as u_ref is on u_h's elements).
    """
    mesh, problem = sol.mesh, sol.problem
    rule = ngs.IntegrationRule(ngs.TRIG, 2 * sol.u.space.globalorder + 4)
    points = mesh.MapToAllElements({ngs.TRIG: rule}, ngs.VOL)
    xy = np.asarray(ngs.CF((ngs.x, ngs.y))(points)).reshape(-1, 2)
    foreign = reference.mesh(xy[:, 0], xy[:, 1])
    area = ngs.Integrate(ngs.CF(1) * ngs.dx, mesh, element_wise=True).NumPy()
    weights = 2 * np.outer(area, np.asarray(rule.weights)).ravel()

    def values(cf, at, size):
        return np.asarray(cf(at)).reshape(len(xy), size)

    def energy_density(e):  # C e : e for a symmetric e (rows of 4), written out: lam tr(e)^2 + 2 mu e : e
        return problem.lam * (e[:, 0] + e[:, 3]) ** 2 + 2 * problem.mu * np.sum(e**2, axis=1)

    strain_ref = values(strain(reference.u), foreign, 4)
    difference = strain_ref - values(strain(sol.u), points, 4)
    gradient = values(ngs.Grad(reference.u), foreign, 4) - values(ngs.Grad(sol.u), points, 4)
    displacement = values(reference.u, foreign, 2) - values(sol.u, points, 2)
    volume = float(np.sum(weights * energy_density(difference)))
    _, jumps = energy_norm_squared_parts(problem, mesh, sol.u)
    energy = float(np.sqrt(volume + jumps))
    return dict(energy=energy, energy_volume=float(np.sqrt(volume)), energy_jumps=float(np.sqrt(jumps)),
                relative=energy / float(np.sqrt(np.sum(weights * energy_density(strain_ref)))),
                h1=float(np.sqrt(np.sum(weights * np.sum(gradient**2, axis=1)))),
                l2=float(np.sqrt(np.sum(weights * np.sum(displacement**2, axis=1)))))
