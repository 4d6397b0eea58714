"""The forces at redundant contact points (ngdgfric.solvers.selection): one multiplier whatever the solver's path."""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.solvers import pardiso
from ngdgfric.solvers.selection import select


@pytest.fixture(scope="module")
def redundant():
    """Example 6.1, SIPG on h = 1/4 with p_T = 2 or 3 at random: q = 4 Gauss points on every contact edge, so an edge
    of degree 2 has more points than trace values and the forces there are not unique."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 0.25)
    orders = np.where(np.random.default_rng(0).random(mesh.ne) < 0.5, 2, 3)
    cold = ndf.solve(problem, mesh, method="sipg", order=orders)
    assert cold.contact.traces.redundant
    return problem, mesh, orders, cold


def _others(problem, mesh, orders):
    """The same problem solved along other paths: from the solution of another friction bound, and (with PARDISO)
    by the full-space iteration."""
    start = ndf.solve(dataclasses.replace(problem, c_tau=0.3 * problem.c_tau), mesh, method="sipg", order=orders)
    yield ndf.solve(problem, mesh, method="sipg", order=orders, initial=start)
    if pardiso.available():
        yield ndf.solve(problem, mesh, method="sipg", order=orders, formulation="full-space")


def test_every_path_gives_one_multiplier_and_one_estimate(redundant):
    """Before the selection the three paths gave multipliers 0.07 apart and eta_h differing from the fifth digit;
    now they agree to round-off (measured 5e-13 in lam_tau, eta_h to 1e-15 relative; tested at 1e-9 and 1e-12)."""
    problem, mesh, orders, cold = redundant
    eta = ndf.estimate(cold).eta_h
    for other in _others(problem, mesh, orders):
        assert np.max(np.abs(other.lam_tau.vec.FV().NumPy() - cold.lam_tau.vec.FV().NumPy())) < 1e-9
        assert ndf.estimate(other).eta_h == pytest.approx(eta, rel=1e-12)


def test_the_selected_forces_solve_the_laws(redundant):
    """The least-norm forces leave u and the KKT conditions of Lemma 3.1 as they were: |lam_tau| <= 1,
    complementarity and equilibrium at round-off."""
    kkt = ndf.kkt_residuals(redundant[3])
    assert kkt["lam_excess"] == 0.0
    assert kkt["complementarity"] < 1e-10
    assert kkt["equilibrium"] < 1e-10


def test_a_sticking_edge_carries_a_polynomial_of_its_degree(redundant):
    """On an edge whose points all stick, the selected multiplier is a polynomial of the element's degree p_T along
    the edge (the traction of least norm lies in the trace space): through the q = 4 values a polynomial of degree
    p_T fits to round-off, also where p_T = 2 < q - 1 (the solver alone left a degree-3 part there)."""
    problem, mesh, orders, cold = redundant
    state = ndf.contact_state(cold)
    q = cold.contact.gauss.q
    edges = ndf.contact.boundary.boundary_edges(problem, cold.mesh)
    checked = 0
    for k, (_, element) in enumerate(edges):
        lam = state["lam_tau"][k * q:(k + 1) * q]
        if np.max(np.abs(lam)) >= 1 - 1e-6:
            continue  # a slipping point: the multiplier is +-1 there, no freedom
        s = state["x"][k * q:(k + 1) * q]
        degree = orders[element.nr]
        fit = np.polynomial.polynomial.Polynomial.fit(s, lam, degree)
        assert np.max(np.abs(fit(s) - lam)) < 1e-10
        checked += degree < q - 1
    assert checked >= 1


def _edge(lam, c_tau=1.0):
    """One edge of a degree-1 element with q = 3 Gauss points on [0, 1] (three tangential rows u_t = a + b s, rank
    2): a stand-in for ``ContactTraces`` and the laws' state at the forces f_t = omega c_tau lam, u_t = 0."""
    s = 0.5 + np.array([-1.0, 0.0, 1.0]) * np.sqrt(0.6) / 2
    omega = np.array([5.0, 8.0, 5.0]) / 18
    traces = SimpleNamespace(M=3, foundation=3, redundant=True, omega=omega, rows=np.repeat(np.arange(3, 6), 2),
                             cols=np.tile([0, 1], 3), values=np.column_stack([np.ones(3), s]).ravel())
    beta = omega * c_tau
    f = np.concatenate([np.zeros(3), beta * np.asarray(lam)])
    state = SimpleNamespace(stick=np.abs(lam) < 1, beta=beta, w=np.zeros(6))
    return traces, f, state, np.column_stack([np.ones(3), s]), omega


def test_least_norm_forces_by_their_normal_equations():
    """The selection against the least-norm problem solved another way: minimise sum f^2 / omega subject to
    B^T f = B^T f0 by its Lagrange conditions f = Omega B c, B^T Omega B c = B^T f0.  A point at the bound that does
    not slip (lam = 1, u_t = 0) takes part (else the two other points are independent and nothing would change)."""
    traces, f, state, B, omega = _edge([1.0, 0.2, 0.9])
    c = np.linalg.solve(B.T @ (omega[:, None] * B), B.T @ f[3:])
    expected = omega * (B @ c)
    assert np.all(np.abs(expected) <= state.beta)  # the least-norm forces keep the bound here
    assert np.allclose(select(traces, f, state)[3:], expected, rtol=0, atol=1e-15)


def test_forces_whose_least_norm_passes_the_bound_are_kept():
    """lam = (-1, 1, 1) at non-slipping points: the least-norm traction, the linear one with the same mean and first
    moment, reaches 1.44 at the last point, past the bound, so the group keeps the forces it has."""
    traces, f, state, B, omega = _edge([-1.0, 1.0, 1.0])
    c = np.linalg.solve(B.T @ (omega[:, None] * B), B.T @ f[3:])
    assert np.any(np.abs(omega * (B @ c)) > state.beta)
    assert np.array_equal(select(traces, f, state), f)


def test_each_group_keeps_or_takes_its_own_forces():
    """Two edges of two elements (no shared unknowns): the first one's least-norm forces keep the bound and are
    taken, the second one's pass it and that edge keeps its forces; the bound is checked group by group."""
    first, second = _edge([1.0, 0.2, 0.9]), _edge([-1.0, 1.0, 1.0])
    t1, t2 = first[0], second[0]
    traces = SimpleNamespace(M=6, foundation=6, redundant=True, omega=np.concatenate([t1.omega, t2.omega]),
                             rows=np.concatenate([t1.rows + 3, t2.rows + 6]),
                             cols=np.concatenate([t1.cols, t2.cols + 2]), values=np.concatenate([t1.values, t2.values]))
    f = np.concatenate([np.zeros(6), first[1][3:], second[1][3:]])
    state = SimpleNamespace(stick=np.concatenate([first[2].stick, second[2].stick]),
                            beta=np.concatenate([first[2].beta, second[2].beta]), w=np.zeros(12))
    alone = select(first[0], first[1], first[2])[3:]
    assert not np.allclose(alone, f[6:9])  # the first edge's forces change
    assert np.allclose(select(traces, f, state)[6:], np.concatenate([alone, f[9:]]), rtol=0, atol=1e-15)
