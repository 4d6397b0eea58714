"""Progress lines (ngdgfric.progress): the logger "ngdgfric" unless a callable is given; printed by the CLI."""

import inspect
import io
import logging

import pytest

import ngdgfric as ndf
from ngdgfric.progress import LOGGER, log, printed, reporter
from ngdgfric.studies import strategy_run, uniform_study
from ngdgfric.studies.runner import run_cases


def test_the_default_progress_is_the_logger_a_callable_gets_the_lines_and_none_silences(caplog):
    assert LOGGER.name == "ngdgfric"
    for function in (ndf.adapt, uniform_study, run_cases, strategy_run):
        assert inspect.signature(function).parameters["progress"].default is log, function
    seen = []
    reporter(seen.append)("one line")
    assert seen == ["one line"]
    with caplog.at_level(logging.INFO, logger="ngdgfric"):
        reporter(log)("to the logger")
        reporter(None)("nowhere")
    assert [record.getMessage() for record in caplog.records] == ["to the logger"]
    with pytest.raises(ValueError, match="progress must be a callable"):
        reporter("print")


def test_printed_shows_the_info_lines_in_the_block_only(caplog):
    stream = io.StringIO()
    before = (LOGGER.level, LOGGER.propagate, list(LOGGER.handlers))
    with printed(stream):
        log("level   0: 42 dofs")
        LOGGER.debug("not shown")
    log("after the block")  # silent again: logging is not configured here
    assert stream.getvalue() == "level   0: 42 dofs\n"
    assert (LOGGER.level, LOGGER.propagate, list(LOGGER.handlers)) == before
    assert "after the block" not in caplog.text and logging.getLogger().level >= logging.WARNING
