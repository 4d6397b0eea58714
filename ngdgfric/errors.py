"""Errors raised by the solvers."""

__all__ = ["SolverError"]


class SolverError(RuntimeError):
    """A nonlinear solver failed; ``history`` holds its convergence history (one entry per iteration)."""

    def __init__(self, message, history=(), solver=""):
        super().__init__(message)
        self.history = list(history)
        self.solver = solver
