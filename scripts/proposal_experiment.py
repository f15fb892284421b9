#!/usr/bin/env python3
"""Does simulating the scenes `suspflow propose` ranks first narrow the bands more than
simulating as many candidates drawn at random? (issue 52, item 4)

1. `propose` ranks the candidates of --candidates with the models of --models and writes its
   batch of --top (picked to cover the widest bands of all candidates, the arm `proposed`);
   beside it the --top widest by their own bands alone (`widest`, what `propose` wrote
   before it picked batches) and --draws sets of as many candidates drawn at random
   (seeded, `random<k>`).
2. Each arm's scenes are run by `generate` (runs of 1-4 minutes, three seeds:
   grids/propose_candidates.toml), except those an earlier arm already ran: the same scene
   file and seeds, so the same simulations, whose runs are copied; then merged with the
   training runs (--train-runs) into a training table per arm.
3. Each arm's table trains the four mappings with the models' own hyper-parameters (`train
   --params-from`), which also calibrates their intervals and the bands of `solve`.
4. `propose` ranks the candidates again with each arm's models: the mean relative band
   width over all candidates, and over the candidates no arm added, before and after.

Everything is written under --out (grids, datasets, models, rankings, README.md); each
step is skipped when its output is there, so an interrupted run resumes.

    nice -n 5 python3 scripts/proposal_experiment.py --suspflow target/release/suspflow \
        --models models --train-runs datasets/wide_plugs.csv \
        --candidates grids/propose_candidates.toml --out reports/proposal
"""
import argparse
import csv
import json
import math
import os
import random
import re
import subprocess
import sys

CLOSURE = "learned"


def run(cmd, log=None, tolerate=False):
    print("+", " ".join(cmd), flush=True)
    out = subprocess.run(cmd, capture_output=True, text=True)
    if log:
        with open(log, "w") as f:
            f.write(out.stdout + out.stderr)
    if out.returncode != 0 and tolerate:
        print(f"  exit status {out.returncode}, going on with what finished", flush=True)
    elif out.returncode != 0:
        sys.exit(f"failed ({out.returncode}): {' '.join(cmd)}\n{out.stderr[-2000:]}")
    return out.stdout


RANK_LINE = re.compile(
    r"^\s*(\d+) ([ *])(\S+) (.*) \(L_y (\S+), phi (\S+)\): "
    r"(?:score (\S+) \(relative widths u (\S+), phi_loc (\S+), mu (\S+)\)|not solved)"
)
BATCH_LINE = re.compile(r"in the order (.*)\): ")


def ranking(text):
    """The candidates of `propose`'s printed ranking, id -> (profile, phi, score, widths),
    and the ids of its batch in the order picked."""
    rows = {}
    for line in text.splitlines():
        m = RANK_LINE.match(line)
        if not m:
            continue
        score = float(m.group(7)) if m.group(7) else float("nan")
        widths = [float(m.group(k)) if m.group(k) else float("nan") for k in (8, 9, 10)]
        rows[m.group(3)] = (m.group(4), float(m.group(6)), score, widths)
    batch = BATCH_LINE.search(text)
    return rows, batch.group(1).split(", ") if batch else []


def propose(args, models, out_grid, log, top):
    if not os.path.exists(log):
        text = run(
            [args.suspflow, "propose", args.candidates, "--models", models, "--closure",
             CLOSURE, "--top", str(top), "--out", out_grid, "--force"],
        )
        with open(log, "w") as f:
            f.write(text)
    with open(log) as f:
        return ranking(f.read())[0]


def proposed_batch(log):
    """The ids of the batch `propose` picked, in its log `log`, in the order picked."""
    with open(log) as f:
        return ranking(f.read())[1]


def reuse_runs(args, arm, cases, earlier):
    """Writes `datasets/<arm>_reused.csv` (and its scenes table) with the runs of the
    `cases` (profile, phi) that one of the `earlier` arms ran; returns the cases left to
    generate."""
    runs, scenes, left = [], [], []
    header = scene_header = None
    for case in cases:
        for other in earlier:
            base = os.path.join(args.out, "datasets", other)
            with open(base + ".scenes.csv") as f:
                s_rows = list(csv.DictReader(f))
            ids = {r["scene_id"] for r in s_rows
                   if (r["profile"], float(r["phi"])) == (case[0], float(case[1]))}
            if not ids:
                continue
            with open(base + ".csv") as f:
                reader = csv.DictReader(f)
                header = reader.fieldnames
                runs += [r for r in reader if r["scene_id"] in ids]
            scene_header = list(s_rows[0].keys())
            scenes += [r for r in s_rows if r["scene_id"] in ids]
            break
        else:
            left.append(case)
    if runs:
        path = os.path.join(args.out, "datasets", f"{arm}_reused")
        for name, head, rows in ((path + ".csv", header, runs),
                                 (path + ".scenes.csv", scene_header, scenes)):
            with open(name, "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=head, lineterminator="\n")
                w.writeheader()
                w.writerows(rows)
    return left


def random_grid(candidates_grid, chosen_cases, name, path):
    """The candidate grid with its cases and phi fixed to the chosen (profile, phi) pairs."""
    with open(candidates_grid) as f:
        text = f.read()
    head = text.split("[vary]")[0]
    head = re.sub(r'^name = ".*"$', f'name = "{name}"', head, flags=re.M)
    cases = "".join(
        f'\n[[cases]]\n"fluid.profile" = "{p}"\n"particles.phi" = {phi}\n'
        for p, phi in chosen_cases
    )
    with open(path, "w") as f:
        f.write(head + cases)


def margins(models):
    """The learned closure's 90 % band margins (u, phi_loc, mu) of a models folder's bands.json."""
    with open(os.path.join(models, "bands.json")) as f:
        bands = json.load(f)
    closure = next(c for c in bands["closures"] if c["closure"] == CLOSURE)
    out = []
    for scores in closure["scores"]:
        rank = math.ceil((len(scores) + 1) * 0.9)
        out.append(scores[rank - 1] if rank <= len(scores) else float("inf"))
    return out


def mu_noise(table):
    """The mean over a table's scenes of mu's own noise, ||mu_se|| / ||mu||."""
    with open(table) as f:
        rows = [r for r in csv.DictReader(f) if r["mu"] and r["mu_se"]]
    scenes = {}
    for r in rows:
        scenes.setdefault(r["scene_id"], []).append(r)
    return mean([
        math.sqrt(sum(float(r["mu_se"]) ** 2 for r in rs) / sum(float(r["mu"]) ** 2 for r in rs))
        for rs in scenes.values()
    ])


def verdict(summary, arms):
    """The change of each arm's mean band width against before, over all candidates and over
    those the arm did not add, and how the proposed arm ranks among the random ones."""
    before = summary[0]["all"]
    change = {}
    for arm, s in zip(arms, summary[1:]):
        change[arm] = (s["all"] / before - 1, s["not_added_by_arm"] / s["not_added_by_arm_before"] - 1)
    randoms = [a for a in arms if a.startswith("random")]
    out = ["\nChange of the mean relative band width against the shipped models, over all "
           "candidates / over those the arm did not add:\n"]
    out += [f"- `{a}`: {100 * c[0]:+.1f} % / {100 * c[1]:+.1f} %" for a, c in change.items()]
    for k, what in enumerate(["all candidates", "the candidates each arm did not add"]):
        r = [change[a][k] for a in randoms]
        for arm in [a for a in ("proposed", "widest") if a in change and r]:
            p = change[arm][k]
            beaten = sum(1 for x in r if p < x)
            out.append(
                f"\nOver {what}: `{arm}` {100 * p:+.1f} %, the {len(r)} random draws "
                f"{100 * min(r):+.1f} to {100 * max(r):+.1f} % (mean {100 * mean(r):+.1f} %); "
                f"`{arm}` narrowed the bands more than {beaten} of {len(r)} draws."
            )
    return out


def code_versions(args, arms):
    """Which code made the added runs (their datasets' `code_version`), the retrained models
    and the shipped ones (their `bands.json`): (what, versions) pairs."""
    runs, models = [], []
    for arm in arms:
        with open(os.path.join(args.out, "datasets", f"{arm}.csv")) as f:
            runs += {r["code_version"] for r in csv.DictReader(f)}
        with open(os.path.join(args.out, "models", arm, "bands.json")) as f:
            models.append(json.load(f).get("code_version", "?"))
    with open(os.path.join(args.models, "bands.json")) as f:
        shipped = json.load(f).get("code_version", "?")
    return [("added runs", ", ".join(sorted(set(runs)))),
            ("retrained models and rankings", ", ".join(sorted(set(models)))),
            ("shipped models", shipped)]


def mean(values):
    values = [v for v in values if v == v]
    return sum(values) / len(values) if values else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--suspflow", default="target/release/suspflow")
    ap.add_argument("--models", default="models")
    ap.add_argument("--train-runs", default="datasets/wide_plugs.csv")
    ap.add_argument("--candidates", default="grids/propose_candidates.toml")
    ap.add_argument("--out", default="reports/proposal")
    ap.add_argument("--top", type=int, default=4)
    ap.add_argument("--draws", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    before = propose(
        args, args.models, os.path.join(args.out, "proposed.toml"),
        os.path.join(args.out, "ranking_before.txt"), args.top,
    )
    ranked = sorted(before.items(), key=lambda kv: -kv[1][2] if kv[1][2] == kv[1][2] else -1e9)
    batch = proposed_batch(os.path.join(args.out, "ranking_before.txt"))
    arms = {
        "proposed": [(before[i][0], before[i][1]) for i in batch],
        "widest": [(v[0], v[1]) for _, v in ranked[: args.top]],
    }
    rng = random.Random(args.seed)
    pool = [(v[0], v[1]) for _, v in sorted(before.items())]
    for d in range(args.draws):
        arms[f"random{d + 1}"] = rng.sample(pool, args.top)
    # The random draws and the widest ran first: the proposed batch reuses their runs.
    order = [a for a in arms if a != "proposed"] + ["proposed"]
    for k, arm in enumerate(order):
        cases = arms[arm]
        grid = os.path.join(args.out, f"{arm}.toml")
        if arm != "proposed":
            random_grid(args.candidates, cases, arm, grid)
        data = os.path.join(args.out, "datasets", f"{arm}.csv")
        os.makedirs(os.path.dirname(data), exist_ok=True)
        if not os.path.exists(data):
            left = reuse_runs(args, arm, cases, order[:k])
            parts = []
            if len(left) < len(cases):
                parts.append(os.path.join(args.out, "datasets", f"{arm}_reused.csv"))
            if left:
                new_grid = os.path.join(args.out, f"{arm}_new.toml")
                random_grid(args.candidates, left, f"{arm}_new", new_grid)
                new = os.path.join(args.out, "datasets", f"{arm}_new.csv")
                if not os.path.exists(new):
                    run([args.suspflow, "generate", new_grid, "--out", new, "--jobs", "2",
                         "--threads", "1"],
                        log=os.path.join(args.out, f"generate_{arm}.log"), tolerate=True)
                parts.append(new)
            run([args.suspflow, "merge", *parts, "--out", data])
            with open(data.replace(".csv", ".scenes.csv"), "w") as f:
                for n, part in enumerate(parts):
                    with open(part.replace(".csv", ".scenes.csv")) as g:
                        lines = g.readlines()
                    f.writelines(lines if n == 0 else lines[1:])
        merged = os.path.join(args.out, "datasets", f"train_{arm}.csv")
        if not os.path.exists(merged):
            run([args.suspflow, "merge", args.train_runs, data, "--out", merged])
        models = os.path.join(args.out, "models", arm)
        if not os.path.exists(os.path.join(models, "bands.json")):
            run([args.suspflow, "train", "--data", merged.replace(".csv", ".ensemble.csv"),
                 "--out", models, "--params-from", args.models, "--force"],
                log=os.path.join(args.out, f"train_{arm}.log"))
    after = {
        arm: propose(args, os.path.join(args.out, "models", arm),
                     os.path.join(args.out, f"reranked_{arm}.toml"),
                     os.path.join(args.out, f"ranking_{arm}.txt"), args.top)
        for arm in arms
    }
    added = {c for cases in arms.values() for c in cases}
    untouched = [i for i, v in before.items() if (v[0], v[1]) not in added]
    rows = [("before (shipped models)", None, before)] + [
        (f"after adding `{a}`", a, r) for a, r in after.items()
    ]
    summary = []
    lines = [
        "# Proposed scenes against random ones\n",
        f"Made by `scripts/proposal_experiment.py` (its docstring gives the method), closure "
        f"`{CLOSURE}`, 90 % bands, {args.top} scenes per arm, {args.draws} random draws (seed "
        f"{args.seed}). Score: a candidate's mean relative band width of u, phi_loc and mu "
        f"(`propose`); means over all {len(before)} candidates, over the "
        f"{len(untouched)} that no arm added, and over the {len(before) - args.top} or more "
        f"that the arm itself did not add (in brackets the same candidates before). u, "
        f"phi_loc, mu: the mean relative widths over all candidates.\n",
        "| models | all candidates | not added by any arm | not added by this arm | u | phi_loc | mu |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, arm, r in rows:
        all_mean = mean([v[2] for v in r.values()])
        rest = mean([r[i][2] for i in untouched if i in r])
        others = [i for i, v in before.items() if arm and (v[0], v[1]) not in arms[arm]]
        own = mean([r[i][2] for i in others])
        own_before = mean([before[i][2] for i in others])
        w = [mean([v[3][k] for v in r.values()]) for k in range(3)]
        summary.append({"models": label, "all": all_mean, "not_added": rest,
                        "not_added_by_arm": own, "not_added_by_arm_before": own_before,
                        "widths": w})
        own_text = f"{own:.4f} ({own_before:.4f})" if arm else "-"
        lines.append(
            f"| {label} | {all_mean:.4f} | {rest:.4f} | {own_text} | "
            f"{w[0]:.4f} | {w[1]:.4f} | {w[2]:.4f} |"
        )
    lines += verdict(summary, list(arms))
    shipped = margins(args.models)
    lines += [
        "\nWhere the change comes from: a band is its margin (from the held-out scores, "
        "`bands.json`) times each bin's scale (from the closure's intervals). The learned "
        "closure's 90 % margins of u, phi_loc and mu, the mean relative widths over all "
        "candidates had the margins stayed the shipped ones (the scales' change alone), and "
        "the added scenes' own mu noise (`||mu_se|| / ||mu||`, mean over their scenes):\n",
        "| models | margins u, phi_loc, mu | widths at the shipped margins | mean of them | "
        "added scenes' mu noise |",
        "|---|---|---|---|---|",
        f"| shipped | {', '.join(f'{m:.3f}' for m in shipped)} | "
        + ", ".join(f"{mean([v[3][k] for v in before.values()]):.4f}" for k in range(3))
        + f" | {mean([v[2] for v in before.values()]):.4f} | "
        f"{mu_noise(args.train_runs.replace('.csv', '.ensemble.csv')):.3f} (training) |",
    ]
    for arm, r in after.items():
        m = margins(os.path.join(args.out, "models", arm))
        at = [mean([v[3][k] * shipped[k] / m[k] for v in r.values()]) for k in range(3)]
        noise = mu_noise(os.path.join(args.out, "datasets", f"{arm}.ensemble.csv"))
        lines.append(f"| `{arm}` | {', '.join(f'{x:.3f}' for x in m)} | "
                     + ", ".join(f"{x:.4f}" for x in at) + f" | {mean(at):.4f} | {noise:.3f} |")
    lines.append("\nScenes per arm (runs that reached no steady state are left out of the "
                 "training table; `datasets/<arm>.scenes.csv` says why):\n")
    for arm, cases in arms.items():
        with open(os.path.join(args.out, "datasets", f"{arm}.scenes.csv")) as f:
            status = [r["status"] for r in csv.DictReader(f)]
        lines.append(f"- `{arm}` ({status.count('done')} of {len(status)} runs done): "
                     + "; ".join(f"`{p}` at phi {phi}" for p, phi in cases))
    lines += [
        "\nMade, and re-made, by the command below: a step whose output exists is skipped. The "
        "added runs are kept (`datasets/<arm>.csv`, with their run and ensemble tables), so "
        "from a checkout it merges, trains and ranks again, and simulates nothing:\n",
        "```sh",
        "nice -n 5 python3 " + " ".join(sys.argv),
        "```\n",
        "Code: " + "; ".join(
            f"{what} {version}" for what, version in code_versions(args, list(arms))
        ) + ".",
    ]
    with open(os.path.join(args.out, "README.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"arms": {a: c for a, c in arms.items()}, "summary": summary}, f, indent=2)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
