"""Thread policy: NGSolve's TaskManager for large work only, OpenBLAS limited while the entry points run.

On a machine with few cores, idle OpenBLAS threads busy-wait and take the cores from NGSolve's
TaskManager; small sparse work gains nothing from threads.  Everything here is scoped to a call
(a context manager or a decorator); importing changes nothing and nothing is cached: the environment
variable ``NGDGFRIC_BLAS_THREADS`` is read, and the loaded OpenBLAS libraries are found, each time a limit
is set (``blas_threads``), so a change of either takes effect at the next call.  Finding them costs a
fraction of a millisecond, little against what each limit wraps: the solve, estimate or adapt call, or a dense
solve of 1000 or more rows, tens of milliseconds and up (the timing: :ref:`decisions-threads`).
"""

import contextlib
import functools
import os

import ngsolve as ngs
import threadpoolctl

__all__ = ["blas_threads", "default_blas_threads", "limited_blas", "call_limited", "dense_threads", "threads"]


PARALLEL_FROM = 20000


def threads(size):
    """NGSolve's TaskManager for work on ``size`` >= 20000 unknowns, else nothing.

    Small operations gain nothing from threads, and on a machine whose other cores are busy a
    parallel region can wait milliseconds for a descheduled worker (seen: 10x slower Newton
    steps at 200 DOFs while another process ran).
    """
    return ngs.TaskManager() if size >= PARALLEL_FROM else contextlib.nullcontext()


BLAS_THREADS_VARIABLE = "NGDGFRIC_BLAS_THREADS"
DENSE_PARALLEL_FROM = 1000


def default_blas_threads():
    """OpenBLAS threads inside ``blas_threads`` by default: the environment variable NGDGFRIC_BLAS_THREADS
    (an integer >= 1) when it is set, else 1; read at each call.  ValueError naming the variable if it is not
    such an integer."""
    value = os.environ.get(BLAS_THREADS_VARIABLE, "1")
    try:
        count = int(value)
    except ValueError:
        count = 0
    if count < 1:
        raise ValueError(f"the environment variable {BLAS_THREADS_VARIABLE} must be an integer >= 1, got {value!r}")
    return count


def _openblas():
    """The OpenBLAS libraries loaded in this process now (numpy's, NGSolve's, and any loaded since the last
    call), found by threadpoolctl (cheap: module docstring)."""
    return threadpoolctl.ThreadpoolController().select(internal_api="openblas")


@contextlib.contextmanager
def blas_threads(count=None):
    """Limit every OpenBLAS of the process to ``count`` threads (default :func:`default_blas_threads`: the
    environment variable NGDGFRIC_BLAS_THREADS, else 1) inside the block; the previous limits come back at
    its end.

    Idle OpenBLAS threads busy-wait for a while after each call; on two cores they took the cores
    from NGSolve's TaskManager, and inside Newton each sparse back-substitution took 30-40 ms
    instead of 3-4 ms (Example 6.1, P2, 24576 DOFs).  Small dense work (12 x 12 blocks, batched
    Vandermonde solves) gains nothing from BLAS threads; large dense solves get all cores back in
    :func:`dense_threads`.  MKL (PARDISO's) is left alone.
    """
    with _openblas().limit(limits=default_blas_threads() if count is None else count):
        yield


def call_limited(function, *args, **kwargs):
    """``function(*args, **kwargs)`` inside ``blas_threads`` (module level: picklable for process pools)."""
    with blas_threads():
        return function(*args, **kwargs)


def limited_blas(function):
    """``function`` run inside ``blas_threads`` (the entry points solve, adapt, estimate)."""
    @functools.wraps(function)
    def limited(*args, **kwargs):
        return call_limited(function, *args, **kwargs)
    return limited


@contextlib.contextmanager
def dense_threads(rows):
    """All cores for OpenBLAS inside the block if the dense work has >= 1000 ``rows``, else nothing.

    The dense Newton systems of the condensed contact problem (:mod:`ngdgfric.solvers.reduced`) reach
    3500 rows on hp meshes; a dense solve of 2700 rows took 0.35 s on one thread and 0.22 s on two.
    No NGSolve work runs inside the block, so busy-waiting BLAS threads steal nothing from it.
    """
    if rows < DENSE_PARALLEL_FROM:
        yield
        return
    with blas_threads(os.cpu_count() or 1):
        yield
