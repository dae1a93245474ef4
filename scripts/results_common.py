"""results_common.py: what the figure scripts of scripts/ (failure_modes.py, noise_figure.py,
noise_kinds.py, transfer_figure.py) share.

  finding roger      find_roger: --roger, else $ROGER, else the source tree's build/engine/roger,
                     else roger on PATH; run_roger: a roger command whose failure is one line
  reading a folder   read_report: a results folder's report.json, or a one-line error;
                     total_rows: its evaluations' Total rows
  partial folders    without_result: the trials failed or pending per evaluation and per training
                     run (summary.csv, report.json); without, marked, partial_of and
                     partial_warning: how the scripts say them
  writing            write_atomically: a file whole or not at all

A script imports it from its own folder (it puts that folder first on sys.path), so a copy of a
script needs this file beside it. Messages that name a script take its name from the caller
(`script`). Standard library only.
"""
import csv
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def find_roger(script, given=None):
    """The roger program to run: `given` (--roger), else $ROGER, else the engine built beside these
    scripts (the source tree's build/engine/roger), else roger on PATH. Exits with one line, naming
    `script` and where it looked, when none is there: a FileNotFoundError traceback from
    subprocess said nothing of where to look."""
    for exe, origin in ((given, "--roger"), (os.environ.get("ROGER"), "$ROGER")):
        if exe:  # a path, or a name looked up on PATH as subprocess would
            if not shutil.which(exe):
                sys.exit(f"{script}: {origin} {exe}: no such program")
            return shutil.which(exe)
    built = os.path.normpath(os.path.join(HERE, os.pardir, "build", "engine", "roger"))
    if os.access(built, os.X_OK):
        return built
    on_path = shutil.which("roger")
    if on_path:
        return on_path
    sys.exit(f"{script}: no roger program: give --roger PATH or set ROGER, or build {built}, or put "
             "roger on PATH")


def run_roger(script, cmd):
    """The stdout of a roger command (cmd: the program, then its arguments). A failing command stops
    `script` with roger's own last line on stderr, not a CalledProcessError traceback."""
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        said = (r.stderr.strip().splitlines() or ["(nothing on stderr)"])[-1]
        sys.exit(f"{script}: `{' '.join(cmd)}` exited {r.returncode}: {said}")
    return r.stdout


def require_results_folder(script, results):
    """A one-line error when `results` is no folder (found by a probe: a misspelt folder was told to
    run `roger report` on it first, which then found no results folder)."""
    if not os.path.isdir(results):
        sys.exit(f"{script}: {results} " + ("is not a folder" if os.path.exists(results) else "does not exist"))


def require_svg_path(script, out):
    """A one-line usage error (status 2) for an OUT.svg the figure cannot be written to: another
    extension (found by a probe: out.png received SVG text) or a folder that does not exist (a
    traceback, after the evaluations had run). Asked before any work."""
    if not out.lower().endswith(".svg"):
        print(f"{script}: {out}: the figure is an SVG picture; name it OUT.svg", file=sys.stderr)
        sys.exit(2)
    folder = os.path.dirname(out) or "."
    if not os.path.isdir(folder):
        print(f"{script}: {out}: the folder {folder} does not exist", file=sys.stderr)
        sys.exit(2)


def _whole(text, low, high, expected):
    """An argparse type's work: `text` as a whole number in [low, high), else an ArgumentTypeError
    saying `expected`."""
    import argparse
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if not low <= n < high:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {n}")
    return n


def positive_int(text):
    """An argparse type: a whole number of at least 1 (found by a probe: --episodes -5 printed a
    table of -5 episodes per shape)."""
    return _whole(text, 1, float("inf"), "a whole number of at least 1")


def seed_int(text):
    """An argparse type: a world seed, a whole number from 0 to 2^64 - 1."""
    return _whole(text, 0, 2 ** 64, "a seed from 0 to 2^64 - 1")


def percent(k, n):
    """k of n as a percentage to one decimal, rounded as roger's tables round it (k / n first: 9635 of
    10000 is 96.4% there, where 100 * k / n prints 96.3%)."""
    return f"{100.0 * (k / n):.1f}"


def read_report(results):
    """RESULTS/report.json, parsed; a missing file, or one that is not JSON, is a one-line error."""
    path = os.path.join(results, "report.json")
    if not os.path.exists(path):
        sys.exit(f"{path} does not exist: run `roger report {results}` first")
    try:
        with open(path) as f:
            return json.load(f)
    except ValueError as e:  # cut short or edited: say which file, not a traceback
        sys.exit(f"{path}: not JSON ({e}): run `roger report {results}` again")


def total_rows(report):
    """Per evaluation: the Total row of its table in report.json (the parsed file)."""
    totals = {}
    for t in report["tables"]:
        rows = [r for r in t.get("rows", []) if r.get("object") == "Total"]
        if t.get("evaluation") and rows:
            totals[t["evaluation"]] = rows[0]
    return totals


def without_result(results, report=None):
    """The trials without a result: {"eval": {evaluation: {"failed": n, "pending": m}}, "train":
    {run/context: ...}}, only those with some. From RESULTS/summary.csv's status column (a corrupt
    record counts as failed), or an evaluation's Total row in report (the parsed report.json, if
    given) where it says more: the report's evaluation rows carry "failed" and "pending" only from
    some version on (.get)."""
    missing = {"eval": {}, "train": {}}
    summary = os.path.join(results, "summary.csv")
    if os.path.exists(summary):
        with open(summary, newline="") as f:
            for row in csv.DictReader(f):
                if row["status"] != "ok":
                    kind, key = (("eval", row["evaluation"]) if row["kind"] == "eval"
                                 else ("train", row["run"] + "/" + row["context"]))
                    m = missing[kind].setdefault(key, {"failed": 0, "pending": 0})
                    m["pending" if row["status"] == "pending" else "failed"] += 1
    for evaluation, row in (total_rows(report) if report is not None else {}).items():
        m = missing["eval"].setdefault(evaluation, {"failed": 0, "pending": 0})
        for key in ("failed", "pending"):
            m[key] = max(m[key], row.get(key, 0))
    return {kind: {k: m for k, m in d.items() if m["failed"] or m["pending"]} for kind, d in missing.items()}


def without(m):
    """'1 failed, 2 pending': the trials {"failed", "pending"} counts, or '' for none."""
    m = m or {}
    return ", ".join(f"{m[k]} {k}" for k in ("failed", "pending") if m.get(k, 0))


def marked(text, m):
    """A table cell or a point with the trials it leaves out: '99.0% [98.2, 99.6] (1 failed)'."""
    return f"{text} ({without(m)})" if without(m) else text


def partial_of(report):
    """'of 14 trials, 1 failed' when report.json (parsed) says the folder is partial (some trials
    failed or have no result yet), else ''."""
    p = report.get("partial") or {}
    return f"of {p.get('trials', '?')} trials, {without(p)}" if without(p) else ""


def partial_warning(script, results, report, lines, scope, pooled):
    """The stderr warning of a folder with trials without a result, or '' when it has none.
    lines: one per part of what `script` shows that leaves trials out ('  evaluation III_x8: 1
    failed'); scope: what it shows, said when no line is ('the evaluations III_x* drawn here');
    pooled: what pools the other trials ('the rates below pool only the trials with results, ...')."""
    partial = partial_of(report)
    if not partial and not lines:
        return ""
    head = f"{results}: partial results, {partial}" if partial else f"{results}: some trials have no result"
    if not lines:
        return f"{script}: {head}; none of them in {scope}"
    return f"{script}: {head}; {pooled}:\n" + "\n".join(lines)


def write_atomically(path, text):
    """Writes the file whole or not at all (a temporary beside it, then a rename): a results folder
    never holds a half-written file, nor the temporary of a failed write."""
    try:
        with open(path + ".tmp", "w") as f:
            f.write(text)
        os.replace(path + ".tmp", path)
    except BaseException:
        if os.path.exists(path + ".tmp"):
            os.remove(path + ".tmp")
        raise
