"""Checks of solver options: a ValueError naming the option and its value, before any work is done."""

from numbers import Integral, Real

import numpy as np

__all__ = ["positive_number", "positive_integer", "callback", "choice", "validate"]


def positive_number(value, name):
    """A finite real number > 0."""
    if not isinstance(value, Real) or isinstance(value, bool) or not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return float(value)


def positive_integer(value, name):
    """An integer >= 1."""
    if not isinstance(value, Integral) or isinstance(value, bool) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def callback(value, name):
    """None or a callable."""
    if value is not None and not callable(value):
        raise ValueError(f"{name} must be callable or None, got {value!r}")
    return value


def choice(*choices):
    """A validator accepting one of ``choices``."""
    def check(value, name):
        if value not in choices:
            raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")
        return value
    return check


def validate(spec, solver, **values):
    """Check ``values`` against ``spec`` (option name -> validator); None means the default.

    Unknown names raise a ValueError listing the options of ``solver``.
    """
    for name, value in values.items():
        if name not in spec:
            raise ValueError(f"solver {solver!r} has no option {name!r}; its options are {sorted(spec)}")
        if value is not None:
            spec[name](value, name)
