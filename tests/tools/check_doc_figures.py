#!/usr/bin/env python3
"""check_doc_figures.py [FILE ...]: every percentage in the results pages says where it comes from
(CTest doc_figures; docs/testing.md).

Each section of a page (the text under its smallest heading) that quotes a percentage must show,
within that section, the command that gives it (a code span or block running `roger`, `python3`,
a script of scripts/ or a test of tests/), a test that pins it (a path under tests/), or the commit
it was measured at (`[measured at `abc1234`]`, or "at abc1234" naming a commit), for figures that
cannot be re-run at HEAD. Every commit named so must exist in the repository's history (a git
checkout; elsewhere the test skips, and fails under CI=true). Default files: docs/results.md and
docs/control.md. Exit 0: every section holds; 1: some do not (each named with its line); 77: no git
history to check the commits against.
"""
import os
import re
import subprocess
import sys

PERCENT = re.compile(r"[0-9]%")
HEADING = re.compile(r"^#{1,6} ")
COMMAND = re.compile(r"`[^`]*(\broger |python3 |PYTHONPATH=|bash |scripts/|tests/)[^`]*`|^```(sh|lua)?\s*$", re.M)
TEST = re.compile(r"\btests/[A-Za-z0-9_/.-]+\.(cpp|py|sh|cmake)\b")
MARK = re.compile(r"measured at `([0-9a-f]{7,40})`|\bat `?([0-9a-f]{7,40})`?\b")


def sections(text):
    """(first line, heading, body) of each section: the text under its smallest heading."""
    out, heading, start, body, fence = [], "(top of the page)", 1, [], False
    for number, line in enumerate(text.split("\n"), 1):
        if line.startswith("```"):
            fence = not fence
        if not fence and HEADING.match(line):
            out.append((start, heading, "\n".join(body)))
            heading, start, body = line.strip(), number, []
        else:
            body.append(line)
    out.append((start, heading, "\n".join(body)))
    return out


def commits(body):
    return {a or b for a, b in MARK.findall(body)}


def commit_exists(sha):
    return subprocess.run(["git", "cat-file", "-e", sha + "^{commit}"], capture_output=True).returncode == 0


def main():
    files = sys.argv[1:] or ["docs/results.md", "docs/control.md"]
    problems, named = [], set()
    for path in files:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for line, heading, body in sections(text):
            named |= {(path, line, sha) for sha in commits(body)}
            if not PERCENT.search(body):
                continue
            if COMMAND.search(body) or TEST.search(body) or commits(body):
                continue
            problems.append(f"{path}:{line}: {heading}: quotes a percentage with no command, test or "
                            "measured-at commit in its section")
    in_git = subprocess.run(["git", "rev-parse", "--git-dir"], capture_output=True).returncode == 0
    if in_git:
        for path, line, sha in sorted(named):
            if not commit_exists(sha):
                problems.append(f"{path}:{line}: names commit {sha}, which this repository does not hold")
    for p in problems:
        print(p)
    if problems:
        print(f"FAILED: {len(problems)} section(s)")
        return 1
    if not in_git:
        why = "not a git checkout: the commits the pages name cannot be checked"
        if os.environ.get("CI") == "true":
            print(f"FAILED (would skip, but CI=true): {why}")
            return 1
        print(f"SKIPPED: {why}")
        return 77
    print(f"every percentage of {', '.join(files)} has its command, test or commit in its section; "
          f"{len({s for _, _, s in named})} commits named, all in the history")
    return 0


if __name__ == "__main__":
    sys.exit(main())
