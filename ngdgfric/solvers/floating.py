r"""Bodies held by contact only (load control): the rigid motions that :math:`B_h` does not hold, and the proximal
iteration that solves the contact problem with them.

A body without a Dirichlet side (:class:`~ngdgfric.ContactPair`: a punch pressed by a force, the upper cylinder of
a Hertz test) has rigid motions :math:`r` with :math:`B_h(r, r) = 0` unless its symmetry sides hold them:
:math:`A` is singular and cannot be factorised, though the contact problem has a solution wherever the contact
forces hold the body.  ``free_motions`` finds those motions: the generalised eigenvectors of
:math:`(R^T A R, R^T M R)` (:math:`R`: the translations and the rotation of each body, :math:`M` the mass matrix)
with eigenvalues below ``FREE`` times the typical :math:`A_{ii} / M_{ii}`.

The contact problem is then solved by the proximal point iteration

.. math::

    A u_{k+1} + \varepsilon M_f (u_{k+1} - u_k) + B^T f(B u_{k+1}) = F,

:math:`M_f` the mass matrix of the bodies with free motions, :math:`\varepsilon = ` ``EPSILON`` times the typical
:math:`A_{ii} / M_{ii}`: each step is the contact solve of :mod:`ngdgfric.solvers.newton`, condensed or in the full
space (:mod:`ngdgfric.solvers.fullspace`), with :math:`A + \varepsilon M_f` (factorised once, or one PARDISO
pattern) and the load :math:`F + \varepsilon M_f u_k`.  Its fixed point solves
the problem itself (the regularisation leaves no trace in the answer); a motion the contact holds with stiffness
:math:`k` contracts by :math:`\varepsilon / (\varepsilon + k)` per step, so a few steps reach round-off.  A motion
that nothing holds (the load pulls the body off, or it slides without friction) drifts by
:math:`F / \varepsilon` per step: after ``MAX_STEPS`` steps, or as soon as no pair point of the body is in contact,
a :class:`~ngdgfric.SolverError` names the body and the motion.
"""

import ngsolve as ngs
import numpy as np

from ..errors import SolverError
from ..sparse import BlockSum, diagonal
from ..threads import threads

__all__ = ["free_motions", "anderson", "FloatingSolve", "EPSILON", "FREE", "MAX_STEPS"]

EPSILON = 1e-6
"""The proximal weight relative to the typical diagonal ratio A_ii / M_ii."""
FREE = 1e-9
"""A rigid motion is free when its energy ratio r^T A r / r^T M r is below FREE times the typical A_ii / M_ii."""
MAX_STEPS = 20
"""The most proximal steps before a motion that keeps drifting is reported free."""
CONVERGED = 1e-13
"""The proximal iteration stops when the proximal force eps M_f (u_k+1 - u_k) of a step, the residual of the
equilibrium its u leaves, is at most CONVERGED times the forces (``FloatingSolve._force_scale``): measured against
u itself, dominated by the free body's rigid motion, it left equilibrium residuals of 1e-9 to 1e-7."""
STILL = 1e-13
"""... or when a step changes u by at most STILL relative to u (round-off: the proximal force cannot fall
further)."""
_NAMES = ("translation in x", "translation in y", "rotation")


def _mass(disc, indicator):
    """The mass matrix of V_h weighted by ``indicator`` (a CoefficientFunction)."""
    u, v = disc.V.TnT()
    form = ngs.BilinearForm(disc.V)
    form += indicator * u * v * ngs.dx
    with threads(disc.V.ndof):
        form.Assemble()
    return form.mat


def _apply(mat, vector):
    x = mat.CreateColVector()
    y = mat.CreateColVector()
    x.FV().NumPy()[:] = vector
    y.data = mat * x
    return y.FV().NumPy().copy()


def _body_indicator(mesh, regions):
    return mesh.MaterialCF({name: 1.0 for name in regions}, default=0.0)


def free_motions(disc, mass, ratio):
    """The rigid motions of the bodies of ``disc.problem`` that B_h does not hold (``mass``: the mass matrix of V_h,
    ``ratio``: the typical A_ii / M_ii): a list of (body number, region names, name of the motion (its largest
    part: a translation or the rotation), coefficient vector on V_h)."""
    mesh, geometry = disc.mesh, disc.problem.geometry
    size = max(geometry.diameter(), 1e-300)
    found = []
    for number in range(len(geometry.bodies)):
        regions = geometry.body_regions(number)
        indicator = _body_indicator(mesh, regions)
        area = ngs.Integrate(indicator, mesh)
        cx, cy = (ngs.Integrate(indicator * c, mesh) / area for c in (ngs.x, ngs.y))
        modes = (ngs.CF((1.0, 0.0)), ngs.CF((0.0, 1.0)), ngs.CF((-(ngs.y - cy) / size, (ngs.x - cx) / size)))
        vectors = []
        for mode in modes:
            r = ngs.GridFunction(disc.V)
            r.Set(indicator * mode)
            vectors.append(r.vec.FV().NumPy().copy())
        R = np.column_stack(vectors)
        energy = R.T @ np.column_stack([_apply(disc.A, r) for r in vectors])
        gram = R.T @ np.column_stack([_apply(mass, r) for r in vectors])
        values, coefficients = np.linalg.eig(np.linalg.solve(gram, 0.5 * (energy + energy.T)))
        for value, mode in zip(values.real, coefficients.real.T, strict=True):
            if value < FREE * ratio:
                weights = np.abs(mode) * np.sqrt(np.diag(gram))
                found.append((number, regions, _NAMES[int(np.argmax(weights))], R @ mode))
    return found


def anderson(steps):
    """The next iterate of the proximal iteration from its last steps ``steps`` [(u_k, G(u_k)), ...] (G: one
    proximal step): Anderson's extrapolation sum_i alpha_i G(u_i) with sum_i alpha_i = 1 and the combination of
    the changes G(u_i) - u_i smallest.  Near the solution G is affine with its error in the span of the free motions
    (it contracts each by eps / (eps + k), close to 1 on fine meshes, where eps grows with A_ii / M_ii), so one more
    step than there are free motions makes that error vanish; a single step is the plain proximal step."""
    if len(steps) == 1:
        return steps[0][1]
    changes = [image - u for u, image in steps]
    D = np.column_stack([change - changes[-1] for change in changes[:-1]])
    gamma = np.linalg.lstsq(D, -changes[-1], rcond=None)[0]
    alpha = np.append(gamma, 1.0 - gamma.sum())
    return sum(a * image for a, (_, image) in zip(alpha, steps, strict=True))


class FloatingSolve:
    """The proximal iteration of the module docstring around a ``NewtonState`` (:mod:`ngdgfric.solvers.newton`) or
    a ``FullSpaceState`` (:mod:`ngdgfric.solvers.fullspace`) made with ``A`` = A + eps M_f (``BlockSum`` of
    :mod:`ngdgfric.sparse`: the mass matrix lives in the element blocks); ``motions``: the free motions
    (``free_motions``), ``mass``: eps M_f.  ``of`` makes one where a body has free motions."""

    def __init__(self, disc, motions, epsilon):
        self.disc, self.motions = disc, motions
        regions = {name for _, names, _, _ in motions for name in names}
        self.mass = _mass(disc, epsilon * _body_indicator(disc.mesh, regions))
        self.A = BlockSum(disc.A, pattern=self.mass).update(self.mass)

    @classmethod
    def of(cls, disc):
        """The ``FloatingSolve`` of ``disc``, or None where B_h holds every rigid motion."""
        mass = _mass(disc, ngs.CF(1.0))
        ratio = float(np.median(np.abs(diagonal(disc.A)) / np.maximum(diagonal(mass), 1e-300)))
        motions = free_motions(disc, mass, ratio)
        return cls(disc, motions, EPSILON * ratio) if motions else None

    def _force_scale(self, state):
        """The size of the forces the equilibrium balances: the load F and the contact forces B^T f (whichever is
        larger)."""
        forces = state.traces.apply_transpose(np.asarray(state.f)) if state.f is not None else 0.0
        return max(float(np.linalg.norm(self.disc.F.FV().NumPy())), float(np.linalg.norm(forces)), 1e-300)

    def load(self, u_vec):
        """F + eps M_f u_k as a numpy array."""
        return self.disc.F.FV().NumPy() + _apply(self.mass, u_vec)

    def drift(self, change):
        """The motion that moved most in ``change`` (a step of u): (its description, its amplitude)."""
        amplitudes = [abs(float(r @ _apply(self.mass, change)) / float(r @ _apply(self.mass, r)))
                      for _, _, _, r in self.motions]
        k = int(np.argmax(amplitudes))
        number, regions, name, _ = self.motions[k]
        return f"the {name} of body {number} (regions {', '.join(map(repr, regions))})", amplitudes[k]

    def run(self, state, options, u_start):
        """Proximal steps with ``state`` (a NewtonState or FullSpaceState of ``self.A``) from u_start (array); returns
        (u, lam_tau, info) of the last step, ``info["proximal_steps"]`` its number of steps."""
        u_k, total_iterations, history, steps = u_start, 0, [], []
        for step in range(1, MAX_STEPS + 1):
            state.reload(self.load(u_k))
            u, lam_tau, info = state.run(options)
            total_iterations += info["iterations"]
            history += info["history"]
            u_new = u.vec.FV().NumPy().copy()
            change = u_new - u_k
            if np.linalg.norm(_apply(self.mass, change)) <= CONVERGED * self._force_scale(state) \
                    or np.linalg.norm(change) <= STILL * np.linalg.norm(u_new):  # or u no longer moves
                info.update(proximal_steps=step, iterations=total_iterations, history=history)
                return u, lam_tau, info
            gap = state.traces.apply(u_new)[:state.traces.M] - state.traces.g_a
            if step > 1 and not np.any(gap > 0):
                break  # no point pushes: nothing holds the body
            steps = (steps + [(u_k, u_new)])[-(len(self.motions) + 1):]
            u_k = anderson(steps)
        what, amplitude = self.drift(change)
        raise SolverError(f"nothing holds {what}: it moved by {amplitude:.3g} in the last of {step} proximal steps "
                          f"(the load pulls the body off or along its contact); hold it by a Dirichlet or symmetry "
                          f"side, or press it onto the other body", history=history, solver="newton")
