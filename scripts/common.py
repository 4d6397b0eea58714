"""Helpers shared by the scripts: examples by name, results folder, Markdown/CSV writers."""

import csv
import os
import sys
from pathlib import Path

import ngdgfric as ndf

RESULTS = Path(__file__).resolve().parent.parent / "results"
EXAMPLES = {"6.1": ndf.example_6_1, "6.2": ndf.example_6_2}


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
    fields = fields or list(rows[0])
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def fmt(value, spec=".4e"):
    return "-" if value is None else format(value, spec)


def say(message):
    print(message, flush=True)


os.environ.setdefault("PYTHONUNBUFFERED", "1")


def save_figure(fig, path, dpi=120):
    """Lay out, write and close a matplotlib figure."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
