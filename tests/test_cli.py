"""TOML problem files (ngdgfric.problem_file) and the command line (ngdgfric.cli)."""

import csv
import dataclasses
import inspect
import signal
import sys
import threading
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.cli import build_parser, main
from ngdgfric.problem_file import example_file, load_problem, tomllib

H = 0.25


def solve(problem):
    return ndf.solve(problem, ndf.uniform_mesh(problem, H))


def coefficients(problem):
    return solve(problem).u.vec.FV().NumPy().copy()


def variant(tmp_path, old, new, name="variant.toml"):
    """The shipped Example 6.1 file with one piece of text replaced."""
    text = example_file("6.1").read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


def test_spatially_varying_gap(tmp_path):
    problem = load_problem(variant(tmp_path, "g_a = 0.05 ", 'g_a = "0.05 - 0.01*x"'))
    assert isinstance(problem.g_a, ngs.CoefficientFunction)
    expected = dataclasses.replace(ndf.example_6_1(), g_a=0.05 - 0.01 * ngs.x)
    u = coefficients(problem)
    assert np.max(np.abs(u - coefficients(expected))) < 1e-12
    # the gap is seen (c_n = 1 is a soft foundation, so only slightly, but far above round-off)
    assert np.max(np.abs(u - coefficients(ndf.example_6_1()))) > 1e-7


def printed_numbers(output):
    """{label: value} of the indented result lines of `ngdgfric solve` (without the timing)."""
    pairs = [line.split(maxsplit=1) for line in output.splitlines() if line.startswith("  ")]
    return {label: value for label, value in pairs if label != "time"}


@pytest.mark.slow
def test_solve_command_matches_the_api(tmp_path, capsys):
    sol = solve(ndf.example_6_1())
    expected = dict(ndof=sol.ndof, iterations=sol.iterations, energy_norm=ndf.energy_norm(sol),
                    eta_h=ndf.estimate(sol).eta_h)
    printed = []
    for problem, tag in (("6.1", "6_1"), (str(example_file("6.1")), "example_6_1")):
        assert main(["solve", problem, "--h", str(H), "--out", str(tmp_path)]) == 0
        printed.append(printed_numbers(capsys.readouterr().out))
        with open(tmp_path / f"{tag}_sipg_p1.csv") as handle:
            (row,) = csv.DictReader(handle)
        assert int(row["ndof"]) == expected["ndof"]
        assert int(row["iterations"]) == expected["iterations"]
        assert float(row["energy_norm"]) == pytest.approx(expected["energy_norm"], rel=1e-10)
        assert float(row["eta_h"]) == pytest.approx(expected["eta_h"], rel=1e-10)
        vtu = (tmp_path / f"{tag}_sipg_p1.vtu").read_text(errors="replace")
        assert "displacement" in vtu and "von_mises" in vtu
        assert (tmp_path / f"{tag}_sipg_p1.png").stat().st_size > 0
    assert printed[0] == printed[1]
    check_forces(tmp_path / f"{tag}_sipg_p1", sol)
    assert int(printed[0]["DOFs"]) == expected["ndof"]
    assert float(printed[0]["|||u_h|||_h"]) == pytest.approx(expected["energy_norm"], rel=1e-9)
    assert float(printed[0]["eta_h"]) == pytest.approx(expected["eta_h"], rel=1e-9)


def check_forces(stem, sol):
    """The forces CSV and the contact PNG next to the outputs ``stem``.* hold the forces of the solution ``sol``."""
    balance = ndf.force_balance(sol)
    with open(f"{stem}_forces.csv") as handle:
        rows = {(row["kind"], row["side"]): row for row in csv.DictReader(handle)}
    assert set(rows) == {("dirichlet", "dirichlet"), ("contact", "contact"), ("traction", "traction"), ("body", ""),
                         ("residual", "")}
    for kind, side, vector in [*balance.vectors(), ("residual", "", balance.residual)]:
        row = rows[(kind, side)]
        assert [float(row["force_x"]), float(row["force_y"])] == pytest.approx(vector, rel=1e-10, abs=1e-9)
    contact, side = rows[("contact", "contact")], balance.contact["contact"]
    assert float(contact["normal"]) == pytest.approx(side.normal, rel=1e-10)
    assert float(contact["tangential"]) == pytest.approx(side.tangential, rel=1e-10)
    for zone in ("contact", "stick", "slip"):
        assert float(contact[f"{zone}_length"]) == pytest.approx(getattr(side, zone).length, rel=1e-10)
        assert int(contact[f"{zone}_pieces"]) == len(getattr(side, zone).pieces)
    assert float(contact["contact_end_x"]) == pytest.approx(side.contact.end[0], rel=1e-10)
    residual = np.hypot(float(rows[("residual", "")]["force_x"]), float(rows[("residual", "")]["force_y"]))
    assert residual < 1e-12 * np.hypot(float(contact["force_x"]), float(contact["force_y"]))  # equilibrium
    assert Path(f"{stem}_contact.png").stat().st_size > 0


def test_solve_prints_the_forces(tmp_path, capsys):
    assert main(["solve", "6.2", "--h", "0.5", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    lines = out[out.index("forces on the body"):].splitlines()
    balance = ndf.force_balance(ndf.solve(ndf.example_6_2(), ndf.uniform_mesh(ndf.example_6_2(), 0.5)))
    reaction = balance.reactions["dirichlet"].force
    assert f"  dirichlet side 'dirichlet': reaction ({reaction[0]:.6e}, {reaction[1]:.6e})" in lines
    side = balance.contact["contact"]
    assert f"  contact side 'contact': normal {side.normal:.6e}, tangential {side.tangential:.6e}" in out
    assert any(line.startswith("    slip zone") for line in lines) and lines[-2].startswith("  equilibrium: ")
    assert "_forces.csv" in lines[-1] and "_contact.png" in lines[-1]


def test_the_command_line_has_the_libraries_defaults():
    # one source: every option of `adaptive` and `solve` defaults to the keyword of ndf.adapt / ndf.solve (or to the
    # field of ndf.AdaptOptions, the keywords' grouped form)
    adaptive = build_parser().parse_args(["adaptive", "6.1"])
    options = dict(method="method", order="order", theta="theta", levels="max_levels", max_ndof="max_ndof",
                   tol="tol", hp="hp", max_order="max_order", variant="variant", solver="solver",
                   max_seconds="max_seconds", eta="eta", solver_tol="solver_tol", layers="layers")
    signature = {**inspect.signature(ndf.adapt).parameters, **inspect.signature(ndf.AdaptOptions).parameters}
    assert {name: getattr(adaptive, name) for name in options} == {
        name: signature[keyword].default for name, keyword in options.items()}
    assert (adaptive.order, adaptive.theta, adaptive.levels, adaptive.max_ndof, adaptive.hp) == (4, 0.8, 100, 10**6,
                                                                                                 True)
    solve = build_parser().parse_args(["solve", "6.1"])
    signature = inspect.signature(ndf.solve).parameters
    keywords = ("method", "order", "solver")
    assert (solve.method, solve.order, solve.solver) == tuple(signature[k].default for k in keywords)


@pytest.mark.slow
def test_an_adaptive_run_that_stops_before_its_tolerance_exits_with_4(tmp_path, capsys):
    assert main(["adaptive", "6.2", "--levels", "2", "--tol", "1e-9", "--out", str(tmp_path)]) == 4
    err = capsys.readouterr().err
    assert "stopped before --tol 1e-09 (--levels reached): eta_h = " in err and "after 2 levels" in err
    assert (tmp_path / "6_2_adaptive_auto_p4_hp.csv").exists()  # the levels done are written
    assert main(["adaptive", "6.2", "--tol", "1e3", "--out", str(tmp_path), "--overwrite"]) == 0
    assert main(["adaptive", "6.2", "--no-hp", "--order", "1", "--max-seconds", "1e-9", "--tol", "1e-9",
                 "--out", str(tmp_path)]) == 4
    assert "(--max-seconds reached)" in capsys.readouterr().err
    # without --tol or --rtol the run has the default accuracy: a budget stop before it is said, not an error
    assert main(["adaptive", "6.2", "--levels", "2", "--out", str(tmp_path), "--overwrite"]) == 0
    out = capsys.readouterr().out
    assert "target: eta_h <= rtol |||u_h|||_h with rtol = 0.001, the default" in out
    assert "stopped before the default accuracy rtol = 0.001 (--levels reached): eta_h = " in out


@pytest.mark.slow
def test_uniform_and_adaptive_commands(tmp_path, capsys):
    assert main(["uniform", "6.2", "--levels", "2", "--method", "sipg", "nipg", "--out", str(tmp_path)]) == 0
    with open(tmp_path / "6_2_uniform.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["method"] for r in rows] == ["sipg", "nipg"]
    assert "| sipg | 2^-1 |" in (tmp_path / "6_2_uniform.md").read_text()
    assert main(["adaptive", "6.1", "--levels", "3", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert out.count("level ") == 3 and "method cg: nu = 0.4 is moderate" in out
    with open(tmp_path / "6_1_adaptive_auto_p4_hp.csv") as handle:
        levels = list(csv.DictReader(handle))
    assert [int(r["level"]) for r in levels] == [0, 1, 2]
    assert (tmp_path / "6_1_adaptive_auto_p4_hp.png").stat().st_size > 0
    assert f"final solution ({levels[-1]['ndof']} DOFs): forces on the body" in out  # printed and written
    with open(tmp_path / "6_1_adaptive_auto_p4_hp_forces.csv") as handle:
        forces = {row["kind"]: row for row in csv.DictReader(handle)}
    assert float(forces["contact"]["normal"]) > 0 and float(forces["contact"]["slip_length"]) > 0
    assert abs(float(forces["residual"]["force_x"])) < 1e-12 * abs(float(forces["dirichlet"]["force_x"]))
    assert (tmp_path / "6_1_adaptive_auto_p4_hp_contact.png").stat().st_size > 0
    # a re-run with other options does not touch an earlier run's output unless asked to
    before = (tmp_path / "6_1_adaptive_auto_p4_hp.csv").read_bytes()
    assert main(["adaptive", "6.1", "--levels", "1", "--variant", "paper", "--out", str(tmp_path)]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert (tmp_path / "6_1_adaptive_auto_p4_hp.csv").read_bytes() == before
    # --variant paper: the same loop with the estimator of Section 4 as printed (larger: E = 2000)
    assert main(["adaptive", "6.1", "--levels", "1", "--variant", "paper", "--out", str(tmp_path),
                 "--overwrite"]) == 0
    with open(tmp_path / "6_1_adaptive_auto_p4_hp.csv") as handle:
        paper = list(csv.DictReader(handle))
    assert float(paper[0]["eta_h"]) > 20 * float(levels[0]["eta_h"])
    # its old name --weights still works, with a warning (for one release)
    capsys.readouterr()
    assert main(["adaptive", "6.1", "--levels", "1", "--weights", "paper", "--out", str(tmp_path),
                 "--overwrite"]) == 0
    assert "ngdgfric: warning: --weights is deprecated and will be removed in the next release: use --variant" in \
        capsys.readouterr().err
    with open(tmp_path / "6_1_adaptive_auto_p4_hp.csv") as handle:
        assert list(csv.DictReader(handle))[0]["eta_h"] == paper[0]["eta_h"]


L_SHAPE = """
name = "L-shaped block"
[material]
E = 1000
nu = 0.3
[geometry]
vertices = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]
labels = ["floor", "free", "free", "free", "wall", "free"]
[boundaries]
dirichlet = "wall"
traction = "free"
contact = "floor"
[loads]
f = [0, "-10*sin(pi*x/2)"]
[contact]
c_n = 1e4
m_n = 1.5
g_a = "0.001*(x - 1)**2"
c_tau = 20
"""


def test_general_polygon(tmp_path, capsys):
    path = tmp_path / "lshape.toml"
    path.write_text(L_SHAPE)
    problem = load_problem(path)
    assert problem.boundary_names() == ("wall", "free", "floor") and problem.g == (0.0, 0.0)
    assert main(["solve", str(path), "--maxh", "0.5", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "lshape_sipg_p1.png").stat().st_size > 0
    capsys.readouterr()
    check_one_line_error(main(["solve", str(path), "--h", "0.5", "--out", str(tmp_path)]), capsys, "--maxh")


def test_every_command_runs_on_a_rectangle_whose_sides_the_default_sizes_do_not_divide(tmp_path, capsys):
    # 1.3 x 0.7: solve (h = 0.125), adaptive (h = 1/2) and uniform (h = 1/2, 1/4) exited 2 on this valid file
    path = variant(tmp_path, "[[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]",
                   "[[0.0, 0.05], [1.3, 0.05], [1.3, 0.75], [0.0, 0.75]]", "rectangle.toml")
    assert main(["solve", str(path), "--out", str(tmp_path)]) == 0
    assert "cells of sides at most 0.125, 132 elements" in capsys.readouterr().out  # 11 x 6 cells
    assert main(["adaptive", str(path), "--levels", "2", "--out", str(tmp_path)]) == 0
    assert main(["uniform", str(path), "--levels", "3", "--out", str(tmp_path)]) == 0
    with open(tmp_path / "rectangle_uniform.csv") as handle:
        assert [int(row["k"]) for row in csv.DictReader(handle)] == [1, 2]
    # the default mesh's size is checked before meshing: a 300 x 300 rectangle (11.5 million triangles) was meshed
    # and ran out of memory; its refusal names the default mesh
    huge = variant(tmp_path, "[[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]",
                   "[[0.0, 0.0], [300.0, 0.0], [300.0, 300.0], [0.0, 300.0]]", "huge.toml")
    capsys.readouterr()
    check_one_line_error(main(["solve", str(huge), "--out", str(tmp_path)]), capsys,
                         "the default mesh (cells of sides at most 0.125): ")
    # 6 x 2 x (3 x 16) x (2 x 16) P1 DOFs, counted exactly
    check_one_line_error(main(["uniform", str(path), "--levels", "5", "--max-ndof", "1000", "--out", str(tmp_path),
                               "--overwrite"]), capsys, "--levels 5: 1.843e+04 DOFs")


BAD_ARGUMENTS = {
    "unknown method": (["solve", "6.1", "--method", "dg"], "--method"),
    "negative h": (["solve", "6.1", "--h", "-0.25"], "--h"),
    "h not dividing the sides": (["solve", "6.1", "--h", "0.3"], "does not divide"),
    "bad order": (["solve", "6.1", "--order", "0"], "--order"),
    "non-integer order": (["solve", "6.1", "--order", "1.5"], "--order"),
    "infinite order": (["solve", "6.1", "--order", "inf"], "--order"),
    "unknown command": (["bogus", "6.1"], "bogus"),
    "missing file": (["solve", "missing.toml"], "missing.toml"),
    "bad theta": (["adaptive", "6.1", "--theta", "1.5"], "--theta"),
    # the size is estimated before meshing (h = 1e-5 asked for 74 GiB; maxh = 1e-9 ran away in Netgen)
    "tiny h": (["solve", "6.1", "--h", "1e-5"], "--h 1e-05"),
    "tiny maxh": (["solve", "6.1", "--maxh", "1e-9"], "--maxh 1e-09"),
    "too many uniform levels": (["uniform", "6.2", "--levels", "14"], "GB"),
    "above --max-ndof": (["solve", "6.1", "--h", "0.125", "--max-ndof", "100"], "max_ndof = 100"),
}

DATA = Path(__file__).resolve().parent / "data"
BAD_FILES = {case.pop("name"): case for case in tomllib.loads((DATA / "bad_problem_files.toml").read_text())["case"]}
FOUND_WHEN_SOLVING = sorted(name for name, case in BAD_FILES.items() if "api" in case)


def check_one_line_error(code, capsys, expected):
    err = capsys.readouterr().err
    assert code == 2
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("ngdgfric: error: ")
    assert expected in lines[0]


@pytest.mark.parametrize("case", sorted(BAD_ARGUMENTS))
def test_bad_arguments(case, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv, expected = BAD_ARGUMENTS[case]
    check_one_line_error(main([*argv, "--out", str(tmp_path)]), capsys, expected)


@pytest.mark.parametrize("case", sorted(set(BAD_FILES) - set(FOUND_WHEN_SOLVING)))
def test_bad_problem_files(case, tmp_path, capsys):
    old, new, expected = (BAD_FILES[case][key] for key in ("old", "new", "cli"))
    path = variant(tmp_path, old, new, name="bad.toml")
    check_one_line_error(main(["solve", str(path), "--out", str(tmp_path)]), capsys, expected)
    with pytest.raises(ValueError, match="bad.toml"):
        load_problem(path)


@pytest.mark.parametrize("case", FOUND_WHEN_SOLVING)
def test_data_checked_pointwise(case, tmp_path, capsys):
    old, new, in_cli, in_api = (BAD_FILES[case][key] for key in ("old", "new", "cli", "api"))
    path = variant(tmp_path, old, new, name="bad.toml")
    check_one_line_error(main(["solve", str(path), "--out", str(tmp_path)]), capsys, f"bad.toml: {in_cli}")
    problem = load_problem(path)
    with pytest.raises(ValueError, match=in_api):
        ndf.solve(problem, ndf.uniform_mesh(problem, 0.25))


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.startswith("ngdgfric ")


@pytest.mark.parametrize("command", ["solve", "uniform", "adaptive"])
def test_unwritable_output_folder_is_refused_before_computing(command, tmp_path, capsys, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setattr("ngdgfric.commands.solve", None)  # nothing may be computed
    monkeypatch.setattr("ngdgfric.commands.uniform_study", None)
    monkeypatch.setattr("ngdgfric.commands.adapt", None)
    check_one_line_error(main([command, "6.2", "--out", str(blocker / "out")]), capsys, "cannot write to the output")


def test_unwritable_output_file_is_an_error(tmp_path, capsys):
    (tmp_path / "6_2_sipg_p1.vtu").mkdir()  # reported as "wrote ...vtu" with exit 0 before
    check_one_line_error(main(["solve", "6.2", "--h", "0.5", "--out", str(tmp_path)]), capsys, "is a folder")
    check_one_line_error(main(["solve", "6.2", "--h", "0.5", "--out", str(tmp_path), "--overwrite"]), capsys,
                         "is a folder")


def test_interrupted_uniform_run_keeps_its_finished_studies(tmp_path, capsys, monkeypatch):
    from ngdgfric import commands

    original, calls = commands.uniform_study, []

    def study_then_interrupt(*args, **kwargs):  # Ctrl-C during the second study
        calls.append(args[1])
        if len(calls) == 2:
            raise KeyboardInterrupt
        return original(*args, **kwargs)

    monkeypatch.setattr(commands, "uniform_study", study_then_interrupt)
    assert main(["uniform", "6.2", "--levels", "2", "--method", "sipg", "nipg", "--out", str(tmp_path)]) == 130
    with open(tmp_path / "6_2_uniform.csv") as handle:
        assert {r["method"] for r in csv.DictReader(handle)} == {"sipg"}
    assert "| sipg | 2^-1 |" in (tmp_path / "6_2_uniform.md").read_text()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary files left


@pytest.fixture
def callers_sigterm_handler():
    """A SIGTERM handler of the caller's, which main must not run and must restore (without one, SIGTERM ends
    pytest)."""
    def previous(signum, frame):
        raise AssertionError("the caller's SIGTERM handler ran while main ran")

    before = signal.signal(signal.SIGTERM, previous)
    yield previous
    signal.signal(signal.SIGTERM, before)


def test_sigterm_while_main_runs_exits_143_and_main_restores_the_previous_handler(tmp_path, capsys, monkeypatch,
                                                                                  callers_sigterm_handler):
    from ngdgfric import cli

    def terminated(args, problem, tag):
        signal.raise_signal(signal.SIGTERM)
        pytest.fail("SIGTERM did not stop the command")

    monkeypatch.setitem(cli.COMMANDS, "solve", terminated)
    assert main(["solve", "6.2", "--out", str(tmp_path)]) == 143
    assert capsys.readouterr().err == "ngdgfric: error: terminated (SIGTERM)\n"
    assert signal.getsignal(signal.SIGTERM) is callers_sigterm_handler
    monkeypatch.setitem(cli.COMMANDS, "solve", lambda args, problem, tag: [])
    assert main(["solve", "6.2", "--out", str(tmp_path)]) == 0  # a run that ends normally restores it too
    assert signal.getsignal(signal.SIGTERM) is callers_sigterm_handler
    assert "ngdgfric-sigterm" not in [thread.name for thread in threading.enumerate()]


def lost_in_pybind11():
    try:
        signal.raise_signal(signal.SIGTERM)
    except KeyboardInterrupt:  # cleared, as while ngs.CF((a, b)) tries its next overload
        pass


def made_another_error():
    try:
        signal.raise_signal(signal.SIGTERM)
    except KeyboardInterrupt:
        raise RuntimeError("Unable to cast Python instance of type <class 'tuple'> to C++ type '?'") from None


class Finalized:
    def __del__(self):
        signal.raise_signal(signal.SIGTERM)


def dropped_in_del():
    Finalized()  # collected at once


@pytest.mark.parametrize("lose", [lost_in_pybind11, made_another_error, dropped_in_del])
def test_a_lost_sigterm_still_ends_the_run_with_143(lose, tmp_path, capsys, monkeypatch, callers_sigterm_handler):
    from ngdgfric import cli

    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)

    def lost_then_busy(args, problem, tag):
        lose()
        time.sleep(10 * cli.RESEND)
        pytest.fail("the SIGTERM was not sent again")

    monkeypatch.setitem(cli.COMMANDS, "solve", lost_then_busy)
    start = time.perf_counter()
    assert main(["solve", "6.2", "--out", str(tmp_path)]) == 143
    assert time.perf_counter() - start < 5 * cli.RESEND
    assert capsys.readouterr().err == "ngdgfric: error: terminated (SIGTERM)\n"
    assert unraisable == [] and sys.unraisablehook == unraisable.append  # nothing printed, the hook restored
    assert signal.getsignal(signal.SIGTERM) is callers_sigterm_handler


def test_sigterm_does_not_interrupt_the_cleanup_of_an_interrupt(tmp_path, capsys, monkeypatch,
                                                                callers_sigterm_handler):
    from ngdgfric import cli

    cleaned = []

    def interrupted(args, problem, tag):
        try:
            raise KeyboardInterrupt
        finally:  # a cleanup, such as removing a temporary file
            signal.raise_signal(signal.SIGTERM)
            cleaned.append(True)

    monkeypatch.setitem(cli.COMMANDS, "solve", interrupted)
    assert main(["solve", "6.2", "--out", str(tmp_path)]) == 130
    assert cleaned == [True]


def test_problem_file_that_is_not_utf8_is_named(tmp_path, capsys):
    path = tmp_path / "latin1.toml"
    path.write_bytes(example_file("6.1").read_bytes().replace(b'"Example 6.1"', b'"Exemple \xe9"'))
    check_one_line_error(main(["solve", str(path), "--out", str(tmp_path)]), capsys, "latin1.toml: not a UTF-8 text")


def test_adaptive_passes_the_solver_tolerance(tmp_path, monkeypatch):
    seen = {}

    class Stop(Exception):
        pass

    def fake_adapt(*args, **kwargs):
        seen.update(kwargs)
        raise Stop

    monkeypatch.setattr("ngdgfric.commands.adapt", fake_adapt)
    main(["adaptive", "6.2", "--solver-tol", "1e-10", "--tol", "0.5", "--out", str(tmp_path)])  # stopped in adapt
    assert seen["solver_tol"] == 1e-10 and seen["tol"] == 0.5
