"""ngdgfric.linalg: contact blocks added to A (Uzawa's Jacobians), sparse sums, and the scoped BLAS thread limits."""

import ctypes
import inspect
import os
import subprocess
import sys

import numpy as np
import pytest

import ngdgfric as ndf
import ngdgfric.threads
from ngdgfric.sparse import BlockSum, diagonal
from ngdgfric.threads import blas_threads, dense_threads, limited_blas


def test_block_sum_adds_the_contact_blocks_only():
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))
    contact = ndf.Contact(disc)
    groups = contact.groups()
    bs = BlockSum(disc.A, groups)
    K = disc.A.CreateMatrix()
    K.AsVector().FV().NumPy()[:] = 1.0  # a matrix with A's pattern, ones everywhere
    J = bs.update(K)
    x = disc.F.CreateVector()
    x.FV().NumPy()[:] = np.random.default_rng(0).standard_normal(len(x))
    y, z = x.CreateVector(), x.CreateVector()
    y.data = J * x
    z.data = disc.A * x
    inside = np.zeros(len(x), dtype=bool)
    inside[np.concatenate(groups)] = True
    expected = z.FV().NumPy().copy()
    block_sum = {}
    for g in groups:
        for i in g:
            block_sum[i] = sum(x.FV().NumPy()[j] for j in g)
    for i, value in block_sum.items():
        expected[i] += value
    assert np.allclose(y.FV().NumPy(), expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    assert not inside.all()


def test_diagonal_against_the_dense_matrix():
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), method="ldg")  # the stencil of the global lifting
    dense = np.array(disc.A.ToDense())
    assert diagonal(disc.A) == pytest.approx(np.diag(dense), rel=1e-15)


def openblas_threads():
    """The thread count each loaded OpenBLAS reports through its own getter (read by ctypes from
    /proc/self/maps, independently of threadpoolctl)."""
    with open("/proc/self/maps") as maps:
        paths = sorted({line.split()[-1] for line in maps if "openblas" in line.rsplit("/", 1)[-1].lower()})
    names = ("openblas_get_num_threads", "scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads")
    counts = []
    for path in paths:
        library = ctypes.CDLL(path)
        getter = next((getattr(library, name) for name in names if hasattr(library, name)), None)
        if getter is not None:
            counts.append(getter())
    return counts


def test_blas_threads_limits_inside_the_block_only():
    before = openblas_threads()
    assert before
    with blas_threads(1):
        assert set(openblas_threads()) == {1}
    assert openblas_threads() == before


def test_limited_blas_runs_the_function_under_the_limit():
    seen = limited_blas(openblas_threads)()
    assert set(seen) == {int(os.environ.get("NGDGFRIC_BLAS_THREADS", "1"))}


def test_the_environment_variable_is_read_when_the_limit_is_set(monkeypatch):
    """NGDGFRIC_BLAS_THREADS changed after import takes effect at the next call; a bad value is named."""
    for count in (2, 1):
        monkeypatch.setenv("NGDGFRIC_BLAS_THREADS", str(count))
        assert set(limited_blas(openblas_threads)()) == {count}
    for bad in ("0", "two"):
        monkeypatch.setenv("NGDGFRIC_BLAS_THREADS", bad)
        with pytest.raises(ValueError, match=f"NGDGFRIC_BLAS_THREADS must be an integer >= 1, got '{bad}'"):
            limited_blas(openblas_threads)()


def test_the_openblas_libraries_are_found_at_each_limit(monkeypatch):
    """No selection cached for the life of the process: a library loaded later is limited too (finding them
    costs 0.3 ms, see ngdgfric.threads)."""
    made = []
    controller = ngdgfric.threads.threadpoolctl.ThreadpoolController
    select = controller.select

    def counting(self, **kwargs):
        made.append(kwargs)
        return select(self, **kwargs)

    monkeypatch.setattr(controller, "select", counting)
    for _ in range(2):
        with blas_threads(1):
            assert set(openblas_threads()) == {1}
    assert len(made) == 2


def test_dense_threads_gives_all_cores_to_large_dense_solves_and_restores_the_limit():
    rng = np.random.default_rng(0)
    matrix, rhs = rng.random((1200, 1200)) + 1200 * np.eye(1200), rng.random(1200)
    expected = np.linalg.solve(matrix, rhs)
    with blas_threads(1):
        with dense_threads(1200):
            inside = openblas_threads()
            solution = np.linalg.solve(matrix, rhs)
        assert set(openblas_threads()) == {1}
        with dense_threads(999):  # small work keeps the limit
            assert set(openblas_threads()) == {1}
    assert np.allclose(solution, expected, rtol=1e-12, atol=0)
    if os.cpu_count() and os.cpu_count() > 1:
        assert min(inside) > 1


def test_importing_the_package_changes_no_thread_count():
    code = (f"import ctypes, numpy, ngsolve\n{inspect.getsource(openblas_threads)}\nbefore = openblas_threads()\n"
            "import ngdgfric\nprint(before == openblas_threads() and len(before) > 0)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"
