"""Progress lines of the long computations: logged, not printed.

:func:`ngdgfric.adapt` (one line per level), ``ngdgfric.studies.runner.run_cases`` (one per finished case),
``ngdgfric.studies.uniform.uniform_study`` and ``ngdgfric.studies.strategies.strategy_run`` take
``progress=``: a callable(str) that receives every line, None for no lines, and by default ``log``, which sends
them to the logger ``"ngdgfric"`` (``LOGGER``) at level INFO, the convention of Python libraries: silent unless
the application configures logging, e.g. ``logging.basicConfig(format="%(message)s")`` and
``logging.getLogger("ngdgfric").setLevel(logging.INFO)``.  The command line prints them (``printed``).
"""

import contextlib
import logging
import sys

__all__ = ["LOGGER", "log", "reporter", "printed"]

LOGGER = logging.getLogger("ngdgfric")


def log(line):
    """The default ``progress``: ``line`` to ``LOGGER`` at INFO."""
    LOGGER.info(line)


def _silent(line):
    """``progress=None``: no lines."""


def reporter(progress):
    """The callable that receives the progress lines: ``progress`` (a callable(str)), or nothing for None."""
    if progress is None:
        return _silent
    if not callable(progress):
        raise ValueError(f"progress must be a callable(str), ngdgfric.progress.log (the logger 'ngdgfric') or None, "
                         f"got {progress!r}")
    return progress


@contextlib.contextmanager
def printed(stream=None):
    """Within the block, the INFO lines of ``LOGGER`` written to ``stream`` (default: ``sys.stdout`` on entry),
    the message alone, and not passed on to the root logger's handlers."""
    handler = logging.StreamHandler(sys.stdout if stream is None else stream)
    handler.setFormatter(logging.Formatter("%(message)s"))
    level, propagate = LOGGER.level, LOGGER.propagate
    LOGGER.addHandler(handler)
    LOGGER.setLevel(logging.INFO)
    LOGGER.propagate = False
    try:
        yield
    finally:
        LOGGER.removeHandler(handler)
        LOGGER.setLevel(level)
        LOGGER.propagate = propagate
