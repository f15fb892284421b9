#!/usr/bin/env python3
"""Where a flow curve has its viscosity minimum (thesis Fig. 5.3; reports/mixtures/README.md):
for each composition (alpha, phi, mu_p) of one or more `suspflow flow-curves` tables
(flow_curves.csv), eta_r against log10 Pe_c (the mean over seeds at each Pe_c, its standard
error from their spread, or a single run's block error), and the vertex of the parabola in
log10 Pe_c through the lowest point and its two neighbours. Its 16-84 % range comes from
20000 draws of every point within its error (normal, seeded: the same tables give the same
range), each draw taking its own lowest point; draws whose lowest point is at an end of the
curve, or whose parabola opens downwards, have no interior minimum and are counted. The
minimum in Pe_cg is the same vertex times the composition's Pe_cg / Pe_c (a_cg / a_c).
Nothing else is computed: every value is the flow-curves table's.

    python3 scripts/flow_curve_minimum.py reports/mixtures/collapse/flow_curves.csv
"""
import argparse
import csv
import math
import random
import statistics
import sys
from collections import defaultdict

DRAWS = 20000


def vertex(xs, ys):
    """The vertex x of the parabola through three points, or None if it opens downwards."""
    (x0, x1, x2), (y0, y1, y2) = xs, ys
    d01 = (y1 - y0) / (x1 - x0)
    d12 = (y2 - y1) / (x2 - x1)
    curvature = (d12 - d01) / (x2 - x0)
    if curvature <= 0:
        return None
    # y = y0 + d01 (x - x0) + curvature (x - x0) (x - x1): zero slope at the vertex.
    return (x0 + x1) / 2 - d01 / (2 * curvature)


def minimum(xs, ys):
    """The vertex through the lowest interior point of (xs, ys) and its neighbours."""
    k = min(range(len(ys)), key=ys.__getitem__)
    if k == 0 or k == len(ys) - 1:
        return None
    return vertex(xs[k - 1:k + 2], ys[k - 1:k + 2])


def curves(paths):
    """{(alpha, phi, mu_p): [(log10 Pe_c, Pe_cg / Pe_c, eta_r, se)]} sorted by Pe_c."""
    runs = defaultdict(list)
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                if not r.get("alpha") or not r.get("peclet_c"):
                    continue
                key = (float(r["alpha"]), float(r["phi"]), float(r["mu_p"]))
                pe = float(r["peclet_c"])
                runs[key, pe].append((float(r["eta_r"]), float(r["eta_r_se"]),
                                      float(r["peclet_cg"]) / pe))
    out = defaultdict(list)
    for (key, pe), rs in runs.items():
        etas = [e for e, _, _ in rs]
        se = statistics.stdev(etas) / math.sqrt(len(etas)) if len(etas) > 1 else rs[0][1]
        out[key].append((math.log10(pe), rs[0][2], statistics.mean(etas), se))
    return {k: sorted(v) for k, v in out.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("tables", nargs="+", help="flow_curves.csv files of mixture grids")
    args = parser.parse_args()
    found = curves(args.tables)
    if not found:
        sys.exit("no mixture rows with a Peclet number in " + ", ".join(args.tables))
    rng = random.Random(1)
    print("| alpha | phi | mu_p | Pe_c points | minimum Pe_c (16-84 %) | Pe_cg (16-84 %) | "
          "draws without an interior minimum |")
    print("|---|---|---|---|---|---|---|")
    for (alpha, phi, mu_p), points in sorted(found.items()):
        xs = [p[0] for p in points]
        ratio = points[0][1]
        pes = ", ".join(f"{10 ** x:.3g}" for x in xs)
        central = minimum(xs, [p[2] for p in points]) if len(points) >= 3 else None
        if central is None:
            print(f"| {alpha:g} | {phi:g} | {mu_p:g} | {pes} | no interior minimum | | |")
            continue
        drawn, missed = [], 0
        for _ in range(DRAWS):
            v = minimum(xs, [rng.gauss(p[2], p[3]) for p in points])
            if v is None:
                missed += 1
            else:
                drawn.append(v)
        drawn.sort()
        lo, hi = (drawn[int(q * (len(drawn) - 1))] for q in (0.16, 0.84))
        print(f"| {alpha:g} | {phi:g} | {mu_p:g} | {pes} | {10 ** central:.3g} "
              f"({10 ** lo:.3g}-{10 ** hi:.3g}) | {ratio * 10 ** central:.3g} "
              f"({ratio * 10 ** lo:.3g}-{ratio * 10 ** hi:.3g}) | {missed} of {DRAWS} |")


if __name__ == "__main__":
    main()
