#!/usr/bin/env python3
"""teachers_digest.py RESULTS: the figures docs/results.md ("Teachers") quotes beside its tables.

Reads a results folder of `roger run scripts/teachers.lua`, finished or still running: its
manifest.json's trials, each finished one's trials/ID/result.json and, for ALP-GMM and random, its
episodes.jsonl (summary.csv is written only at the end). Prints, for the trials whose result.json
has a "teacher" record, grouped by run/context:

  sequence  in how many trials it never left its first step, in how many it promoted and between
            which training episodes (its first promotion: teacher.state.moves), and at how many
            episodes the others reached the threshold (episodes_to_threshold);
  LCAS      the most common lift schedule (teacher.state.lifts' episodes) and in how many trials,
            then the others;
  ALP-GMM   the mean number of obstacles of its training tasks (episodes.jsonl's task.obstacles,
            pooled over the row's episodes) per context, against the axis's uniform mean and the
            random teacher's draws in the same context;
  cost      per teacher kind, teacher_wall_s over train_wall_s (the training episodes' wall time,
            the teacher's included, without the checkpoints' evaluations): median and largest;
  skipped   each trial's training tasks whose world could not be placed (skipped_tasks).

A move or lift at an episode count the trial never reached (decided on its last episode) set no
episode: it is left out and counted apart. A partial folder (trials failed, or pending: not run
yet or running) is digested from the trials with results, said on stderr with the counts pooled.
A folder that is not a results folder, or a record that is not JSON or lacks a field read here, is
a one-line error. Standard library only.
"""
import json
import os
import re
import statistics
import sys
from collections import Counter

FIELDS = ("run", "context", "teacher_wall_s", "train_wall_s", "train_episodes", "reached", "episodes_to_threshold",
          "threshold")
NAMES = {"alp_gmm": "ALP-GMM", "plr": "PLR", "sequence": "sequence", "lcas": "LCAS", "random": "random"}


class Unreadable(Exception):
    pass


def read_json(path, what=None):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise Unreadable(f"{what} ({path}: {e.strerror or e})" if what else f"{path}: {e}")


def load(folder):
    """The trials with a teacher (id, row run/context, result.json), and how many of manifest.json's
    trials are done, failed (error.json) or pending (neither yet: not run, or running)."""
    manifest = read_json(os.path.join(folder, "manifest.json"), f"{folder} is not a results folder of roger run")
    if not isinstance(manifest, dict) or not isinstance(manifest.get("trials"), list):
        raise Unreadable(f"{folder}/manifest.json is not a manifest of roger run (no list of trials)")
    status, trials = Counter(), []
    for id in manifest["trials"]:
        d = os.path.join(folder, "trials", id)
        if not os.path.exists(os.path.join(d, "result.json")):
            status["failed" if os.path.exists(os.path.join(d, "error.json")) else "pending"] += 1
            continue
        status["done"] += 1
        res = read_json(os.path.join(d, "result.json"))
        if isinstance(res, dict) and res.get("teacher"):
            lacks = [k for k in FIELDS if k not in res] + ([] if "kind" in res["teacher"] else ["teacher.kind"])
            if lacks:
                raise Unreadable(f"{d}/result.json has no {', '.join(lacks)}: not a trial of a stage with a teacher")
            trials.append({"id": id, "row": res["run"] + "/" + res["context"], "context": res["context"],
                           "kind": res["teacher"]["kind"], "result": res, "dir": d})
    return trials, status


def by_row(trials, kind):
    rows = {}
    for t in trials:
        if t["kind"] == kind:
            rows.setdefault(t["row"], []).append(t)
    return rows


def trained(moves, t):
    """The moves (or lifts) that set a training episode, and how many were decided on the last."""
    n = t["result"]["train_episodes"]
    return [m for m in moves if m["episode"] < n], sum(m["episode"] >= n for m in moves)


def episodes_text(values):
    """At episodes 100, 200 and 300; never."""
    if not values:
        return "never"
    head = ", ".join(map(str, values[:-1]))
    return "at episodes " + (f"{head} and {values[-1]}" if head else str(values[0]))


def count(n, word):
    """'1 trial', '2 trials'."""
    return f"{n} {word}" + ("" if n == 1 else "s")


def span(values):
    return f"{min(values)} to {max(values)}" if min(values) != max(values) else str(values[0])


def sequence_lines(trials):
    lines = []
    for row, ts in by_row(trials, "sequence").items():
        first, late, stayed = [], 0, []
        for t in ts:
            moves, last = trained(t["result"]["teacher"]["state"].get("moves", []), t)
            late += last
            ups = [m["episode"] for m in moves if m["to"] > m["from"]]
            if ups:
                first.append(ups[0])
            else:
                stayed.append(t)
        line = f"{row}: never left its first step in {len(stayed)} of {len(ts)} trials; promoted in {len(first)} of {len(ts)}"
        if first:
            line += f", all between episodes {min(first)} and {max(first)}" if len(first) > 1 else f", at episode {first[0]}"
        reached = [t["result"]["episodes_to_threshold"] for t in stayed if t["result"]["reached"]]
        if stayed:
            pct = f"{100 * stayed[0]['result']['threshold']:g}%"
            line += f"; of the {len(stayed)} that did not, {len(reached)} reached {pct} on the first step alone"
            line += f", at {span(reached)} episodes" if reached else ""
        if late:
            line += f" ({count(late, 'move')} decided on a last episode, never trained, left out)"
        lines.append(line)
    return lines or ["no sequence trial has a result"]


def lcas_lines(trials):
    lines = []
    for row, ts in by_row(trials, "lcas").items():
        schedules, late, param = Counter(), 0, ts[0]["result"]["teacher"]["state"].get("param", "?")
        for t in ts:
            lifts, last = trained(t["result"]["teacher"]["state"].get("lifts", []), t)
            late += last
            schedules[tuple(m["episode"] for m in lifts)] += 1
        (top, n), *rest = schedules.most_common()
        line = f"{row}: {param} lifted {episodes_text(top)} in {n} of {len(ts)} trials"
        if rest:
            line += "; otherwise " + "; ".join(f"{episodes_text(s)} ({k})" for s, k in rest)
        if late:
            line += f" ({count(late, 'lift')} decided on a last episode, never trained, left out)"
        lines.append(line)
    return lines or ["no LCAS trial has a result"]


def mean_obstacles(ts):
    """The mean of task.obstacles over the trials' training episodes, and the trials without
    episodes.jsonl."""
    total, n, missing = 0, 0, 0
    for t in ts:
        path = os.path.join(t["dir"], "episodes.jsonl")
        if not os.path.exists(path):
            missing += 1
            continue
        try:
            with open(path) as f:
                for line in f:
                    total += json.loads(line)["task"]["obstacles"]
                    n += 1
        except (OSError, ValueError, KeyError, TypeError) as e:
            raise Unreadable(f"{path}: no task.obstacles in its episodes ({e})")
    return (total / n if n else None), n, missing


def alp_lines(trials):
    lines = []
    alp, rand = by_row(trials, "alp_gmm"), by_row(trials, "random")
    for row, ts in alp.items():
        mean, n, missing = mean_obstacles(ts)
        if mean is None:
            lines.append(f"{row}: no episodes.jsonl")
            continue
        axis = re.search(r"obstacles = roger\.int\((\d+), (\d+)\)", ts[0]["result"].get("tasks", ""))
        line = (f"{row}: drew {mean:.2f} obstacles on average "
                f"({count(n, 'training episode')} of {count(len(ts) - missing, 'trial')})")
        if axis:
            line += f", against uniform's {(int(axis[1]) + int(axis[2])) / 2:.1f}"
        others = [r for r, rt in rand.items() if rt[0]["context"] == ts[0]["context"]]
        for r in others:
            m = mean_obstacles(rand[r])[0]
            line += f"; {r} drew {m:.2f}" if m is not None else ""
        lines.append(line + (f" ({count(missing, 'trial')} without episodes.jsonl)" if missing else ""))
    return lines or ["no ALP-GMM trial has a result"]


def cost_lines(trials):
    lines = []
    for kind, name in NAMES.items():
        shares = [(t["result"]["teacher_wall_s"] / t["result"]["train_wall_s"], t) for t in trials
                  if t["kind"] == kind and t["result"].get("train_wall_s")]
        if not shares:
            continue
        share, t = max(shares, key=lambda s: s[0])
        median = statistics.median(s for s, _ in shares)
        lines.append(f"{name}: median {100 * median:.2f}%, at most {100 * share:.2f}% ({t['id']}: "
                     f"{t['result']['teacher_wall_s']:.3f} s of {t['result']['train_wall_s']:.1f} s), "
                     f"{count(len(shares), 'trial')}")
    return lines or ["no trial with a teacher has a result"]


def skipped_lines(trials):
    lines = []
    for t in trials:
        skips = t["result"].get("skipped_tasks") or []
        if skips:
            where = [f"episode {s['episode']}" + (f" (the object {s['task']['robot_distance']:.3f} m from Roger)"
                                                  if "robot_distance" in s.get("task", {}) else "") for s in skips]
            lines.append(f"{t['id']}: {len(skips)} skipped: " + ", ".join(where))
    n = sum(len(t["result"].get("skipped_tasks") or []) for t in trials)
    if not n:
        return [f"none of the {len(trials)} trials met a training task whose world could not be placed"]
    head = f"{len(lines)} of the {len(trials)} trials met {count(n, 'training task')} whose world could not be placed"
    return [head] + lines


def partial_note(folder, trials, status):
    """The stderr line of a folder with trials without results, or ''."""
    if not status["failed"] and not status["pending"]:
        return ""
    return (f"teachers_digest: {folder} is partial: {status['done']} of {sum(status.values())} trials done, "
            f"{status['failed']} failed, {status['pending']} pending; pooled the {len(trials)} done trials with a teacher")


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        print("usage: teachers_digest.py RESULTS (a results folder of `roger run scripts/teachers.lua`)", file=sys.stderr)
        sys.exit(2)
    folder = sys.argv[1]
    try:
        trials, status = load(folder)
        sections = [("Sequence: its first step and its promotions", sequence_lines(trials)),
                    ("LCAS: when it lifted", lcas_lines(trials)),
                    ("ALP-GMM: obstacles of its training tasks", alp_lines(trials)),
                    ("What a teacher costs: teacher_wall_s over the training wall time (train_wall_s)",
                     cost_lines(trials)),
                    ("Training tasks skipped: the world could not be placed", skipped_lines(trials))]
    except Unreadable as e:
        sys.exit(f"teachers_digest: {e}")
    except (KeyError, TypeError) as e:  # a teacher's state without a field read here
        sys.exit(f"teachers_digest: {folder}: a trial's teacher record has no {e}")
    # A folder of another script's runs digests to nothing: said, not printed as empty sections
    # (found by a probe).
    if not trials and status["done"] > 0:
        sys.exit(f"teachers_digest: {folder}: no trial there has a teacher's record (a results folder of "
                 "`roger run scripts/teachers.lua` is expected)")
    note = partial_note(folder, trials, status)
    if note:
        print(note, file=sys.stderr)
    print("\n\n".join(title + "\n" + "\n".join("- " + line for line in lines) for title, lines in sections))


if __name__ == "__main__":
    main()
