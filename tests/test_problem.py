import dataclasses
import math

import ngsolve as ngs
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ngdgfric as ndf


def test_lame_parameters_follow_section_6():
    p = ndf.example_6_1()
    assert p.mu == pytest.approx(2000 / (2 * 1.4))
    assert p.lam == pytest.approx(2000 * 0.4 / (1.4 * 0.2))


def test_examples_carry_their_geometry():
    p1, p2 = ndf.example_6_1(), ndf.example_6_2()
    assert p1.geometry.bounds == (0.0, 0.05, 1.0, 1.05)
    assert p1.geometry.labels == ("contact", "dirichlet", "traction", "traction")
    assert p2.geometry.bounds == (0.0, 0.0, 1.0, 1.0)
    assert p2.geometry.labels == ("contact", "traction", "dirichlet", "traction")


def test_replace_gives_a_valid_problem_on_the_same_geometry():
    p = dataclasses.replace(ndf.example_6_2(), E=1000.0, f=(1.0, ngs.x), g_a=0.01 * ngs.x)
    assert p.geometry == ndf.example_6_2().geometry
    mesh = ndf.uniform_mesh(p, 0.5)
    assert mesh.ne == 8


@pytest.mark.parametrize("field, value", [
    ("E", 0.0), ("E", -1.0), ("nu", 0.5), ("nu", -1.0), ("nu", 0.7), ("m_n", 0.5),
    ("c_n", -1.0), ("c_tau", -0.1), ("f", (1.0,)), ("g", "abc"), ("g_a", "x"),
    ("m_n", float("inf")), ("nu", float("nan")),
])
def test_bad_values_raise_value_error_naming_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        dataclasses.replace(ndf.example_6_1(), **{field: value})


def test_bad_geometry_labels_raise():
    with pytest.raises(ValueError, match="'floor'"):
        dataclasses.replace(ndf.example_6_1(), geometry=ndf.Polygon.rectangle(
            0, 0, 1, 1, bottom="floor", right="dirichlet", top="traction", left="traction"))
    with pytest.raises(ValueError, match="contact"):
        dataclasses.replace(ndf.example_6_1(), geometry=ndf.Polygon.rectangle(
            0, 0, 1, 1, bottom="traction", right="dirichlet", top="traction", left="traction"))
    with pytest.raises(ValueError, match="counter-clockwise"):
        ndf.Polygon(((0, 0), (0, 1), (1, 1)), ("a", "b", "c"))


def test_negative_spatially_varying_friction_bound_is_rejected_when_solving():
    p = dataclasses.replace(ndf.example_6_1(), c_tau=450 * (ngs.x - 0.5))
    with pytest.raises(ValueError, match="c_tau"):
        ndf.solve(p, ndf.uniform_mesh(p, 0.5))


NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize("field, value", [
    ("g_a", NAN), ("g_a", INF), ("c_n", INF), ("c_tau", -INF), ("E", INF), ("E", 10**400), ("m_t", INF),
    ("f", (0.0, NAN)), ("g", (INF, 0.0)),
])
def test_non_finite_numbers_raise_naming_the_field(field, value):
    # g_a = nan gave the no-contact solution with exit 0; the others ended as "did not converge"
    with pytest.raises(ValueError, match=rf"{field}(\[\d\])? must be a finite number"):
        dataclasses.replace(ndf.example_6_1(), **{field: value})


FIELDS = {"E": (0, None, True), "nu": (-1, 0.5, True), "c_n": (0, None, False), "m_n": (1, None, False),
          "g_a": (None, None, False), "c_tau": (0, None, False), "m_t": (0, None, False)}


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(st.sampled_from(sorted(FIELDS)),
       st.floats() | st.integers(-10**400, 10**400) | st.booleans() | st.text(max_size=3) | st.none())
def test_any_number_is_accepted_exactly_when_valid(field, value):
    """ContactProblem accepts a number for a field iff it is a finite real in the field's range (the
    range written out here from Section 1 and the docstring), else a ValueError naming the field."""
    low, high, low_open = FIELDS[field]
    try:
        number = float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None
    except OverflowError:
        number = None
    valid = number is not None and math.isfinite(number) and (
        low is None or number > low or (number == low and not low_open)) and (high is None or number < high)
    try:
        dataclasses.replace(ndf.example_6_1(), **{field: value})
    except ValueError as exc:
        assert not valid and str(exc).startswith(field)
        return
    assert valid
