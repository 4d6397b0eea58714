"""Helpers shared by scripts/ and benchmarks/: the common options, results folder, timing, Markdown/CSV/figure
writers, a process pool.  The benchmarks import it with scripts/ put on sys.path (see any of them)."""

import argparse
import csv
import dataclasses
import multiprocessing
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from ngdgfric import files
from ngdgfric.examples import EXAMPLES
from ngdgfric.output import write_png
from ngdgfric.threads import call_limited

RESULTS = Path(__file__).resolve().parent.parent / "results"


def script_parser(doc, quick, example=None):
    """The argument parser of every script and benchmark; the caller adds its own options to it.

    ``doc``: the module docstring, whose first paragraph describes the script; ``quick``: the help of ``--quick``
    (the smoke-sized run the tests call).  Every parser has ``--quick`` and ``--out`` (default results/);
    ``example``: None (no ``--example``), ``"one"`` (one of the paper's examples, default 6.1) or ``"many"`` (one
    or more, default both)."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help=quick)
    parser.add_argument("--out", type=Path, default=RESULTS, help="output folder (default: results/)")
    if example == "one":
        parser.add_argument("--example", choices=sorted(EXAMPLES), default="6.1")
    elif example == "many":
        parser.add_argument("--example", nargs="+", choices=sorted(EXAMPLES), default=sorted(EXAMPLES))
    elif example is not None:
        raise ValueError(f"example must be None, 'one' or 'many', not {example!r}")
    return parser


def contact_free(problem):
    """The same problem without contact forces: no friction, a gap no displacement closes."""
    return dataclasses.replace(problem, c_tau=0.0, g_a=1e6)


def best(repeat, function):
    """(smallest seconds, result of that run) over ``repeat`` calls of function()."""
    runs = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        runs.append((time.perf_counter() - start, result))
    return min(runs, key=lambda run: run[0])


def results_path(name):
    """Path of a file in results/ (created if missing)."""
    RESULTS.mkdir(exist_ok=True)
    return RESULTS / name


def command_line():
    """The command that ran this script, for 'regenerate with' notes."""
    script = Path(sys.argv[0]).resolve()
    try:
        script = script.relative_to(RESULTS.parent)
    except ValueError:
        pass
    return " ".join(["python", str(script)] + sys.argv[1:])


def write_csv(path, rows, fields=None):
    """Rows as CSV, written atomically (columns ``fields``, default the first row's keys)."""
    files.write_csv(path, rows, fields or list(rows[0]))


def read_csv(path, text=()):
    """The rows of a CSV that ``write_csv`` wrote, numbers as numbers (an int where the text is one, else a float),
    the columns ``text`` kept as text whatever they hold; empty cells left out of their row."""

    def value(key, cell):
        if key in text:
            return cell
        for kind in (int, float):
            try:
                return kind(cell)
            except ValueError:
                pass
        return cell

    with open(path, newline="") as handle:
        return [{key: value(key, cell) for key, cell in row.items() if cell != ""} for row in csv.DictReader(handle)]


def fmt(value, spec=".4e"):
    return "-" if value is None else format(value, spec)


def say(message):
    print(message, flush=True)



def save_figure(fig, path, dpi=120):
    """Lay out, write (:func:`ngdgfric.output.write_png`) and close a pyplot figure."""
    import matplotlib.pyplot as plt

    write_png(fig, path, dpi)
    plt.close(fig)


def run_script(main):
    """A script's ``main()`` under the OpenBLAS limit of the library's entry points
    (:func:`ngdgfric.threads.blas_threads`): the work a script does outside solve/estimate/adapt
    (assembly, factorisations, dense eigenvalues) runs as the library's does."""
    return call_limited(main)


def in_processes(function, items, workers):
    """(index, function(item)) for every item as it finishes: in this process (workers = 1) or in a
    pool of ``workers`` spawned processes (cancelled on an exception or when the caller stops)."""
    if workers == 1:
        for index, item in enumerate(items):
            yield index, function(item)
        return
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = {pool.submit(call_limited, function, item): index for index, item in enumerate(items)}
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        pool.shutdown(wait=False, cancel_futures=True)
