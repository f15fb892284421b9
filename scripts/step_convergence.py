#!/usr/bin/env python3
"""Convergence of a Brownian flow curve in the time step (issue 50 item 3; docs/physics.md
section 11): for every state of a grid run at several `run.dt_factor` (e.g.
grids/brownian_step_convergence.toml), eta_r and each of its parts at the longest step
against the run at a third of it. The numbers come from `suspflow flow-curves`' per-run
table (`flow_curves.csv`) and each run's step, from the run table of `suspflow generate`
(`bins.scenes.csv`) or, for runs made one by one (`suspflow simulate` into the grid's work
folders), from each folder's `summary.json` (`--work`); this script only pairs and
tabulates them.

A part passes when the two runs differ by at most 5 % of the shorter step's value AND by at
most 2 combined standard errors (the issue's target); both figures are printed, so a reader
sees which one fails.

    python3 scripts/step_convergence.py --runs reports/brownian/step_convergence/bins.scenes.csv \\
        --curves reports/brownian/step_convergence/flow_curves.csv \\
        --out reports/brownian/step_convergence/convergence.md
    python3 scripts/step_convergence.py --work reports/brownian/step_convergence/runs.work \\
        --curves reports/brownian/step_convergence/flow_curves.csv
"""
import argparse
import csv
import json
import math
import os
import sys
from collections import defaultdict

PARTS = ["eta_r", "eta_r_contact", "eta_r_hydrodynamic", "eta_r_brownian"]


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def steps_from_work(work, curves):
    """Each finished run's step and its limit, from `<work>/<scene_id>_seed<seed>/summary.json`."""
    steps = {}
    for row in curves:
        path = os.path.join(work, f"{row['scene_id']}_seed{row['seed']}", "summary.json")
        if os.path.exists(path):
            with open(path) as f:
                summary = json.load(f)
            steps[row["scene_id"]] = {"status": "done", "dt": summary["dt"], "dt_limit": summary["dt_limit"]}
    return steps


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = ap.add_mutually_exclusive_group(required=True)
    source.add_argument("--runs", help="generate's run table (bins.scenes.csv)")
    source.add_argument("--work", help="the grid's work folder of runs (summary.json in each)")
    ap.add_argument("--curves", required=True, help="flow-curves' per-run table (flow_curves.csv)")
    ap.add_argument("--out", help="Markdown table (printed as well)")
    ap.add_argument("--tolerance", type=float, default=0.05, help="relative tolerance (0.05)")
    ap.add_argument("--sigmas", type=float, default=2.0, help="combined standard errors (2)")
    a = ap.parse_args()
    curves = read(a.curves)
    steps = steps_from_work(a.work, curves) if a.work else {r["scene_id"]: r for r in read(a.runs)}
    groups = defaultdict(list)
    for row in curves:
        run = steps.get(row["scene_id"])
        if run is None or run["status"] != "done":
            continue
        key = (float(row["phi"]), float(row["peclet"] or "nan"), float(row["mu_p"]), row["seed"])
        groups[key].append((float(run["dt"]), run["dt_limit"], row))
    lines = [
        "| phi | Pe | mu_p | seed | dt (limit) | dt/3 | part | at dt | at dt/3 | difference | / value | / comb. se | pass |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    failures = 0
    compared = 0
    for key in sorted(groups):
        runs = sorted(groups[key], key=lambda r: -r[0])
        if len(runs) < 2:
            continue
        (dt, limit, long_), (dt3, _, short) = runs[0], runs[-1]
        if abs(dt / dt3 - 3.0) > 0.01:
            print(f"skipped {key}: steps {dt:.3e} and {dt3:.3e} are not a factor 3 apart", file=sys.stderr)
            continue
        for part in PARTS:
            q, q3 = float(long_[part]), float(short[part])
            se = math.hypot(float(long_[part + "_se"]), float(short[part + "_se"]))
            diff = q - q3
            rel = diff / q3 if q3 else float("nan")
            sig = diff / se if se > 0 else float("inf")
            ok = abs(rel) <= a.tolerance and abs(sig) <= a.sigmas
            compared += 1
            failures += not ok
            phi, pe, mu, seed = key
            lines.append(
                f"| {phi} | {pe:g} | {mu:g} | {seed} | {dt:.3e} ({limit}) | {dt3:.3e} | {part} | "
                f"{q:.3f} +- {float(long_[part + '_se']):.3f} | {q3:.3f} +- {float(short[part + '_se']):.3f} | "
                f"{diff:+.3f} | {100 * rel:+.1f} % | {sig:+.1f} | {'yes' if ok else '**no**'} |"
            )
    lines.append("")
    lines.append(f"{compared - failures} of {compared} comparisons within {100 * a.tolerance:g} % and {a.sigmas:g} combined standard errors.")
    text = "\n".join(lines) + "\n"
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
