"""Condensed contact problems (:class:`ngdgfric.solvers.reduced.ReducedContact`) for the tests of reduced,
complementary_energy and semismooth: random ones, and Example 6.1 with nu = 0.499 condensed."""

import dataclasses

import numpy as np

import ngdgfric as ndf
from ngdgfric.solvers.condensation import Condensation
from ngdgfric.solvers.reduced import ReducedContact


def random_problem(seed, M=12, symmetric=True, redundant=False, c_n=1e3, c_tau=50.0, m_n=1.0, m_t=0.0, gap=0.0):
    """A contact problem at M points with W = B A^-1 B^T from a random SPD (or nonsymmetric coercive) A."""
    rng = np.random.default_rng(seed)
    n = 4 * M
    A = rng.standard_normal((n, n))
    A = A @ A.T + n * np.eye(n)
    if not symmetric:
        skew = rng.standard_normal((n, n))
        A = A + 0.5 * (skew - skew.T) * n ** 0.5
    B = rng.standard_normal((2 * M, n))
    if redundant:
        B[M - 1] = B[M - 2]  # two points with the same normal trace: W singular
        B[2 * M - 1] = B[2 * M - 2]
    F = rng.standard_normal(n) * 10
    W = B @ np.linalg.solve(A, B.T)
    w0 = B @ np.linalg.solve(A, F)
    omega = rng.uniform(0.5, 1.5, M)
    data = dict(W=W, w0=w0, omega=omega, g_a=np.full(M, gap) + rng.uniform(-0.5, 0.5, M),
                c_n=np.full(M, c_n), c_tau=np.full(M, c_tau), m_n=m_n, m_t=m_t, symmetric=symmetric,
                redundant=redundant)
    return ReducedContact(**data), (A, B, F)


def redundant_edges_problem(seed, edges=30, q=8, k=5, c_tau=3.0, skew=1.0):
    """A NIPG-like problem with the redundancy of hp meshes: q points per edge whose traces (normal and tangential)
    are polynomials of k < q coefficients, W = B A^-1 B^T from a random coercive A with a skew part ``skew``."""
    rng = np.random.default_rng(seed)
    M = edges * q
    n = 6 * M
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    A = A @ A.T + 0.05 * np.eye(n)
    S = rng.standard_normal((n, n)) / np.sqrt(n)
    A = A + skew * 0.5 * (S - S.T)
    V = np.vander(np.linspace(-1, 1, q), k, increasing=True)
    B = np.zeros((2 * M, n))
    for e in range(edges):
        for component in range(2):
            B[component * M + e * q: component * M + (e + 1) * q] = V @ rng.standard_normal((k, n))
    F = rng.standard_normal(n) * 10
    return ReducedContact(W=B @ np.linalg.solve(A, B.T), w0=B @ np.linalg.solve(A, F), omega=np.full(M, 1 / q),
                          g_a=np.zeros(M), c_n=np.full(M, 1e3), c_tau=np.full(M, c_tau), m_n=1.0, m_t=0.0,
                          symmetric=skew == 0, redundant=True)


def law_violation(reduced, f):
    """The relative KKT residual at f, and max |lam_tau| - 1."""
    s = reduced.evaluate(f)
    multiplier = reduced.multiplier(f)
    return reduced.residual(s), float(np.max(np.abs(multiplier)) - 1)


def nearly_incompressible_data():
    """The condensed Example 6.1 with nu = 0.499, h = 1/32: the problem the old solver failed on."""
    problem = dataclasses.replace(ndf.example_6_1(), nu=0.499)
    disc = ndf.Discretization(problem, ndf.uniform_mesh(problem, 1 / 32))
    contact = ndf.Contact(disc)
    traces = contact.traces
    condensation = Condensation(disc.A, disc.F, traces, True)
    return dict(W=condensation.W, w0=condensation.w0, omega=traces.omega, g_a=traces.g_a, c_n=traces.c_n,
                c_tau=traces.c_tau, m_n=traces.m_n, m_t=traces.m_t, symmetric=True, redundant=False)
