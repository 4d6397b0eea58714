"""Solver options: one frozen dataclass per solver, its values checked when it is built.

Each solver's options class (:class:`ngdgfric.solvers.newton.NewtonOptions`,
:class:`ngdgfric.solvers.uzawa.UzawaOptions`,
:class:`ngdgfric.solvers.fixed_point.FixedPointOptions`) derives from :class:`SolverOptions`; ``solve(**options)``
builds it with :meth:`SolverOptions.from_keywords`, so an unknown name or a bad value raises a
ValueError naming it before anything is assembled.
"""

import dataclasses
from numbers import Integral, Real

import numpy as np

__all__ = ["SolverOptions", "positive_number", "positive_integer", "callback", "choice", "optional"]


def positive_number(value, name):
    """A finite real number > 0."""
    if not isinstance(value, Real) or isinstance(value, bool) or not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")


def positive_integer(value, name):
    """An integer >= 1."""
    if not isinstance(value, Integral) or isinstance(value, bool) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")


def callback(value, name):
    """None or a callable."""
    if value is not None and not callable(value):
        raise ValueError(f"{name} must be callable or None, got {value!r}")


def choice(*choices):
    """A check accepting one of ``choices``."""
    def check(value, name):
        if value not in choices:
            raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")
    return check


def optional(check):
    """``check``, or None."""
    def check_optional(value, name):
        if value is not None:
            check(value, name)
    return check_optional


class SolverOptions:
    """Base of the solvers' frozen option dataclasses.

    A subclass sets the class attributes ``solver`` (its name in messages) and ``checks`` (field name
    -> check(value, name), raising ValueError); every field is checked when an instance is built.
    """

    solver = ""
    checks = {}

    def __post_init__(self):
        for field in dataclasses.fields(self):
            self.checks[field.name](getattr(self, field.name), field.name)

    @classmethod
    def from_keywords(cls, solver=None, **options):
        """The options from keywords (e.g. those of :func:`ngdgfric.solve`); None means the default.

        An unknown name raises a ValueError listing the options of ``solver`` (default ``cls.solver``).
        """
        known = sorted(field.name for field in dataclasses.fields(cls))
        for name in options:
            if name not in known:
                raise ValueError(f"solver {solver or cls.solver!r} has no option {name!r}; its options are {known}")
        return cls(**{name: value for name, value in options.items() if value is not None})
