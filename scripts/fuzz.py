"""Fuzz ngdgfric with bad input through the Python API and the command line; write results/fuzz.md.

The cases are data: ``tests/data/fuzz/<family>.toml`` (format: ``tests/data/fuzz/README.md``), the same
files that ``tests/test_fuzz.py`` runs.  This script runs every case in a fresh process of its own (cwd: a
temporary folder holding the case's files), with a timeout and a cap on its address space:

* API cases run ``python -c SNIPPET``: the snippet (``PREAMBLE``) imports ngdgfric, runs the case's
  ``setup`` (outside the check) and makes one call.  A ValueError (or FileNotFoundError for a missing file)
  is the contract: it prints ``NAMED-ERROR <Type>: <message>`` and exits 3; any other exception
  propagates (traceback, exit 1: "wrong exception type"); a call that returns prints ``SILENT``
  ("silent answer").
* CLI cases run ``python -m ngdgfric ...``.  Bad input must end with exit code 2 and exactly one
  stderr line ``ngdgfric: error: ...``, no traceback.

A negative return code is a "signal", a case killed at the timeout (its whole process group) a
"hang".  A case may name words (``expect``) one of which the error message must contain (case
insensitive, as a whole word), else "unnamed error"; output-safety cases also check that the
error came before any computing, or that an earlier result was left unchanged.  The cases marked
"issue case" are the ones listed in the issue; the rest are systematic (every datum x every bad value,
via the API and via a TOML problem file on the command line, bad command-line numbers, bad files,
expressions, meshes, references).

The report starts with counts per verdict and lists the cases that are not a "named error"; the
exit code is 0 iff every case run is a "named error".  Regenerate results/fuzz.md with

    python scripts/fuzz.py [--workers 2] [--timeout 30] [--only SUBSTRING] [--family NAME] [--quick] [--out results]

``--quick`` runs only the cases of the problem-file schema (``tests/data/fuzz/schema.toml``: regions,
holes, arcs, symmetry sides, data per region and per side, u_D and the expression functions step, min,
max, if).
"""

import argparse
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import tomllib

from ngdgfric.files import write_text

REPO = Path(__file__).resolve().parent.parent
RESULTS = REPO / "results"
DATA = REPO / "tests" / "data" / "fuzz"
FAMILIES = ("data", "functions", "expressions", "geometry", "mesh", "reference", "files", "arguments", "output",
            "schema", "surface", "pairs")

NAMED = "named error"
UNNAMED = "unnamed error"
SIGNAL = "signal"
HANG = "hang"
SILENT = "silent answer"
TRACEBACK = "traceback"
WRONG_TYPE = "wrong exception type"
EXIT_1 = "solver failure reported as exit 1 (should be 2 for bad input)"
LATE = "error only after computing"
CHANGED = "earlier result changed"
OTHER = "other"
VERDICTS = (SIGNAL, HANG, SILENT, TRACEBACK, WRONG_TYPE, UNNAMED, EXIT_1, LATE, CHANGED, OTHER, NAMED)

# files of a case: relative path -> str or bytes (contents), DIR, FIFO or ("symlink", target)
DIR, FIFO = ("dir",), ("fifo",)


@dataclass
class Case:
    """One bad input.  API: ``snippet`` (the checked call) after ``setup``, expected to raise ``error``;
    CLI: ``argv`` of ``python -m ngdgfric`` after the untimed ``commands`` (argv lists, run the same way),
    expected to exit 2."""

    id: str
    interface: str  # "api" or "cli"
    description: str
    snippet: str = ""
    setup: str = ""
    argv: tuple = ()
    files: dict = field(default_factory=dict)
    commands: tuple = ()
    expect: tuple = ()  # the message must contain one of these words (case insensitive)
    issue: bool = False
    check: str = ""  # "quiet": no output before the error; "unchanged": files under out/ unchanged
    error: str = ""  # API: the exception type the call raises (ValueError, FileNotFoundError)
    family: str = ""  # the data file: tests/data/fuzz/<family>.toml
    isolated: str = ""  # why tests/test_fuzz.py runs the case only in a process of its own


# ----------------------------------------------------------------------------------------- cases

PREAMBLE = """\
import dataclasses, math, os, sys
import numpy as np
import ngsolve as ngs
import ngdgfric as ndf
nan, inf = float("nan"), float("inf")
x, y = ngs.x, ngs.y
p = ndf.example_6_1()
def solve(q, h=0.25):
    return ndf.solve(q, ndf.uniform_mesh(q, h))
"""

# Example 6.1 as a problem file (ngdgfric/data/example_6_1.toml without comments); raw TOML values
BASE_TOML = {
    "material": {"E": "2000.0", "nu": "0.4"},
    "geometry": {"vertices": "[[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]",
                 "labels": '["contact", "dirichlet", "traction", "traction"]'},
    "loads": {"f": "[0.0, 0.0]", "g": '["200*(5 - y)", -190.0]'},
    "contact": {"c_n": "1.0", "m_n": "1.0", "g_a": "0.05", "c_tau": "450.0"},
}

# contents too long or too binary to spell out in the data: {"factory": name, "n": n}
FACTORIES = {
    "nested_parentheses": lambda n: "(" * n + "x" + ")" * n,
    "sum_of_x": lambda n: "+".join(["x"] * n),
    "byte_range": lambda n: bytes(range(256)) * n,
}


def toml(changes=None, top="", name="fuzz case"):
    """The problem file of Example 6.1 with ``changes`` {"section.key": raw TOML value, or False to delete}."""
    sections = {section: dict(values) for section, values in BASE_TOML.items()}
    for dotted, raw in (changes or {}).items():
        section, key = dotted.split(".")
        if raw is False:
            sections[section].pop(key, None)
        else:
            sections.setdefault(section, {})[key] = raw
    lines = [f'name = "{name}"'] + ([top] if top else [])
    for section, values in sections.items():
        lines += ["", f"[{section}]"] + [f"{key} = {value}" for key, value in values.items()]
    return "\n".join(lines) + "\n"


def _factory(spec):
    return FACTORIES[spec["factory"]](spec["n"])


def file_contents(spec):
    """A file of a case from its data (tests/data/fuzz/README.md): str, bytes, DIR, FIFO or ("symlink", target)."""
    if isinstance(spec, str):
        return spec
    if "factory" in spec:
        return _factory(spec)
    if "kind" in spec:
        return {"dir": DIR, "fifo": FIFO}[spec["kind"]]
    if "symlink" in spec:
        return ("symlink", spec["symlink"])
    changes = {key: json.dumps(_factory(raw)) if isinstance(raw, dict) else raw
               for key, raw in spec.get("changes", {}).items()}
    text = toml(changes, spec.get("top", ""), spec.get("name", "fuzz case"))
    for old, new in spec.get("replace", ()):
        text = text.replace(old, new)
    return text.encode(spec["encoding"]) if "encoding" in spec else text


def output_file(argv, suffix):
    """The file with ``suffix`` that ``ngdgfric ARGV --out out`` writes for Example 6.1 (the command line's own
    naming, so that a blocked output file follows a change of the defaults)."""
    from ngdgfric import cli

    args = cli.build_parser().parse_args([*argv, "--out", "out"])
    return next(str(path) for path in cli.outputs(args, "6_1") if path.suffix == suffix)


def _outputs(text, argv):
    """``text`` with {output:.SUFFIX} / {output_name:.SUFFIX} replaced by that output file of ``argv``."""
    return re.sub(r"\{output(_name)?:(\.\w+)\}",
                  lambda m: Path(output_file(argv, m[2])).name if m[1] else output_file(argv, m[2]), text)


def case_from_data(entry, family):
    """A Case from one [[case]] table of tests/data/fuzz/<family>.toml."""
    interface = "api" if "call" in entry else "cli"
    argv = tuple(entry.get("argv", ()))
    return Case(entry["id"], interface, _outputs(entry["description"], argv), snippet=entry.get("call", ""),
                setup=entry.get("setup", ""), argv=argv,
                files={_outputs(name, argv): file_contents(spec) for name, spec in entry.get("files", {}).items()},
                commands=tuple(tuple(c) for c in entry.get("commands", ())),
                expect=tuple(_outputs(word, argv) for word in entry.get("expect", ())),
                issue=entry.get("issue", False), check=entry.get("check", ""), error=entry.get("error", ""),
                family=family, isolated=entry.get("isolated", ""))


def load_cases(folder=DATA, families=FAMILIES):
    """Every case of the data files, family by family in the order of ``families``."""
    return [case_from_data(entry, family) for family in families
            for entry in tomllib.loads((Path(folder) / f"{family}.toml").read_text(encoding="utf-8"))["case"]]


CASES = load_cases()
QUICK = "-schema-"  # --quick: the cases of schema.toml

# --------------------------------------------------------------------------------------- running

# caps the address space, then becomes the real command: python -c LIMIT BYTES ARGS... runs python ARGS...
LIMIT = ("import os, resource, sys\n"
         "n = int(sys.argv[1]); soft, hard = resource.getrlimit(resource.RLIMIT_AS)\n"
         "n = n if hard == resource.RLIM_INFINITY else min(n, hard)\n"
         "resource.setrlimit(resource.RLIMIT_AS, (n, hard))\n"
         "os.execv(sys.executable, [sys.executable, *sys.argv[2:]])")


def environment():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    env.update(PYTHONIOENCODING="utf-8:backslashreplace", MPLBACKEND="Agg", OMP_NUM_THREADS="1",
               MKL_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", NGDGFRIC_BLAS_THREADS="1")
    return env


ENV = environment()


@dataclass
class Outcome:
    returncode: int | None  # None: killed at the timeout
    stdout: str
    stderr: str
    seconds: float


def run_process(args, cwd, timeout, memory_bytes=0):
    """Run ``python args...`` in its own session; at the timeout kill its whole process group.

    (subprocess.run kills only the child at a timeout; Popen + os.killpg kill what it started too.)
    """
    argv = [sys.executable, "-c", LIMIT, str(int(memory_bytes)), *args] if memory_bytes else [sys.executable, *args]
    start = time.perf_counter()
    process = subprocess.Popen(argv, cwd=cwd, env=ENV, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = process.communicate(timeout=timeout)
        code = process.returncode
    except subprocess.TimeoutExpired:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = process.communicate()
        code = None
    seconds = time.perf_counter() - start
    return Outcome(code, out.decode("utf-8", "backslashreplace"), err.decode("utf-8", "backslashreplace"), seconds)


def api_program(case):
    """The Python program of an API case (see the module docstring)."""
    return "\n".join([
        "import sys, traceback",
        "try:",
        textwrap.indent(PREAMBLE + case.setup, "    "),
        "except BaseException:",
        "    traceback.print_exc()",
        "    print('SETUP-FAILED')",
        "    sys.exit(4)",
        "try:",
        textwrap.indent(case.snippet, "    "),
        "except (ValueError, FileNotFoundError) as exc:",
        "    print('NAMED-ERROR ' + type(exc).__name__ + ': ' + ' '.join(str(exc).split()))",
        "    sys.exit(3)",
        "print('SILENT')",
        "",
    ])


def case_args(case):
    """Arguments of python for the case."""
    return ["-c", api_program(case)] if case.interface == "api" else ["-m", "ngdgfric", *case.argv]


def make_files(folder, files):
    for name, contents in files.items():
        path = Path(folder) / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if contents == DIR:
            path.mkdir()
        elif contents == FIFO:
            os.mkfifo(path)
        elif isinstance(contents, tuple) and contents[0] == "symlink":
            os.symlink(contents[1], path)
        elif isinstance(contents, bytes):
            path.write_bytes(contents)
        else:
            path.write_text(contents)


def snapshot(folder):
    """{relative path: bytes} of the files under folder/out."""
    root = Path(folder) / "out"
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()} \
        if root.is_dir() else {}


def names_datum(message, expect):
    """True if the message contains one of the expected words (case insensitive, not inside a longer word)."""
    if not expect:
        return True
    for word in expect:
        pattern = re.escape(word)
        if re.match(r"\w", word[0]):
            pattern = r"(?<![\w])" + pattern
        if re.match(r"\w", word[-1]):
            pattern += r"(?![\w])"
        if re.search(pattern, message, re.IGNORECASE):
            return True
    return False


def _first(text):
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[0] if lines else ""


def _last(text):
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else ""


def _marker(stdout, prefix):
    found = [line for line in stdout.splitlines() if line.startswith(prefix)]
    return found[-1][len(prefix):].strip() if found else None


def signal_name(code):
    try:
        return signal.Signals(-code).name
    except ValueError:
        return f"signal {-code}"


def classify(case, outcome, timeout):
    """(verdict, what happened) of a finished case."""
    code, out, err = outcome.returncode, outcome.stdout, outcome.stderr
    if code is None:
        return HANG, f"no exit within {timeout:g} s: process group killed; last output: {_last(err) or _last(out)!r}"
    if code < 0:
        return SIGNAL, f"{signal_name(code)} (return code {code}); stderr: {_first(err)!r}"
    if case.interface == "api":
        named = _marker(out, "NAMED-ERROR ")
        if code == 3 and named is not None:
            kind, _, message = named.partition(": ")
            verdict = NAMED if message.strip() and names_datum(message, case.expect) else UNNAMED
            return verdict, f"exit 3: {named}"
        if code == 0 and _marker(out, "SILENT") is not None:
            return SILENT, "exit 0: returned normally"
        if code == 4 and _marker(out, "SETUP-FAILED") is not None:
            return OTHER, f"exit 4: setup of the case failed: {_last(err)}"
        if code == 1 and "Traceback" in err:
            return WRONG_TYPE, f"exit 1: {_last(err)}"
        return OTHER, f"exit {code}: {_last(err) or _last(out)}"
    if code == 0:
        return SILENT, f"exit 0: {_last(out)}"
    if "Traceback" in err:
        return TRACEBACK, f"exit {code}: {_last(err)}"
    lines = [line for line in err.splitlines() if line.strip()]
    errors = [line.strip() for line in lines if line.startswith("ngdgfric: error: ")]
    shown = errors[-1] if errors else _first(err)
    if code == 2:
        if len(lines) == 1 and lines[0].startswith("ngdgfric: error: "):
            message = lines[0][len("ngdgfric: error: "):]
            verdict = NAMED if message.strip() and names_datum(message, case.expect) else UNNAMED
            return verdict, f"exit 2: {lines[0]}"
        return OTHER, f"exit 2 with {len(lines)} stderr lines: {shown!r}"
    if code == 1:
        return EXIT_1, f"exit 1: {shown}"
    return OTHER, f"exit {code}: {shown}" + (f" ({len(lines)} stderr lines)" if len(lines) > 1 else "")


@dataclass
class Result:
    case: Case
    verdict: str
    happened: str
    seconds: float


def run_case(case, timeout=30.0, memory_gb=6.0):
    """Run one case in a fresh temporary folder; its Result."""
    memory = memory_gb * 2**30
    with tempfile.TemporaryDirectory(prefix=f"fuzz-{case.id[:40]}-", ignore_cleanup_errors=True) as folder:
        make_files(folder, case.files)
        for command in case.commands:  # untimed setup of a CLI case
            done = run_process(["-m", "ngdgfric", *command], folder, max(timeout, 120), memory)
            if done.returncode != 0:
                return Result(case, OTHER, f"setup command {' '.join(command)} failed: exit {done.returncode}, "
                                           f"{_last(done.stderr)!r}", 0.0)
        before = snapshot(folder)
        outcome = run_process(case_args(case), folder, timeout, memory)
        verdict, happened = classify(case, outcome, timeout)
        if verdict == NAMED and case.check == "quiet" and outcome.stdout.strip():
            verdict = LATE
            happened += f" (after printing {_first(outcome.stdout)!r})"
        if case.check == "unchanged":
            after = snapshot(folder)
            changed = sorted(name for name in before if after.get(name) != before[name])
            if changed:
                happened += f"; changed or removed: {', '.join(changed)}"
                if verdict == NAMED:
                    verdict = CHANGED
            elif not before:
                happened += "; the setup run wrote nothing to out/"
    return Result(case, verdict, f"{happened}; {outcome.seconds:.1f} s", outcome.seconds)


# -------------------------------------------------------------------------------------- reporting

MARKUP = re.compile(r"([\\`*_$<|\[\]])")
"""The characters that would start Markdown (MyST) markup in a table cell's plain text: escaped."""
QUOTED = re.compile(r"('[^']*')")
"""A quoted value in a case's description (``g_a = 'if(*x)'``): shown as code, as it is typed."""


def _cell(text, limit=300):
    """A case's description as a table cell: its quoted values as code, the rest plain text with markup escaped."""
    text = " ".join(str(text).split())
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return "".join(_code(piece) if QUOTED.fullmatch(piece) else MARKUP.sub(r"\\\1", piece)
                   for piece in QUOTED.split(text) if piece)


def _code(text, limit=160):
    text = " ".join(text.split())
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return "`" + text.replace("`", "'").replace("|", "\\|") + "`"


def shown_input(case):
    if case.interface == "cli":
        command = "ngdgfric " + " ".join(shlex.quote(a) for a in case.argv)
        return f"{_cell(case.description)}<br>{_code(command)}"
    return f"{_cell(case.description)}<br>{_code(case.snippet.replace(chr(10), '; '))}"


def report(results, args, seconds):
    """The Markdown of results/fuzz.md."""
    counts = {verdict: sum(r.verdict == verdict for r in results) for verdict in VERDICTS}
    api_count = sum(r.case.interface == "api" for r in results)
    lines = [
        "# Fuzzing ngdgfric with bad input",
        "",
        "Every bad input of the fuzz data given to the API and to the command line, each in its own process: a "
        "case passes when it ends in an error that names the bad datum; a signal, a hang, a silent answer or a "
        "traceback is a failure.",
        "",
        f"{len(results)} cases ({api_count} API, {len(results) - api_count} CLI; "
        f"{sum(r.case.issue for r in results)} listed in the request for fuzzing), each in its own process: "
        f"timeout {args.timeout:g} s, "
        + (f"address space capped at {args.memory:g} GB" if args.memory else "address space not capped")
        + f", {args.workers} in parallel; {seconds:.0f} s in all.",
    ]
    if args.quick:
        lines.append(f"Quick run: only the cases of the problem-file schema (ids containing {QUICK!r}).")
    if args.only:
        lines.append(f"Only the cases whose id contains {' or '.join(map(repr, args.only))}.")
    if args.family:
        lines.append(f"Only the famil{'ies' if len(args.family) > 1 else 'y'} {', '.join(args.family)}.")
    lines += [
        "",
        "| verdict | cases |",
        "|---|---|",
        f"| signals | {counts[SIGNAL]} |",
        f"| hangs | {counts[HANG]} |",
        f"| silent answers | {counts[SILENT]} |",
        f"| CLI tracebacks | {counts[TRACEBACK]} |",
        f"| API: wrong exception type | {counts[WRONG_TYPE]} |",
        f"| unnamed errors (message does not name the datum) | {counts[UNNAMED]} |",
        f"| CLI: {EXIT_1} | {counts[EXIT_1]} |",
        f"| CLI: {LATE} | {counts[LATE]} |",
        f"| CLI: {CHANGED} | {counts[CHANGED]} |",
        f"| other | {counts[OTHER]} |",
        f"| **named errors** | **{counts[NAMED]}** |",
        "",
    ]
    failing = [r.case.id for r in results if r.verdict != NAMED]
    lines.append(f"Not a named error ({len(failing)}): " + (", ".join(f"`{i}`" for i in failing) or "none") + ".")
    lines += [
        "",
        "Verdicts.  API (`python -c SNIPPET`): *named error*: ValueError (FileNotFoundError for a missing file) "
        "whose message is non-empty and contains one of the expected words; *unnamed error*: such an error "
        "without them; *wrong exception type*: any other exception (traceback, exit 1); *silent answer*: the "
        "call returned.  CLI (`python -m ngdgfric`): *named error*: exit 2 and exactly one stderr line "
        "`ngdgfric: error: ...` naming the datum; *silent answer*: exit 0; *traceback*: `Traceback` on stderr; "
        f"*{EXIT_1}*; *{LATE}*: output printed before the error (the output folder must be checked first); "
        f"*{CHANGED}*: a rerun modified an earlier result.  Both: *signal*: killed by a signal; *hang*: "
        "no exit within the timeout (process group killed).",
        "",
        "| case | interface | listed in the request | input | what happened | verdict |",
        "|---|---|---|---|---|---|",
    ]
    for r in results:
        verdict = r.verdict if r.verdict == NAMED else f"**{r.verdict}**"
        lines.append(f"| `{r.case.id}` | {r.case.interface} | {'yes' if r.case.issue else ''} | {shown_input(r.case)} "
                     f"| {_code(r.happened, 300)} | {verdict} |")  # what the program printed, as printed
    lines += ["", "Regenerate: `python scripts/fuzz.py` (its docstring says what is checked; the cases: "
              "`tests/data/fuzz/`, one file per family)."]
    return "\n".join(lines) + "\n"


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=RESULTS, help="folder of fuzz.md (default: results/)")
    parser.add_argument("--workers", type=int, default=2, help="cases run in parallel (default: 2)")
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds before a case is a hang (default: 30)")
    parser.add_argument("--only", action="append", metavar="SUBSTRING",
                        help="run only the cases whose id contains SUBSTRING (repeatable: any of them)")
    parser.add_argument("--family", action="append", choices=FAMILIES,
                        help="run only the cases of this family (tests/data/fuzz/FAMILY.toml; repeatable)")
    parser.add_argument("--quick", action="store_true",
                        help=f"run only the cases of the problem-file schema (ids containing {QUICK!r}: regions, "
                             "holes, arcs, symmetry, data per part, u_D, the expression functions)")
    parser.add_argument("--memory", type=float, default=6.0,
                        help="cap of each case's address space in GB, 0 for none (default: 6)")
    args = parser.parse_args(argv)
    if args.workers < 1 or not args.timeout > 0 or args.memory < 0:
        parser.error("--workers must be >= 1, --timeout > 0 and --memory >= 0")
    return args


def selected(args):
    """The cases that ``args`` (--quick, --only) select, in the order of CASES."""
    return [case for case in CASES if (not args.quick or QUICK in case.id)
            and (not args.only or any(part in case.id for part in args.only))
            and (not args.family or case.family in args.family)]


def main(argv=None):
    args = parse(argv)
    cases = selected(args)
    if not cases:
        print(f"fuzz: no case id contains {' or '.join(map(repr, args.only or [QUICK]))}", file=sys.stderr)
        return 2
    print(f"{len(cases)} cases, {args.workers} workers, timeout {args.timeout:g} s", flush=True)
    start = time.perf_counter()
    results = {}
    with ThreadPoolExecutor(max_workers=args.workers) as pool:
        futures = {pool.submit(run_case, case, args.timeout, args.memory): case for case in cases}
        for done, future in enumerate(as_completed(futures), 1):
            result = future.result()
            results[result.case.id] = result
            print(f"[{done:3d}/{len(cases)}] {result.case.id}: {result.verdict} ({result.seconds:.1f} s)", flush=True)
    seconds = time.perf_counter() - start
    ordered = [results[c.id] for c in cases]
    path = args.out / "fuzz.md"
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text(path, report(ordered, args, seconds))
    failing = sum(r.verdict != NAMED for r in ordered)
    print(f"{len(ordered) - failing} of {len(ordered)} named errors in {seconds:.0f} s; wrote {path}", flush=True)
    return 0 if failing == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
