#!/usr/bin/env python3
"""Steps per strain and cost of grids under two builds of `suspflow` (issue 50 item 5): each
grid's runs as `suspflow generate GRID --check` lists them (N, dt, particle-steps), with
one binary and with another (for instance a build of d2f2153, the last with the old
Brownian step rule, against the current one). This script only runs the two checks and
tabulates them; the step rule itself is in sim/src/input/timestep.rs.

The particle-steps are `--check`'s: equilibration up to the grid's `run.max_strain` (the
budget, an upper bound: most runs reach their steady state well before it) plus the
averaging; for the new build also the least, after the shortest warm-up (four windows, what
a grid with a loose `run.steady_chi2` takes). Core-hours divide them by `--rate`
particle-steps per second per core.

    python3 scripts/grid_costs.py --old OLD_BIN --new target/release/suspflow \\
        --rate 1e5 grids/brownian_*.toml grids/mixtures_*.toml --out reports/brownian/costs.md
"""
import argparse
import re
import subprocess
import sys

RATE_PER_SHEAR = re.compile(r"^([-+0-9.eE]+)\*\(y-L/2\)$")


def check(binary, grid):
    """Per run of the grid: (scene, n, dt, particle-steps at most, at least or None, shear rate
    or None). The columns are found by the header's names: builds before 99dbc22 print one
    `part-steps` column (the most), later ones `least` and `most`."""
    out = subprocess.run([binary, "generate", grid, "--out", "/tmp/grid_costs_unused/bins.csv", "--check"],
                         capture_output=True, text=True)
    if out.returncode != 0:
        last = [l for l in out.stderr.splitlines() if l.startswith("error")][-1:] or [out.stderr[-300:]]
        print(f"{grid}: {binary} refuses it: {last[0].strip()}", file=sys.stderr)
        return None
    runs = []
    header = None
    for line in out.stdout.splitlines():
        f = line.split()
        if f[:1] == ["scene"]:
            header = {name: k for k, name in enumerate(f)}
            continue
        if header and len(f) == len(header) and f[1].isdigit() and f[2].isdigit():
            most = float(f[header["most" if "most" in header else "part-steps"]])
            least = float(f[header["least"]]) if "least" in header else None
            m = RATE_PER_SHEAR.match(f[header["profile"]])
            runs.append((f[0], int(f[2]), float(f[header["dt"]]), most, least,
                         float(m.group(1)) if m else None))
    return runs


def shown(x, spec):
    """`x` formatted by `spec`, or "refused" for the NaN of a grid the old build refuses."""
    return "refused" if x != x else format(x, spec)


def span(values, fmt):
    if any(v != v for v in values):
        return "refused"
    lo, hi = min(values), max(values)
    return fmt(lo) if abs(hi - lo) <= 1e-9 * abs(hi) else f"{fmt(lo)} - {fmt(hi)}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--old", required=True, help="the binary of the old rule")
    ap.add_argument("--new", required=True, help="the binary of the new rule")
    ap.add_argument("--rate", type=float, default=1e5, help="particle-steps per second per core")
    ap.add_argument("--out", help="Markdown table (printed as well)")
    ap.add_argument("grids", nargs="+")
    a = ap.parse_args()
    sci = lambda x: f"{x:.2e}"
    whole = lambda x: f"{x:,.0f}"
    lines = [
        f"| grid | runs | dt old | dt new | steps per strain old | new | particle-steps old | new | new / old | core-h old | core-h new | core-h new, least |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for grid in a.grids:
        old, new = check(a.old, grid), check(a.new, grid)
        if new is None:
            continue
        if old is None:  # a scene beyond the old build's limits
            old = [(r[0], r[1], float("nan"), float("nan"), None, r[5]) for r in new]
        if [r[0] for r in old] != [r[0] for r in new]:
            print(f"skipped {grid}: the two builds list different runs", file=sys.stderr)
            continue
        ps_old = sum(r[3] for r in old)
        ps_new = sum(r[3] for r in new)
        least_new = sum(r[4] for r in new) if all(r[4] is not None for r in new) else None
        sheared = [(o, n) for o, n in zip(old, new) if o[5]]
        per_strain = (lambda rs, k: span([1.0 / (r[5] * r[2]) for r in rs], whole)) if sheared else None
        name = grid.rsplit("/", 1)[-1].removesuffix(".toml")
        lines.append(
            f"| {name} | {len(old)} | {span([r[2] for r in old], sci)} | {span([r[2] for r in new], sci)} | "
            f"{per_strain([o for o, _ in sheared], 0) if sheared else '-'} | "
            f"{per_strain([n for _, n in sheared], 0) if sheared else '-'} | "
            f"{shown(ps_old, '.2e')} | {ps_new:.2e} | {shown(ps_new / ps_old, '.2f')} | "
            f"{shown(ps_old / a.rate / 3600, '.1f')} | {ps_new / a.rate / 3600:.1f} | "
            f"{'-' if least_new is None else f'{least_new / a.rate / 3600:.1f}'} |")
    text = "\n".join(lines) + "\n"
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
