"""Errors raised by the solvers, and warnings that point at the user's code."""

import importlib
import sys
import time
import warnings
from pathlib import Path

__all__ = ["SolverError", "TimeLimitError", "SolverWarning", "deadline", "check_deadline", "warn"]

PACKAGE = str(Path(__file__).resolve().parent)
IMPORTLIB = str(Path(importlib.__file__).resolve().parent)


class SolverError(RuntimeError):
    """A nonlinear solver failed; ``history`` holds its convergence history (one entry per iteration).

    Raised by :func:`ngdgfric.solve` (and :func:`ngdgfric.adapt`) when the contact solver diverges or does not
    converge in ``maxit`` iterations; exit code 1 of the command line.

    Parameters
    ----------
    message : str
        What failed.
    history : iterable of float, optional
        The solver's convergence history, one entry per iteration.  Default ``()``.
    solver : str, optional
        The solver's name, e.g. ``"newton"``.  Default ``""``.

    Attributes
    ----------
    history : list of float
        The convergence history.
    solver : str
        The solver's name.
    """

    def __init__(self, message, history=(), solver=""):
        super().__init__(message)
        self.history = list(history)
        self.solver = solver


class TimeLimitError(SolverError):
    """A solver reached its time limit (option ``max_seconds``) before its tolerance.

    A :class:`ngdgfric.SolverError`, raised by :func:`ngdgfric.solve` with the option ``max_seconds`` of
    :class:`ngdgfric.NewtonOptions`, :class:`ngdgfric.UzawaOptions` or :class:`ngdgfric.FixedPointOptions`.

    Parameters
    ----------
    message : str
        How far the solver got.
    history : iterable of float, optional
        The solver's convergence history up to the limit.  Default ``()``.
    solver : str, optional
        The solver's name.  Default ``""``.
    """


class SolverWarning(RuntimeWarning):
    """A solver took a fallback that its result survived but that you should know about.

    The fallbacks: a singular Newton system solved by least squares, or a Delassus diagonal entry raised to a
    floor (``Solution.info`` of the solve counts them: ``least_squares_solves``, ``clamped_points``).
    """


def deadline(max_seconds):
    """The ``time.perf_counter()`` reading at which a run limited to ``max_seconds`` (None: unlimited) ends."""
    return None if max_seconds is None else time.perf_counter() + max_seconds


def check_deadline(when, solver, history, what):
    """Raise ``TimeLimitError`` for ``solver`` (with its ``history``) if the ``deadline`` ``when`` has passed;
    ``what`` says how far it got."""
    if when is not None and time.perf_counter() > when:
        raise TimeLimitError(f"{solver} stopped at its time limit (max_seconds) {what}", history=history,
                             solver=solver)


def _ours(frame):
    """True for a frame of ngdgfric or of the import machinery (an old import path: its stub module is imported)."""
    name = frame.f_code.co_filename
    return name.startswith("<frozen importlib") or str(Path(name).resolve()).startswith((PACKAGE, IMPORTLIB))


def warn(message, category):
    """``warnings.warn(message, category)`` attributed to the first caller outside ngdgfric (the line of the
    user's script that called solve, estimate, adapt ... or used an old name), however deep inside the package or
    the import machinery it is issued; the warning filters see that caller's module (a DeprecationWarning shows
    in ``__main__``, as Python's default filters intend)."""
    frame = sys._getframe(1)
    while frame is not None and _ours(frame):
        frame = frame.f_back
    if frame is None:  # called from the package itself, with no caller outside it
        warnings.warn(message, category, stacklevel=2)
        return
    # no module_globals: with them warn_explicit asks the module's loader for its source, which raises ImportError
    # for __main__ in the REPL, python -c and python - (its loader is BuiltinImporter); warnings.warn never asks
    caller = frame.f_globals
    warnings.warn_explicit(message, category, frame.f_code.co_filename, frame.f_lineno,
                           module=caller.get("__name__", "__main__"),
                           registry=caller.setdefault("__warningregistry__", {}))
