#!/usr/bin/env python3
"""Time of `suspflow solve` with and without its bands on the 50-bin scenes of a table
(issue 52: a 50-bin profile solved with bands in under 0.2 s).

Every scene of --data with 50 bins (L_y = 100 at bins of 2 a) is solved from its forcing
with each closure, once with the models of --models and once with the same models less
their `bands.json` (so without bands), the two in turn. Reported per closure: the solve's
own wall time (`summary.json` `wall_ms`: the solve and, with bands, the bands; not the
loading), and the whole process's CPU time (user + sys, from the operating system), whose
part beyond the local closure's (a solve of under a millisecond: loading the models and the
training table) is the solve's CPU time. On a shared machine the wall times carry the
waits for a core; the CPU times do not.

    nice -n 5 python3 scripts/solve_timing.py --suspflow target/release/suspflow \\
        --models models --data datasets/wide_plugs.ensemble.csv
"""
import argparse
import csv
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from solver_lofo import write_scene  # noqa: E402

CLOSURES = ["local", "learned", "nonlocal", "extremum"]
BINS = 50


def solve(exe, scene, models, train, closure, out):
    """One solve: (wall_ms of summary.json, the process's CPU ms, whether it had bands)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([exe, "solve", scene, "--models", models, "--train", train,
                        "--closure", closure, "--out", out, "--force"],
                       capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit(f"solve failed: {scene} {closure}\n{p.stderr[-1000:]}")
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    if s["bins"] != BINS:
        sys.exit(f"{scene}: {s['bins']} bins, not {BINS}")
    cpu = (after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime) * 1e3
    return s["wall_ms"], cpu, s.get("bands") is not None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--suspflow", default="target/release/suspflow")
    ap.add_argument("--models", default="models")
    ap.add_argument("--data", default="datasets/wide_plugs.ensemble.csv")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="solve_timing.")
    rows = {}
    with open(args.data) as f:
        for r in csv.DictReader(f):
            rows.setdefault(r["scene_id"], []).append(r)
    scenes = []
    for sid, rs in sorted(rows.items()):
        if len(rs) == BINS:
            scenes.append(os.path.join(work, sid + ".toml"))
            write_scene(scenes[-1], rs)
    bare = os.path.join(work, "models_without_bands")
    os.makedirs(bare)
    for name in os.listdir(args.models):
        if name.endswith(".json") and name != "bands.json":
            os.symlink(os.path.abspath(os.path.join(args.models, name)), os.path.join(bare, name))
    out = os.path.join(work, "out")
    timings = {}
    for closure in CLOSURES:
        for scene in scenes:
            for arm, models in (("bands", args.models), ("none", bare)):
                wall, cpu, banded = solve(args.suspflow, scene, models, args.data, closure, out)
                if banded != (arm == "bands"):
                    sys.exit(f"{models}: bands {'missing' if arm == 'bands' else 'present'}")
                timings.setdefault((closure, arm), []).append((wall, cpu, os.path.basename(scene)))
    base = statistics.median(c for _, c, _ in timings[("local", "bands")])
    print(f"{len(scenes)} scenes of {BINS} bins from {args.data}, models {args.models}; "
          f"CPU beyond loading: the process's CPU time less the local closure's median "
          f"({base:.0f} ms)")
    print("| closure | solve + bands, wall ms: median (max) | solve alone, wall ms | "
          "CPU beyond loading, ms, with bands: median (max, scene) | without bands | "
          "scenes over 200 ms CPU with bands |")
    print("|---|---|---|---|---|---|")
    for closure in CLOSURES:
        b, n = timings[(closure, "bands")], timings[(closure, "none")]
        worst = max(b, key=lambda t: t[1])
        print(f"| {closure} | {statistics.median(t[0] for t in b):.0f} "
              f"({max(t[0] for t in b):.0f}) | {statistics.median(t[0] for t in n):.0f} | "
              f"{statistics.median(t[1] for t in b) - base:.0f} ({worst[1] - base:.0f}, "
              f"{worst[2][:-5]}) | {statistics.median(t[1] for t in n) - base:.0f} "
              f"({max(t[1] for t in n) - base:.0f}) | "
              f"{sum(1 for t in b if t[1] - base > 200)} / {len(b)} |")


if __name__ == "__main__":
    main()
