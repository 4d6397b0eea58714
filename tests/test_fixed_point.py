"""The fixed point on the friction bound (m_t > 0): each step solves the frozen-bound problem on the same
discretisation, and the outer map contracts at the rate the module docstring states."""

import dataclasses

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact import Contact
from ngdgfric.contact.forms import frozen_bound
from ngdgfric.solvers.fixed_point import FixedPointOptions, fixed_point
from ngdgfric.solvers.newton import NewtonOptions, newton
from ngdgfric.solvers.uzawa import UzawaOptions, uzawa


@pytest.fixture(scope="module")
def m_t_1():
    p = dataclasses.replace(ndf.example_6_1(), m_t=1.0)
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 8))
    return disc, Contact(disc)


@pytest.mark.parametrize("solver, options", [(newton, NewtonOptions()), (uzawa, UzawaOptions(solver_tol=1e-10))])
def test_an_inner_solve_is_the_solve_of_the_frozen_problem(m_t_1, solver, options):
    """The solver on disc with problem=frozen gives what it gives on a discretisation of the frozen problem."""
    disc, contact = m_t_1
    u = newton(disc, contact, NewtonOptions(solver_tol=1e-6))[0]
    frozen = frozen_bound(disc.problem, u)
    inside = solver(disc, contact, options, problem=frozen)[0].vec.FV().NumPy()
    alone_disc = ndf.Discretization(frozen, disc.mesh)
    alone = solver(alone_disc, Contact(alone_disc), options)[0].vec.FV().NumPy()
    assert np.max(np.abs(inside - alone)) <= 1e-12 * np.max(np.abs(alone))


def test_outer_iteration_contracts_by_about_a_quarter(m_t_1):
    """Example 6.1, m_t = 1, c_tau = 450: contraction factor about 0.25 c_tau / 450 (module docstring)."""
    messages = []
    _, _, info = fixed_point(*m_t_1, FixedPointOptions(solver_tol=1e-10, progress=messages.append))
    ratios = np.array(info["history"][3:]) / np.array(info["history"][2:-1])
    assert np.all((0.15 <= ratios) & (ratios <= 0.35))
    assert messages == [f"fixed point {k + 1}: relative change {c:.2e}" for k, c in enumerate(info["history"])]
    assert info["history"][-1] <= 1e-10 and info["iterations"] == len(info["history"])


def test_start_from_the_solution_stops_after_one_step(m_t_1):
    u, lam_tau, _ = newton(*m_t_1, NewtonOptions())
    _, _, info = fixed_point(*m_t_1, FixedPointOptions(), initial=(u, lam_tau))
    assert info["iterations"] == 1 and info["history"][0] <= 1e-8


def test_the_inner_solves_get_the_outer_tolerance(m_t_1, monkeypatch):
    """Options built directly (not from solve's keywords) also pass their solver_tol to the inner solver."""
    seen = []

    def spy(disc, contact, options, **kwargs):
        seen.append(options.solver_tol)
        return newton(disc, contact, options, **kwargs)

    monkeypatch.setitem(ndf.solvers.fixed_point.INNER, "newton", (spy, NewtonOptions))
    fixed_point(*m_t_1, FixedPointOptions(solver_tol=1e-11))
    assert seen and set(seen) == {1e-11}
