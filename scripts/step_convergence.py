#!/usr/bin/env python3
"""Convergence of a Brownian flow curve in the time step (issue 50 item 3; docs/physics.md
section 11): for every state of a grid run at several steps (`run.dt_factor` or `run.dt`,
e.g. grids/brownian_step_convergence.toml), eta_r and each of its parts at each step against
the run of the same seed at the shortest step of its state (for a grid at `dt_factor` 1 and
1/3: the automatic step against a third of it). The numbers come from `suspflow
flow-curves`' per-run table (`flow_curves.csv`) and each run's step, from the run table of
`suspflow generate` (`bins.scenes.csv`) or, for runs made one by one (`suspflow simulate`
into the grid's work folders), from each folder's `summary.json` (give the work folder
instead), or, given `-`, from the table's own `dt` column (recorded by flow-curves since
its runs' steps were; the limit that set each step is then not known and shows as `?`);
this script only pairs, pools and tabulates them. A state is (phi, rho, Pe, mu_p)
and, in a mixture grid, alpha (printed beside phi); runs of one such state whose scenes'
`[forces]` differ (a grid's cases at two contact stiffnesses, say) are told apart by the
entries that differ, printed beside phi as well. Each run's scene is read from
`<run>/scene.toml` in the `--set`'s work folder, or beside its table in `runs.done`; a run
whose scene is not found is told apart from none.

Two tables. Per seed: a run against the shortest step of its seed, their difference against
its combined block standard error. Pooled over seeds (several `--set`s may add seeds of the
same states, e.g. grids/brownian_step_convergence_pe100.toml, or steps, e.g.
grids/brownian_relaxation_limit.toml): for each step and reference step, the mean over seeds
of the per-seed differences, with the larger of two standard errors, the scatter of those
differences between seeds (paired, sd / sqrt(n), n >= 2) and the block errors combined,
because the block errors of one run underestimate the scatter between seeds where the
stress is correlated over more than a block (measured: docs/physics.md section 11). A
comparison passes when its pooled difference is within 5 % of the shorter step's value AND
within 2 of its standard errors (the issue's target); both figures are printed, so a reader
sees which one fails.

With `--against-last` each run is compared with the last set's run of its state and seed
instead, whatever its step: a grid rerun under a new step rule against its old runs
(reports/brownian/rho05_v2: the old rule's runs against the new rule's).

    python3 scripts/step_convergence.py \\
        --set reports/brownian/step_convergence/flow_curves.csv reports/brownian/step_convergence/runs.work \\
        --set reports/brownian/step_convergence_pe100/flow_curves.csv reports/brownian/step_convergence_pe100/bins.scenes.csv \\
        --out reports/brownian/step_convergence/convergence.md
"""
import argparse
import csv
import json
import math
import os
import statistics
import sys
import tomllib
from collections import defaultdict

PARTS = ["eta_r", "eta_r_contact", "eta_r_hydrodynamic", "eta_r_brownian"]


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def steps_from_table(curves):
    """Each run's step from the flow-curves table's own `dt` column (its limit unknown)."""
    steps = {}
    for row in curves:
        if not row.get("dt") or math.isnan(float(row["dt"])):
            sys.exit(f"run {row['scene_id']} seed {row['seed']}: the table records no step (`dt`); "
                     "give its run table (bins.scenes.csv) or work folder instead of -")
        steps[row["scene_id"]] = {"status": "done", "dt": row["dt"], "dt_limit": "?"}
    return steps


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


def scene_forces(curves_path, steps_path, row):
    """The `[forces]` table of a run's scene.toml (None where it is not found): in the work
    folder `steps_path`, else in the `runs.done` folder beside the table `curves_path`."""
    folder = steps_path if os.path.isdir(steps_path) else os.path.join(os.path.dirname(curves_path), "runs.done")
    path = os.path.join(folder, f"{row['scene_id']}_seed{row['seed']}", "scene.toml")
    if not os.path.exists(path):
        return None
    with open(path, "rb") as f:
        return tomllib.load(f).get("forces", {})


def labelled(entries):
    """Each (state, seed, run) of `entries` with its state's label (the 5th entry, printed
    beside phi): `alpha A` in a mixture grid, and the `[forces]` entries in which the scenes
    of one state differ, e.g. `k_n 3000.0`."""
    by_state = defaultdict(list)
    for state, forces, seed, run in entries:
        by_state[state].append(forces)
    varying = {}
    for state, found in by_state.items():
        known = [f for f in found if f is not None]
        names = sorted({k for f in known for k in f})
        varying[state] = [k for k in names if len({repr(f.get(k)) for f in known}) > 1]
    for state, forces, seed, run in entries:
        phi, rho, pe, mu, alpha = state
        label = [f"alpha {alpha}"] if alpha else []
        label += [f"{k} {forces.get(k) if forces is not None else '?'}" for k in varying[state]]
        yield (phi, rho, pe, mu, ", ".join(label)), seed, run


def seed_pairs(sets, against_last=False):
    """(phi, rho, Pe, mu_p, label, dt, dt_ref) -> per seed: (dt, its limit, run at dt, run at
    dt_ref), dt_ref the shortest step of that state and seed or, with `against_last`, the step
    of the last set's run of it (e.g. a grid rerun under a new step rule against the old runs)."""
    entries = []
    for index, (curves_path, steps_path) in enumerate(sets):
        curves = read(curves_path)
        if steps_path == "-":
            steps = steps_from_table(curves)
        elif os.path.isdir(steps_path):
            steps = steps_from_work(steps_path, curves)
        else:
            steps = {r["scene_id"]: r for r in read(steps_path)}
        last = index == len(sets) - 1
        for row in curves:
            run = steps.get(row["scene_id"])
            if run is None or run["status"] != "done":
                continue
            state = (float(row["phi"]), float(row["rho"]), float(row["peclet"] or "nan"),
                     float(row["mu_p"]), row.get("alpha") or "")
            rank = (against_last and last, -float(run["dt"]))
            entries.append((state, scene_forces(curves_path, steps_path, row), row["seed"],
                            (rank, float(run["dt"]), run["dt_limit"], row)))
    runs = defaultdict(list)
    for state, seed, run in labelled(entries):
        runs[(state, seed)].append(run)
    pairs = defaultdict(list)
    for (state, seed), rs in sorted(runs.items()):
        if not against_last:
            rs = distinct_steps(state, seed, rs)
        rs.sort(key=lambda r: r[0])
        _, dt_ref, _, reference = rs[-1]
        for _, dt, limit, run in rs[:-1]:
            key = state + (float(f"{dt:.4g}"), float(f"{dt_ref:.4g}"))
            pairs[key].append((seed, dt, limit, run, reference))
    return pairs


def distinct_steps(state, seed, runs):
    """One run per step of a state and seed: two sets may hold the same run (a flow-curve
    folder's run at the automatic step and a step-convergence grid's), which would otherwise
    count its seed twice. The first set's is kept; a copy whose numbers differ is reported."""
    kept = {}
    for run in runs:
        step = f"{run[1]:.4g}"
        first = kept.setdefault(step, run)
        if first is not run and any(first[3][p] != run[3][p] for p in PARTS):
            print(f"warning: state {state} seed {seed} at dt {step}: two different runs, the first "
                  f"set's kept (eta_r {first[3]['eta_r']} against {run[3]['eta_r']})", file=sys.stderr)
    return list(kept.values())


def verdict(diff, ref, se, a):
    rel = diff / ref if ref else float("nan")
    sig = diff / se if se > 0 else (0.0 if diff == 0 else float("inf"))
    return rel, sig, abs(rel) <= a.tolerance and abs(sig) <= a.sigmas


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--set", nargs=2, action="append", required=True, metavar=("CURVES", "RUNS"),
                    help="flow-curves' per-run table and generate's run table (bins.scenes.csv), "
                         "the grid's work folder (summary.json in each run) or - (the table's "
                         "own dt column)")
    ap.add_argument("--out", help="Markdown tables (printed as well)")
    ap.add_argument("--tolerance", type=float, default=0.05, help="relative tolerance (0.05)")
    ap.add_argument("--sigmas", type=float, default=2.0, help="standard errors (2)")
    ap.add_argument("--against-last", action="store_true",
                    help="compare each run with the last set's run of its state and seed, whatever "
                         "its step (default: with the shortest step)")
    a = ap.parse_args()
    pairs = seed_pairs(a.set, a.against_last)
    per_seed = [
        "| phi | rho | Pe | mu_p | seed | dt (limit) | dt_ref | part | at dt | at dt_ref | difference | / value | / comb. se |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    pooled = [
        "| phi | rho | Pe | mu_p | seeds | dt (limit) | dt_ref | part | at dt | at dt_ref | difference | se (scatter, blocks) | / value | / se | pass |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    summary = [
        "| phi | rho | Pe | mu_p | seeds | dt (limit) | dt_ref | " + " | ".join(PARTS) + " |",
        "|---|---|---|---|---|---|---|" + "---|" * len(PARTS),
    ]
    failures = compared = 0
    for key, seeds in sorted(pairs.items(), key=lambda kv: kv[0][:5] + (-kv[0][5],)):
        phi, rho, pe, mu, label, _, dt_ref = key
        if label:
            phi = f"{phi} ({label})"
        dt = seeds[0][1]
        # The limit that set the step, from a run that records it (not a `-` set's).
        limit = next((seed[2] for seed in seeds if seed[2] != "?"), "?")
        cells = []
        for part in PARTS:
            diffs, block_var, longs, shorts = [], 0.0, [], []
            for seed, seed_dt, seed_limit, long_, short in seeds:
                q, q3 = float(long_[part]), float(short[part])
                se_l, se_s = float(long_[part + "_se"]), float(short[part + "_se"])
                se = math.hypot(se_l, se_s)
                rel, sig, _ = verdict(q - q3, q3, se, a)
                per_seed.append(
                    f"| {phi} | {rho:g} | {pe:g} | {mu:g} | {seed} | {seed_dt:.3e} ({seed_limit}) | {dt_ref:.3e} | {part} | "
                    f"{q:.3f} +- {se_l:.3f} | {q3:.3f} +- {se_s:.3f} | {q - q3:+.3f} | {100 * rel:+.1f} % | {sig:+.1f} |")
                diffs.append(q - q3)
                block_var += se * se
                longs.append(q)
                shorts.append(q3)
            n = len(diffs)
            mean = sum(diffs) / n
            blocks = math.sqrt(block_var) / n
            scatter = statistics.stdev(diffs) / math.sqrt(n) if n >= 2 else float("nan")
            se = max(blocks, scatter) if n >= 2 else blocks
            ref = sum(shorts) / n
            rel, sig, ok = verdict(mean, ref, se, a)
            compared += 1
            failures += not ok
            pooled.append(
                f"| {phi} | {rho:g} | {pe:g} | {mu:g} | {n} | {dt:.3e} ({limit}) | {dt_ref:.3e} | {part} | "
                f"{sum(longs) / n:.3f} | {ref:.3f} | "
                f"{mean:+.3f} | {se:.3f} ({scatter:.3f}, {blocks:.3f}) | {100 * rel:+.1f} % | {sig:+.1f} | "
                f"{'yes' if ok else '**no**'} |")
            cell = f"{100 * rel:+.1f} +- {100 * se / abs(ref) if ref else float('nan'):.1f} %"
            cells.append(cell if ok else f"**{cell}**")
        summary.append(f"| {phi} | {rho:g} | {pe:g} | {mu:g} | {len(seeds)} | {dt:.2e} ({limit}) | "
                       f"{dt_ref:.2e} | "
                       + " | ".join(cells) + " |")
    reference = "the last set's run" if a.against_last else "the shortest of its state"
    text = "\n".join(
        [f"Relative difference, each step against {reference} (dt_ref), pooled over "
         "seeds (bold: beyond 5 % or 2 standard errors):", ""] + summary
        + ["", "Pooled over seeds:", ""] + pooled
        + ["", f"{compared - failures} of {compared} pooled comparisons within {100 * a.tolerance:g} % "
               f"and {a.sigmas:g} standard errors.", "", "Per seed:", ""] + per_seed) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
