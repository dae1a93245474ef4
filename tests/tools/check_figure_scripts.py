#!/usr/bin/env python3
"""check_figure_scripts.py: the figure scripts of scripts/ on small synthetic results folders, without
the roger program: a training trial that never reached its threshold, a partial folder (failed or
pending trials) and a missing roger give figures, warnings and errors, not tracebacks.

  check_figure_scripts.py --work DIR [--scripts DIR]

Builds, under DIR, results folders shaped as `roger run` writes them (summary.csv and report.json,
or manifest.json and the trials' result.json and episodes.jsonl, with only the fields the scripts
read) and checks:

  transfer_unreached      transfer_figure.py on a folder whose trial missed its threshold: no crash,
                          its mean time marked "≥" (its whole training time stands in)
  transfer_partial        a partial folder (report.json's "partial"; an evaluation trial failed in
                          summary.csv): a warning on stderr naming the evaluation, its cell marked
                          "(1 failed)", a note and a "*" in the figure
  transfer_partial_rows   the same with a pending trial, report.json's evaluation rows carrying
                          "failed" and "pending" (as they do from now on)
  transfer_no_file        a folder the script cannot read (report.json cut short): a one-line error
                          and no figure, nor its temporary, left in the folder
  atomic_writes           every file the scripts write goes through a temporary and a rename
  failure_modes_no_roger  failure_modes.py without --roger, $ROGER, build/engine/roger or roger on
                          PATH: a one-line error (also with $ROGER naming no program)
  noise_figure_no_roger   noise_figure.py likewise: a one-line error, no file written
  noise_figure_partial    noise_figure.py's functions (it needs roger to run) on a partial folder:
                          the warning, the marked points, the figure's note; a count given only by
                          an evaluation row's "pending" field is read too
  noise_kinds_options     noise_kinds.py passes --trials, --only and --jobs to roger run, and its
                          defaults give the command as it always was
  noise_kinds_partial     noise_kinds.py's functions on a partial folder: an evaluation without a
                          result gives "-", not an IndexError; the warning; the marked cells
  noise_kinds_no_roger    noise_kinds.py without roger: a one-line error
  teachers_digest_figures teachers_digest.py on a folder of every teacher kind: sequence's trials
                          that never left their first step and its first promotions, LCAS's most
                          common lift schedule, ALP-GMM's mean obstacles (pooled over episodes),
                          each kind's teacher_wall_s over train_wall_s (median, largest), the
                          skipped tasks; a move or lift decided on the last episode left out
  teachers_digest_partial the same folder with trials failed and pending (no summary.csv yet, as
                          while roger run runs): the counts on stderr, the figures of the rest
  teachers_digest_no_file a folder without manifest.json, a result.json cut short, no argument:
                          a one-line error each
  wrong_folders           a missing folder (transfer_figure.py, noise_figure.py), another script's
                          folder (teachers_digest.py), a trial without its policy (failure_modes.py,
                          before any output): a one-line error each; usage errors exit 2 (an OUT
                          that is no .svg or in no folder, before any work; --episodes below 1)

--scripts: the folder of the scripts to check (default: the source tree's scripts/; give a folder of
older copies to see the checks fail on them). Exit 0 when every check holds, 1 otherwise (each
failing check named with what it saw). Standard library only.
"""
import argparse
import importlib.util
import json
import os
import re
import shutil
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = ("id,kind,run,stage,context,evaluation,shape,trial,seed,status,reached,time_to_threshold_s,"
          "episodes_to_threshold,decisions_to_threshold,train_episodes,train_sim_s,success_rate,reward_mean,"
          "reward_std,wall_s,error")
BODIES = ["long_arms", "short_arms", "wide_base", "small", "big_hands", "coarse_eyes", "wide_eyes", "frozen_eyes"]
SCALES = ["0", "0_5", "1", "2", "4", "8"]


class Failed(Exception):
    pass


def expect(condition, message):
    if not condition:
        raise Failed(message)


# ---- synthetic results folders, in the shape `roger run` writes them ----

def train_row(run, stage, context, trial, reached=True, time_s=100.0, sim_s=1678.74, status="ok"):
    head = f"{run}/{context}/{trial:03d},train,{run},{stage},{context},,,{trial},{trial + 1},{status}"
    if status != "ok":
        return head + ",,,,,,,,,,," + ("" if status == "pending" else '"an error"')
    if not reached:  # summary.csv leaves the times to the threshold empty: the run never got there
        return head + f",false,,,,400,{sim_s},0.78,56,82.84926070883192,1.3,"
    return head + f",true,{time_s},20,41,400,{sim_s},1,100,0,0.46,"


def eval_row(name, shape, trial, rate=1.0, status="ok", run="T"):
    head = f"eval/{name}/{shape}/{trial:03d},eval,{run},{'T' if status == 'ok' else ''},DC6,{name},{shape},{trial},,{status}"
    if status != "ok":
        return head + ",,,,,,,,,,," + ("" if status == "pending" else '"scenarios/lib/place.lua:106: no placement"')
    return head + f",,,,,,,{rate},{200 * rate - 100},0,0.08,"


def total_row(obj, rate, episodes, policies, extra=None):
    row = {"episodes": episodes, "evaluations": policies, "interval": "policies", "layouts": episodes, "object": obj,
           "per_policy_success_mean": rate, "per_policy_success_std": 0.0, "policies": policies,
           "reward_mean": 200 * rate - 100, "reward_std": 0.0, "success_high": min(1.0, rate + 0.02),
           "success_low": rate - 0.05, "success_rate": rate}
    row.update(extra or {})
    return row


def training_table(run, contexts, pending=0):
    return {"baseline": contexts[0], "run": run, "title": f"Stage {run} (run {run})", "usage": {}, "usage_comparisons": [],
            "rows": [{"context": c, "failed": 0, "pending": pending, "trials": 2, "success_rate": 1.0,
                      "time_mean_s": 100.0, "time_lower_bound": False} for c in contexts]}


def write_folder(folder, rows, report):
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    with open(os.path.join(folder, "summary.csv"), "w") as f:
        f.write(HEADER + "\n" + "\n".join(rows) + "\n")
    with open(os.path.join(folder, "report.json"), "w") as f:
        f.write(report if isinstance(report, str) else json.dumps(report, indent=1))


def transfer_folder(folder, unreached=(), failed=(), pending_rows=None):
    """A results folder of scripts/transfer.lua, 2 trials a run: runs in `unreached` (run/context)
    have trial 1 missing its threshold; evaluations in `failed` have trial 1 failed (summary.csv only,
    as today's report.json says no more per evaluation); `pending_rows`: {evaluation: n} carried by
    the Total rows' "pending" field (trial 1 pending in summary.csv)."""
    pending_rows = pending_rows or {}
    rows, tables, trials, without = [], [], 0, {"failed": 0, "pending": 0}
    runs = [("SG", "SG", "DC2"), ("T", "T", "DC6"), ("SG_coarse", "SG_coarse", "DC2"), ("T_coarse", "T", "DC6"),
            ("SG_frozen", "SG_frozen", "DC2"), ("T_frozen", "T", "DC6")] + [(f"SG_{b}", "SG", "DC2") for b in BODIES]
    for run, stage, context in runs:
        for i in range(2):
            missed = i == 1 and f"{run}/{context}" in unreached
            rows.append(train_row(run, stage, context, i, reached=not missed, time_s=100.0 + 20 * i,
                                  sim_s=1800.0 + 10 * i))
            trials += 1
        tables.append(training_table(run, [context]))
    for body in BODIES:
        for kind in ("b", "c"):
            for world in ("open", "clutter"):
                name = f"{kind}_{body}_{world}"
                ok = 2
                for i in range(2):
                    status = "failed" if i == 1 and name in failed else "pending" if i == 1 and name in pending_rows else "ok"
                    rows.append(eval_row(name, "all", i, 0.98, status))
                    trials += 1
                    if status != "ok":
                        without[status] += 1
                        ok -= 1
                extra = {"failed": 0, "pending": pending_rows[name]} if name in pending_rows else None
                tables.append({"evaluation": name, "title": f"Evaluation {name}",
                               "rows": [total_row("all", 0.98, 50 * ok, ok), total_row("Total", 0.98, 50 * ok, ok, extra)]})
    report = {"tables": tables}
    if without["failed"] or without["pending"]:
        report = {"partial": {**without, "trials": trials, "with_results": trials - sum(without.values())}, "tables": tables}
    write_folder(folder, rows, report)


def noise_folder(folder, failed=(), pending_rows=None):
    """A results folder of scripts/noise.lua: the evaluations III_x<scale>, 1 policy x 4 shapes each;
    `failed`: scales whose spade trial failed (summary.csv only); `pending_rows`: {scale: n} given by
    the Total rows' "pending" field only (summary.csv's rows say ok: the field alone must be read)."""
    pending_rows = pending_rows or {}
    rows, tables, without = [train_row("SG", "SG", "DC2", 0), train_row("T", "T", "DC6", 0)], [], {"failed": 0, "pending": 0}
    for s in SCALES:
        name = f"III_x{s}"
        shapes = ["circle", "triangle", "pentagon", "spade"]
        ok = []
        for shape in shapes:
            status = "failed" if shape == "spade" and s in failed else "ok"
            rows.append(eval_row(name, shape, 0, 0.98, status))
            if status == "ok":
                ok.append(shape)
            else:
                without[status] += 1
        without["pending"] += pending_rows.get(s, 0)
        extra = {"failed": 0, "pending": pending_rows[s]} if s in pending_rows else None
        tables.append({"evaluation": name, "title": f"Table III under {s} M",
                       "rows": [total_row(sh, 0.98, 50, 1) for sh in ok] + [total_row("Total", 0.98, 50 * len(ok), 1, extra)]})
    trials = len(rows)
    report = {"tables": tables}
    if without["failed"] or without["pending"]:
        report = {"partial": {**without, "trials": trials, "with_results": trials - sum(without.values())}, "tables": tables}
    write_folder(folder, rows, report)


def kinds_folder(folder, names, failed=(), never=()):
    """A results folder of scripts/noise_kinds.lua: the evaluations III_<kind>, 1 policy x 4 shapes;
    `failed`: kinds whose spade trial failed; `never`: kinds none of whose trials ran (pending, as
    --only leaves them: their table has no rows)."""
    rows, tables, without = [], [], {"failed": 0, "pending": 0}
    for kind in names:
        name = f"III_{kind}"
        ok = []
        for shape in ["circle", "triangle", "pentagon", "spade"]:
            status = "pending" if kind in never else "failed" if shape == "spade" and kind in failed else "ok"
            rows.append(eval_row(name, shape, 0, 1.0, status))
            if status == "ok":
                ok.append(shape)
            else:
                without[status] += 1
        # As roger report writes a table none of whose trials has a result: every row, the Total's
        # too, of the counts alone.
        alone = [{"object": sh, "policies": 0, "evaluations": 0, "failed": 0, "pending": 1}
                 for sh in ["circle", "triangle", "pentagon", "spade"]] + \
            [{"object": "Total", "policies": 0, "evaluations": 0, "failed": 0, "pending": 4}]
        tables.append({"evaluation": name, "title": f"Table III's T/DC6 policies under {kind}",
                       "rows": alone if not ok else [total_row(sh, 1.0, 10, 1) for sh in ok] +
                       [total_row("Total", 1.0, 10 * len(ok), 1)]})
    report = {"partial": {**without, "trials": len(rows), "with_results": len(rows) - sum(without.values())},
              "tables": tables}
    write_folder(folder, rows, report)


# A results folder of scripts/teachers.lua: per trial id, its teacher's kind and what it did.
# "moves"/"lifts": the teacher state's episodes (sequence: (episode, from, to)); "obstacles": the
# training tasks' obstacles (episodes.jsonl); "cost": (teacher_wall_s, train_wall_s); "skipped":
# (episode, robot_distance). train_episodes is 1500 unless given ("episodes").
TEACHER_TRIALS = {
    "SG/DC2/000": {"kind": None},  # a trial without a teacher: not pooled
    # B2: trials 0 and 1 never left the circle (reached 90% at 300 and 150 episodes); trial 2
    # promoted at 400, was demoted at 450 and promoted again at 500.
    "T_sequence/B2/000": {"kind": "sequence", "moves": [], "reached": 300, "cost": (0.006, 2.0)},
    "T_sequence/B2/001": {"kind": "sequence", "moves": [], "reached": 150, "cost": (0.004, 2.0)},
    "T_sequence/B2/002": {"kind": "sequence", "moves": [(400, 1, 2), (450, 2, 1), (500, 1, 2)], "reached": 600,
                          "cost": (0.010, 4.0)},
    # DC3: promoted at 993 and at 1138 (then to step 3); trial 2's only move was decided on its last
    # episode (1500): it set no episode, so the trial never left its first step.
    "T_sequence/DC3/000": {"kind": "sequence", "moves": [(993, 1, 2)], "reached": 1200, "cost": (0.02, 5.0)},
    "T_sequence/DC3/001": {"kind": "sequence", "moves": [(1138, 1, 2), (1300, 2, 3)], "reached": 1450,
                           "cost": (0.02, 5.0), "skipped": [(1068, 1.993)]},
    "T_sequence/DC3/002": {"kind": "sequence", "moves": [(1500, 1, 2)], "reached": None, "cost": (0.03, 6.0)},
    "T_lcas/B2/000": {"kind": "lcas", "lifts": [100, 200, 300], "cost": (0.001, 4.0)},
    "T_lcas/B2/001": {"kind": "lcas", "lifts": [100, 200, 300], "cost": (0.002, 4.0)},
    "T_lcas/B2/002": {"kind": "lcas", "lifts": [100, 250, 300], "cost": (0.003, 4.0)},
    # SG: 400 training episodes; trial 2's second lift was decided on its last (400): left out.
    "SG_lcas/B1/000": {"kind": "lcas", "lifts": [50, 100], "episodes": 400, "cost": (0.0002, 0.4)},
    "SG_lcas/B1/001": {"kind": "lcas", "lifts": [50, 100], "episodes": 400, "cost": (0.0001, 0.4)},
    "SG_lcas/B1/002": {"kind": "lcas", "lifts": [50, 400], "episodes": 400, "cost": (0.0001, 0.4)},
    # ALP-GMM's obstacles: 0+1+2+3 and 5+6 and 1+2+4: 24 over 9 episodes, 2.67 pooled (the trials'
    # means, 1.5, 5.5 and 2.33, would give 3.11); shares 0.5%, 1.2%, 1.48%.
    "T_alp/B2/000": {"kind": "alp_gmm", "obstacles": [0, 1, 2, 3], "cost": (0.05, 10.0)},
    "T_alp/B2/001": {"kind": "alp_gmm", "obstacles": [5, 6], "cost": (0.06, 5.0), "skipped": [(40, 1.965), (41, 1.97)]},
    "T_alp/B2/002": {"kind": "alp_gmm", "obstacles": [1, 2, 4], "cost": (0.117, 7.9)},
    "T_random/B2/000": {"kind": "random", "obstacles": [3, 4, 4, 6], "cost": (0.001, 2.0)},
    "T_plr/B2/000": {"kind": "plr", "cost": (0.02, 4.0)},
    "T_plr/B2/001": {"kind": "plr", "cost": (0.01, 4.0)},
}
TASKS = ("obstacles = roger.int(0, 6), robot_distance = roger.real(0.8, 2), "
         "shape = roger.choice{circle, triangle, pentagon, spade}")


def teacher_state(spec, episodes):
    """The teacher's final state as result.json records it (the fields of a real one)."""
    kind = spec["kind"]
    if kind == "sequence":
        moves = [{"episode": e, "from": a, "rate": 0.5, "to": b} for e, a, b in spec["moves"]]
        return {"episodes": episodes, "kind": kind, "moves": moves, "rate": 0.6,
                "step": moves[-1]["to"] if moves else 1, "steps": 3}
    if kind == "lcas":
        sg = spec.get("episodes") == 400
        levels = [32, 64, 128] if sg else [0, 2, 4, 6]
        lifts = [{"episode": e, "from": levels[i], "gain": 0.0, "rate": 0.0, "to": levels[i + 1]}
                 for i, e in enumerate(spec["lifts"])]
        return {"episodes": episodes, "kind": kind, "level": len(lifts) + 1, "levels": len(levels), "lifts": lifts,
                "param": "eye_pixels" if sg else "obstacles", "rate": 0.8, "value": levels[len(lifts)]}
    if kind == "alp_gmm":
        return {"components": [], "dims": ["obstacles", "robot_distance", "shape"], "episodes": episodes, "fits": 20,
                "kind": kind, "mean_alp": 0.1}
    if kind == "plr":
        return {"episodes": episodes, "kind": kind, "levels": 500, "replays": 700, "top": []}
    return {"episodes": episodes, "kind": kind}


def teacher_trial(folder, id, spec):
    """trials/ID/result.json (and episodes.jsonl), as roger run writes them, with these figures."""
    run, context, trial = id.split("/")
    d = os.path.join(folder, "trials", id)
    os.makedirs(d)
    episodes = spec.get("episodes", 1500)
    reached = spec.get("reached", 100)
    result = {"id": id, "run": run, "stage": run, "context": context, "trial": int(trial), "seed": int(trial) + 1,
              "threshold": 0.9, "reached": reached is not None, "episodes_to_threshold": reached or episodes,
              "time_to_threshold_s": 8.0 * (reached or episodes), "train_episodes": episodes,
              "train_sim_s": 8.0 * episodes, "success_rate": 0.95, "stopped_early": False,
              "checkpoints": [{"episodes": 50, "eval_wall_s": 0.3, "success_rate": 0.1, "wall_s": 0.1}]}
    if spec["kind"]:
        teacher_wall, train_wall = spec["cost"]
        result.update({
            "tasks": TASKS, "teacher_wall_s": teacher_wall, "train_wall_s": train_wall,
            # wall_s holds the checkpoints' evaluations too: not the cost's denominator
            "wall_s": 3 * train_wall + 1.0, "test": {"seed": 59, "tasks": 200},
            "teacher": {"kind": spec["kind"], "state": teacher_state(spec, episodes), "wall_s": teacher_wall},
            "skipped_tasks": [{"episode": e, "error": "scenarios/lib/place.lua:78: world:sample_position: no placement",
                               "task": {"obstacles": 2, "robot_distance": r, "shape": "circle"}}
                              for e, r in spec.get("skipped", [])]})
    else:
        result.update({"train_wall_s": 1.0, "wall_s": 2.0})
    with open(os.path.join(d, "episodes.jsonl"), "w") as f:
        for i, n in enumerate(spec.get("obstacles", [3])):
            f.write(json.dumps({"index": i, "epsilon": 1.0, "reward": -100.0, "success": False, "sim_s": 10.0,
                                "task": {"obstacles": n, "robot_distance": 1.5, "shape": "circle"},
                                "td_error": 1.0, "world": {"objects": 1, "obstacles": n, "shapes": ["circle"]}}) + "\n")
    with open(os.path.join(d, "result.json"), "w") as f:
        json.dump(result, f, indent=1)


def teachers_folder(folder, failed=(), pending=(), never=0):
    """A results folder of scripts/teachers.lua as `roger run` leaves it while it runs (manifest.json,
    trials/; summary.csv comes at the end): TEACHER_TRIALS, but `failed` (error.json) and `pending`
    (started: a folder without result.json), and `never` more PLR trials not run yet (no folder)."""
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(os.path.join(folder, "trials"))
    ids = list(TEACHER_TRIALS) + [f"T_plr/B2/{i:03d}" for i in range(2, 2 + never)]
    with open(os.path.join(folder, "manifest.json"), "w") as f:
        json.dump({"format": "roger-results/1", "script": "scripts/teachers.lua", "trials": ids,
                   "seeds": {id: int(id[-3:]) + 1 for id in ids}, "version": "0.1.0"}, f, indent=1)
    for id, spec in TEACHER_TRIALS.items():
        if id in failed:
            os.makedirs(os.path.join(folder, "trials", id))
            with open(os.path.join(folder, "trials", id, "error.json"), "w") as f:
                json.dump({"error": "a fault", "trial": id}, f)
        elif id in pending:
            os.makedirs(os.path.join(folder, "trials", id))  # started: episodes.jsonl so far, no result
        else:
            teacher_trial(folder, id, spec)
    return len(ids)


# ---- running and importing the scripts ----

def run(args, env=None, cwd=None):
    return subprocess.run([sys.executable] + args, capture_output=True, text=True, env=env, cwd=cwd, timeout=120)


def load(scripts, name):
    """A script of scripts/ as a module (its main() is not run)."""
    sys.dont_write_bytecode = True  # no __pycache__ left in the source tree
    spec = importlib.util.spec_from_file_location(name + "_under_test", os.path.join(scripts, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def no_roger_env(work):
    """An environment in which no roger program can be found: no $ROGER, a PATH of an empty folder
    (and, run in `work` with the script copied there by alone(), no build/engine/roger beside the
    script or below the current folder)."""
    env = {k: v for k, v in os.environ.items() if k != "ROGER"}
    empty = os.path.join(work, "empty_path")
    os.makedirs(empty, exist_ok=True)
    env["PATH"] = empty
    return env


def alone(scripts, work, name):
    """A copy of a script in a folder of its own, with the module the scripts import
    (results_common.py, where there is one: older copies had none): no build/engine/roger beside it
    to find."""
    folder = os.path.join(work, "alone", "scripts")
    os.makedirs(folder, exist_ok=True)
    shutil.copy(os.path.join(scripts, name), folder)
    if os.path.exists(os.path.join(scripts, "results_common.py")):
        shutil.copy(os.path.join(scripts, "results_common.py"), folder)
    return os.path.join(folder, name)


def one_line_error(r, what):
    lines = r.stderr.strip().splitlines()
    expect(r.returncode != 0, f"{what}: exit status 0, expected an error")
    expect("Traceback" not in r.stderr, f"{what}: a traceback, not a one-line error:\n{r.stderr}")
    expect(len(lines) == 1, f"{what}: expected one line on stderr, got {len(lines)}:\n{r.stderr}")
    return lines[0]


def table_row(stdout, first_cell):
    rows = [line for line in stdout.splitlines() if line.startswith(f"| {first_cell} |")]
    expect(rows, f"no table row '{first_cell}' in:\n{stdout}")
    return [c.strip() for c in rows[0].strip("|").split("|")]


# ---- the checks ----

def transfer_unreached(scripts, work):
    folder = os.path.join(work, "transfer_unreached")
    transfer_folder(folder, unreached={"SG_small/DC2", "T_coarse/DC6"})
    r = run([os.path.join(scripts, "transfer_figure.py"), folder, os.path.join(work, "transfer_unreached.svg")])
    expect(r.returncode == 0 and "Traceback" not in r.stderr, f"exit status {r.returncode}:\n{r.stderr}")
    # Trial 0 reached the threshold in 100 s; trial 1 never did: its whole training, 1810 s, stands in.
    expect(table_row(r.stdout, "small")[5] == "≥ 15:55", f"small's SG/DC2 time: {table_row(r.stdout, 'small')[5]!r}, "
           "expected '≥ 15:55' (the mean of 100 s and trial 1's whole training, 1810 s)")
    expect(table_row(r.stdout, "long arms")[5] == "1:50", f"long arms' time: {table_row(r.stdout, 'long arms')[5]!r}")
    coarse = table_row(r.stdout, "SG with coarse eyes (32 px, 60 degrees), T full")
    expect(coarse[2] == "≥ 15:55" and coarse[1] == "1:50", f"the maturation row: {coarse}")
    expect(r.stderr == "", f"a complete folder gave a warning:\n{r.stderr}")


def transfer_partial(scripts, work):
    folder = os.path.join(work, "transfer_partial")
    transfer_folder(folder, failed={"b_small_clutter"})
    out = os.path.join(work, "transfer_partial.svg")
    r = run([os.path.join(scripts, "transfer_figure.py"), folder, out])
    expect(r.returncode == 0, f"exit status {r.returncode} (a partial folder is drawn, with a warning):\n{r.stderr}")
    expect("1 failed" in r.stderr and "of 92 trials" in r.stderr and "b_small_clutter" in r.stderr,
           f"no warning naming the partial folder (1 failed of 92 trials) and b_small_clutter on stderr:\n{r.stderr!r}")
    small = table_row(r.stdout, "small")
    expect(small[3].endswith("(1 failed)"), f"small's (b) 3 obstacles cell is not marked '(1 failed)': {small[3]!r}")
    expect(not any("failed" in c or "pending" in c for c in small[1:3] + small[4:]),
           f"cells of complete evaluations are marked: {small}")
    with open(out) as f:
        picture = f.read()
    expect("partial results" in picture and ">*</text>" in picture,
           "the figure has no note of the partial folder and no '*' over the bar concerned")


def transfer_partial_rows(scripts, work):
    folder = os.path.join(work, "transfer_partial_rows")
    transfer_folder(folder, pending_rows={"c_wide_eyes_open": 1})
    r = run([os.path.join(scripts, "transfer_figure.py"), folder, os.path.join(work, "transfer_partial_rows.svg")])
    expect(r.returncode == 0, f"exit status {r.returncode}:\n{r.stderr}")
    expect("1 pending" in r.stderr and "c_wide_eyes_open" in r.stderr, f"no warning naming c_wide_eyes_open:\n{r.stderr!r}")
    cell = table_row(r.stdout, "wide eyes")[2]
    expect(cell.endswith("(1 pending)"), f"wide eyes' (c) open cell is not marked '(1 pending)': {cell!r}")


def transfer_no_file(scripts, work):
    folder = os.path.join(work, "transfer_no_file")
    transfer_folder(folder)
    with open(os.path.join(folder, "report.json")) as f:
        text = f.read()
    with open(os.path.join(folder, "report.json"), "w") as f:
        f.write(text[:len(text) // 2])  # cut short, as by a full disk
    before = sorted(os.listdir(folder))
    r = run([os.path.join(scripts, "transfer_figure.py"), folder])
    after = sorted(os.listdir(folder))
    expect(after == before, f"the failed script left {sorted(set(after) - set(before))} in the results folder")
    one_line_error(r, "transfer_figure.py on a report.json cut short")


def atomic_writes(scripts, work):
    # Every open for writing names a temporary (PATH + ".tmp"), renamed over the file once whole; the
    # scripts' shared write_atomically is in results_common.py (where there is one).
    for name in ("transfer_figure.py", "noise_figure.py", "noise_kinds.py", "failure_modes.py", "results_common.py"):
        if name == "results_common.py" and not os.path.exists(os.path.join(scripts, name)):
            continue
        with open(os.path.join(scripts, name)) as f:
            source = f.read()
        for target in re.findall(r"open\(([^\n]*?),\s*[\"'][wa]b?[\"']", source):
            expect(".tmp" in target, f"{name} writes {target} in place, not through a temporary and os.replace")


def failure_modes_no_roger(scripts, work):
    script = alone(scripts, work, "failure_modes.py")
    env = no_roger_env(work)
    line = one_line_error(run([script, os.path.join(work, "nothing"), "--trials", "0", "--episodes", "1"], env, work),
                          "failure_modes.py without roger")
    expect("roger" in line, f"the error does not say roger is missing: {line!r}")
    env["ROGER"] = os.path.join(work, "no_such_roger")
    line = one_line_error(run([script, os.path.join(work, "nothing")], env, work),
                          "failure_modes.py with $ROGER naming nothing")
    expect("no_such_roger" in line, f"the error does not name $ROGER's program: {line!r}")


def noise_figure_no_roger(scripts, work):
    folder = os.path.join(work, "noise_no_roger")
    noise_folder(folder)
    before = sorted(os.listdir(folder))
    r = run([alone(scripts, work, "noise_figure.py"), folder], no_roger_env(work), work)
    line = one_line_error(r, "noise_figure.py without roger")
    expect("roger" in line, f"the error does not say roger is missing: {line!r}")
    expect(sorted(os.listdir(folder)) == before, f"files left behind: {sorted(set(os.listdir(folder)) - set(before))}")


def noise_figure_partial(scripts, work):
    nf = load(scripts, "noise_figure")
    folder = os.path.join(work, "noise_partial")
    noise_folder(folder, failed={"8"}, pending_rows={"2": 1})
    table = nf.table_three(folder)
    expect(sorted(table) == [0, 0.5, 1, 2, 4, 8], f"table_three: {table}")
    missing = nf.left_out(folder)
    expect(missing == {2: {"failed": 0, "pending": 1}, 8: {"failed": 1, "pending": 0}},
           f"left_out: {missing}, expected 1 pending at 2 M (the Total row's field) and 1 failed at 8 M (summary.csv)")
    note = nf.warning(folder, missing)
    expect("1 failed" in note and "of 26 trials" in note and "III_x8" in note and "III_x2" in note,
           f"the warning does not say the folder is partial and which evaluations: {note!r}")
    points = {nf.SERIES[2][0]: table, nf.SERIES[0][0]: nf.with_wilson({s: (190, 200) for s in nf.SCALES})}
    printed = "\n".join(nf.printed(points, missing))
    expect("8 M 98.0% (147/150)" in printed and "(1 failed)" in printed and "(1 pending)" in printed,
           f"the policies' points are not marked:\n{printed}")
    expect(printed.count("(1 failed)") == 1, f"a scripted point marked too:\n{printed}")
    picture = nf.svg(points, nf.partial_of(folder), set(missing))
    expect("partial results" in picture and picture.count(">*</text>") == 2,
           "the figure has no note of the partial folder, or not one '*' per point concerned")


def noise_kinds_options(scripts, work):
    nk = load(scripts, "noise_kinds")
    expect(nk.run_command("R", "OUT") == ["R", "run", "scripts/noise_kinds.lua", "--out", "OUT", "--jobs", "2"],
           f"the default command changed: {nk.run_command('R', 'OUT')}")
    cmd = nk.run_command("R", "OUT", jobs=1, trials=1, only=["eval/III_none", "T"])
    expect(cmd[:5] == ["R", "run", "scripts/noise_kinds.lua", "--out", "OUT"] and
           " ".join(cmd[5:]) == "--jobs 1 --trials 1 --only eval/III_none --only T", f"the options are not passed: {cmd}")
    r = run([os.path.join(scripts, "noise_kinds.py"), "--help"])
    expect(r.returncode == 0 and all(o in r.stdout for o in ("--trials", "--only", "--jobs")),
           f"--help does not offer --trials, --only and --jobs:\n{r.stdout}{r.stderr}")
    with open(os.path.join(scripts, "noise_kinds.py")) as f:
        doc = f.read().split('"""')[1]
    expect("--trials" in doc and "--only" in doc, "the docstring does not document --trials and --only")


def noise_kinds_partial(scripts, work):
    nk = load(scripts, "noise_kinds")
    folder = os.path.join(work, "kinds_partial")
    kinds_folder(folder, ["none", "joints_bias", "all"], failed={"joints_bias"}, never={"all"})
    expect(nk.table_three(folder, "all") is None, "an evaluation without a result is not None")
    expect(nk.table_three(folder, "joints_bias")[:2] == (30, 30), f"joints_bias: {nk.table_three(folder, 'joints_bias')}")
    missing = nk.left_out(folder)
    expect(missing == {"III_joints_bias": {"failed": 1, "pending": 0}, "III_all": {"failed": 0, "pending": 4}},
           f"left_out: {missing}")
    note = nk.warning(folder, missing, ["III_none", "III_joints_bias", "III_all"])
    expect("of 12 trials" in note and "III_joints_bias" in note and "III_all" in note,
           f"the warning does not say the folder is partial and which evaluations: {note!r}")
    rows = [{"kind": k, "params": p, "unobstructed": [200, 200], "cluttered": [199, 200], "sort": [20, 20],
             "table3": None if nk.table_three(folder, k) is None else list(nk.table_three(folder, k))}
            for k, p in (("none", {}), ("joints_bias", {"noise_joints_bias": "0.02"}), ("all", {"noise_joints_bias": "0.02"}))]
    md = nk.markdown(rows, missing)
    expect(table_row(md, "none")[5] == "100.0% (40/40) [95.0, 100.0]", f"none's cell: {table_row(md, 'none')[5]!r}")
    expect(table_row(md, "joints_bias")[5].endswith("(1 failed)"), f"joints_bias: {table_row(md, 'joints_bias')}")
    expect(table_row(md, "all")[5] == "- (4 pending)", f"all: {table_row(md, 'all')}")


def noise_kinds_no_roger(scripts, work):
    r = run([alone(scripts, work, "noise_kinds.py"), os.path.join(work, "kinds_no_roger")], no_roger_env(work), work)
    line = one_line_error(r, "noise_kinds.py without roger")
    expect("roger" in line, f"the error does not say roger is missing: {line!r}")
    expect(not os.path.exists(os.path.join(work, "kinds_no_roger")), "a results folder was made")


def digest_lines(stdout):
    """The digest's lines, without their "- "."""
    return [line[2:] for line in stdout.splitlines() if line.startswith("- ")]


def expect_line(lines, line):
    expect(line in lines, f"no line\n  {line}\nin the digest:\n  " + "\n  ".join(lines))


def teachers_digest_figures(scripts, work):
    folder = os.path.join(work, "teachers")
    teachers_folder(folder)
    r = run([os.path.join(scripts, "teachers_digest.py"), folder])
    expect(r.returncode == 0 and r.stderr == "", f"exit status {r.returncode}, stderr:\n{r.stderr}")
    lines = digest_lines(r.stdout)
    expect_line(lines, "T_sequence/B2: never left its first step in 2 of 3 trials; promoted in 1 of 3, at episode 400; "
                       "of the 2 that did not, 2 reached 90% on the first step alone, at 150 to 300 episodes")
    expect_line(lines, "T_sequence/DC3: never left its first step in 1 of 3 trials; promoted in 2 of 3, all between "
                       "episodes 993 and 1138; of the 1 that did not, 0 reached 90% on the first step alone "
                       "(1 move decided on a last episode, never trained, left out)")
    expect_line(lines, "T_lcas/B2: obstacles lifted at episodes 100, 200 and 300 in 2 of 3 trials; "
                       "otherwise at episodes 100, 250 and 300 (1)")
    expect_line(lines, "SG_lcas/B1: eye_pixels lifted at episodes 50 and 100 in 2 of 3 trials; otherwise at episodes 50 "
                       "(1) (1 lift decided on a last episode, never trained, left out)")
    alp = (0 + 1 + 2 + 3 + 5 + 6 + 1 + 2 + 4) / 9  # pooled over the episodes
    rand = (3 + 4 + 4 + 6) / 4
    expect_line(lines, f"T_alp/B2: drew {alp:.2f} obstacles on average (9 training episodes of 3 trials), against "
                       f"uniform's 3.0; T_random/B2 drew {rand:.2f}")
    shares = sorted([0.05 / 10.0, 0.06 / 5.0, 0.117 / 7.9])  # over train_wall_s, not wall_s
    expect_line(lines, f"ALP-GMM: median {100 * shares[1]:.2f}%, at most {100 * shares[2]:.2f}% "
                       "(T_alp/B2/002: 0.117 s of 7.9 s), 3 trials")
    for name, kind, most, trials in (("PLR", "plr", "T_plr/B2/000: 0.020 s of 4.0 s", 2),
                                     ("sequence", "sequence", "T_sequence/DC3/002: 0.030 s of 6.0 s", 6),
                                     ("LCAS", "lcas", "T_lcas/B2/002: 0.003 s of 4.0 s", 6),
                                     ("random", "random", "T_random/B2/000: 0.001 s of 2.0 s", 1)):
        shares = [t / w for t, w in (v["cost"] for v in TEACHER_TRIALS.values() if v["kind"] == kind)]
        expect_line(lines, f"{name}: median {100 * statistics.median(shares):.2f}%, at most {100 * max(shares):.2f}% "
                           f"({most}), {trials} trial{'' if trials == 1 else 's'}")
    expect_line(lines, "2 of the 18 trials met 3 training tasks whose world could not be placed")
    expect_line(lines, "T_sequence/DC3/001: 1 skipped: episode 1068 (the object 1.993 m from Roger)")
    expect_line(lines, "T_alp/B2/001: 2 skipped: episode 40 (the object 1.965 m from Roger), "
                       "episode 41 (the object 1.970 m from Roger)")


def teachers_digest_partial(scripts, work):
    folder = os.path.join(work, "teachers_partial")
    n = teachers_folder(folder, failed={"T_sequence/B2/002"}, pending={"T_alp/B2/000", "T_lcas/B2/002"}, never=2)
    r = run([os.path.join(scripts, "teachers_digest.py"), folder])
    expect(r.returncode == 0, f"exit status {r.returncode} (a partial folder is digested, with a warning):\n{r.stderr}")
    # 2 trials started and 2 never ran: 4 pending; 1 failed; of the 16 done, SG/DC2/000 has no teacher.
    expect(f"{n - 5} of {n} trials done, 1 failed, 4 pending" in r.stderr and
           "pooled the 15 done trials with a teacher" in r.stderr and len(r.stderr.splitlines()) == 1,
           f"the partial folder is not said in one line with its counts on stderr:\n{r.stderr!r}")
    lines = digest_lines(r.stdout)
    expect_line(lines, "T_sequence/B2: never left its first step in 2 of 2 trials; promoted in 0 of 2; "
                       "of the 2 that did not, 2 reached 90% on the first step alone, at 150 to 300 episodes")
    expect_line(lines, "T_lcas/B2: obstacles lifted at episodes 100, 200 and 300 in 2 of 2 trials")
    expect_line(lines, f"T_alp/B2: drew {(5 + 6 + 1 + 2 + 4) / 5:.2f} obstacles on average (5 training episodes of 2 "
                       f"trials), against uniform's 3.0; T_random/B2 drew {(3 + 4 + 4 + 6) / 4:.2f}")
    expect_line(lines, f"ALP-GMM: median {100 * (0.06 / 5.0 + 0.117 / 7.9) / 2:.2f}%, at most {100 * 0.117 / 7.9:.2f}% "
                       "(T_alp/B2/002: 0.117 s of 7.9 s), 2 trials")


def teachers_digest_no_file(scripts, work):
    script = os.path.join(scripts, "teachers_digest.py")
    empty = os.path.join(work, "teachers_empty")
    os.makedirs(empty, exist_ok=True)
    line = one_line_error(run([script, empty]), "teachers_digest.py on a folder without manifest.json")
    expect("not a results folder" in line, f"the error does not say it is not a results folder: {line!r}")
    folder = os.path.join(work, "teachers_cut")
    teachers_folder(folder)
    path = os.path.join(folder, "trials", "T_lcas", "B2", "001", "result.json")
    with open(path) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(text[:len(text) // 2])  # cut short, as by a full disk
    line = one_line_error(run([script, folder]), "teachers_digest.py on a result.json cut short")
    expect("T_lcas/B2/001/result.json" in line, f"the error does not name the record: {line!r}")
    one_line_error(run([script]), "teachers_digest.py without a folder")


def wrong_folders(scripts, work):
    # Found by a probe: transfer_figure.py on a missing folder ended in a traceback, teachers_digest.py
    # on another script's folder printed empty sections with status 0, failure_modes.py printed its
    # table's header before finding a trial's policy missing, and usage errors exited 1.
    missing = os.path.join(work, "no_such_folder")
    line = one_line_error(run([os.path.join(scripts, "transfer_figure.py"), missing]), "transfer_figure.py, no folder")
    expect("is not a results folder" in line, f"the error does not say it is not a results folder: {line!r}")
    expect(run([os.path.join(scripts, "transfer_figure.py")]).returncode == 2, "transfer_figure.py's usage: not status 2")
    expect(run([os.path.join(scripts, "teachers_digest.py")]).returncode == 2, "teachers_digest.py's usage: not status 2")
    other = os.path.join(work, "not_teachers")
    teachers_folder(other)
    for id in TEACHER_TRIALS:  # the same trials without a teacher: another script's folder
        path = os.path.join(other, "trials", id, "result.json")
        if os.path.exists(path):
            with open(path) as f:
                record = json.load(f)
            record.pop("teacher", None)
            with open(path, "w") as f:
                json.dump(record, f)
    line = one_line_error(run([os.path.join(scripts, "teachers_digest.py"), other]), "teachers_digest.py, no teacher")
    expect("no trial there has a teacher's record" in line, f"the error does not say what is missing: {line!r}")
    env = dict(os.environ, ROGER=sys.executable)  # any program: the check comes before roger runs
    r = run([os.path.join(scripts, "failure_modes.py"), other, "--trials", "0"], env=env)
    expect(r.stdout == "", f"failure_modes.py printed before its check:\n{r.stdout}")
    line = one_line_error(r, "failure_modes.py, a trial without its policy")
    expect("trial 0: no T/DC6 policy at" in line, f"the error does not name the trial and policy: {line!r}")
    # Found by a probe: noise_figure.py on a missing folder said to run `roger report` on it first;
    # an OUT.svg in a missing folder ended in a traceback (noise_figure.py after its evaluations), and
    # out.png received SVG text; failure_modes.py --episodes -5 printed a table of -5 episodes.
    line = one_line_error(run([os.path.join(scripts, "noise_figure.py"), missing]), "noise_figure.py, no folder")
    expect(line.endswith("does not exist") and "roger report" not in line, f"noise_figure.py, no folder: {line!r}")
    transfer = os.path.join(work, "wrong_out_transfer")
    transfer_folder(transfer)
    noise = os.path.join(work, "wrong_out_noise")
    noise_folder(noise)
    for name, folder in (("transfer_figure.py", transfer), ("noise_figure.py", noise)):
        for out, says in ((os.path.join(work, "figure.png"), "name it OUT.svg"),
                          (os.path.join(missing, "figure.svg"), "does not exist")):
            r = run([os.path.join(scripts, name), folder, out], env=env)
            expect(r.returncode == 2 and r.stdout == "", f"{name} {out}: status {r.returncode}, stdout {r.stdout!r}")
            expect(says in r.stderr and "Traceback" not in r.stderr, f"{name} {out}: {r.stderr!r}")
            expect(not os.path.exists(out), f"{name} wrote {out}")
    r = run([os.path.join(scripts, "failure_modes.py"), other, "--episodes", "-5"], env=env)
    expect(r.returncode == 2 and "at least 1" in r.stderr and r.stdout == "", f"failure_modes.py --episodes -5: {r}")


CHECKS = [transfer_unreached, transfer_partial, transfer_partial_rows, transfer_no_file, atomic_writes,
          failure_modes_no_roger, noise_figure_no_roger, noise_figure_partial, noise_kinds_options,
          noise_kinds_partial, noise_kinds_no_roger, teachers_digest_figures, teachers_digest_partial,
          teachers_digest_no_file, wrong_folders]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", required=True, help="a folder for the synthetic results (emptied first)")
    ap.add_argument("--scripts", default=os.path.join(HERE, os.pardir, os.pardir, "scripts"),
                    help="the folder of the scripts to check (default: the source tree's scripts/)")
    a = ap.parse_args()
    scripts = os.path.abspath(a.scripts)
    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    failed = []
    for check in CHECKS:
        try:
            check(scripts, work)
            print(f"ok    {check.__name__}")
        except Failed as e:
            failed.append(check.__name__)
            print(f"FAIL  {check.__name__}: {e}")
        except Exception as e:  # a script's function missing or crashing: the check fails, the others run
            failed.append(check.__name__)
            print(f"FAIL  {check.__name__}: {type(e).__name__}: {e}")
    if failed:
        print(f"check_figure_scripts: {len(failed)} of {len(CHECKS)} checks failed: {', '.join(failed)}")
        return 1
    print(f"check_figure_scripts: all {len(CHECKS)} checks hold")
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
