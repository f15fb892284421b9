#!/usr/bin/env python3
"""The viscosity table of colloid-grain mixtures (issue 29): the mixture rows of one or
more `suspflow flow-curves` tables (flow_curves.csv, whose last columns carry a mixture's
composition and Peclet numbers), reduced to the columns the mixture study compares with
the thesis, sorted by alpha, phi, friction, Pe_c, seed, density, step, contacts and code
version; a run found in two tables (the same scene, seed, density, step and contacts in two
grids, the same bits) is kept once, and runs of one state by two codes that drew other
random numbers are both kept. Nothing is computed here: every value is the flow-curves
table's. Tables written before flow-curves recorded each run's `rho`, `dt` and
`code_version` leave those empty and name, as the code version, the commit that added the
table (the runs' code is that commit's or older); their contacts (`k_n`, `xi_min`) are
those `flow-curves --table` writes again from the grid.

    python3 scripts/mixture_table.py reports/mixtures/pe1/flow_curves.csv \
        reports/mixtures/grains_pe/flow_curves.csv --out reports/mixtures/viscosity.csv
"""
import argparse
import csv
import os
import subprocess
import sys

COLUMNS = [
    "alpha", "alpha_actual", "phi", "phi_actual", "peclet_c", "peclet_cg", "mu_p", "seed",
    "n_particles", "eta_r", "eta_r_se", "eta_r_contact", "eta_r_contact_se",
    "eta_r_hydrodynamic", "eta_r_hydrodynamic_se", "eta_r_brownian", "eta_r_brownian_se",
    "scene_id",
]
# Columns of newer flow-curves tables: the particle density, the step, the code version and
# the contacts (the normal stiffness and the lubrication's inner gap).
RECORDED = ["rho", "dt", "code_version", "k_n", "xi_min"]


def table_commit(path):
    """The commit that added `path`, as `git log` names it ("" outside a repository)."""
    out = subprocess.run(["git", "log", "--diff-filter=A", "--format=%h", "--", path],
                         capture_output=True, text=True, check=False)
    commits = out.stdout.split()
    return commits[-1] if commits else ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("tables", nargs="+", help="flow_curves.csv files of mixture grids")
    parser.add_argument("--out", required=True, help="the table to write")
    parser.add_argument("--force", action="store_true", help="replace an existing --out")
    args = parser.parse_args()
    if os.path.exists(args.out) and not args.force:
        sys.exit(f"{args.out} exists; give --force to replace it")
    rows = []
    for path in args.tables:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in COLUMNS if c not in reader.fieldnames]
            if missing:
                sys.exit(f"{path}: no column(s) {', '.join(missing)} (not a flow-curves table "
                         "of this version?)")
            table = [r for r in reader if r["alpha"] != ""]
            if not table:
                sys.exit(f"{path}: no mixture rows (empty `alpha`)")
            unrecorded = None
            for r in table:
                row = {c: r.get(c) or "" for c in COLUMNS + RECORDED}
                if not row["code_version"]:
                    unrecorded = unrecorded or f"not recorded (table of {table_commit(path)})"
                    row["code_version"] = unrecorded
                rows.append(row)
    # A run in two grids (the same scene, seed, density and step) is one run: identical
    # bits, kept once. Runs of the same state by codes that draw other numbers (a new noise
    # stream) differ and are kept, each with its code version; two of the same code that
    # differ are an error.
    unique = {}
    for r in rows:
        key = (r["alpha"], r["phi"], r["mu_p"], r["peclet_c"], r["seed"], r["n_particles"],
               r["rho"], r["dt"], r["k_n"], r["xi_min"])
        same = unique.setdefault(key, [])
        if any(u["eta_r"] == r["eta_r"] for u in same):
            continue
        clash = [u for u in same if u["code_version"] == r["code_version"]]
        if clash:
            sys.exit(f"two runs of alpha {key[0]}, phi {key[1]}, mu_p {key[2]}, Pe_c {key[3]}, "
                     f"seed {key[4]}, rho {key[6]}, dt {key[7]}, k_n {key[8]}, xi_min {key[9]} "
                     f"by code {r['code_version']} differ: eta_r {clash[0]['eta_r']} and "
                     f"{r['eta_r']}")
        same.append(r)
    rows = [r for same in unique.values() for r in same]
    # Runs without Brownian forces have no Peclet number (infinite): last of their state.
    rows.sort(key=lambda r: (float(r["alpha"]), float(r["phi"]), float(r["mu_p"]),
                             float(r["peclet_c"] or "inf"), int(r["seed"]),
                             float(r["rho"] or 0), float(r["dt"] or 0),
                             float(r["k_n"] or 0), float(r["xi_min"] or 0), r["code_version"]))
    with open(args.out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS + RECORDED)
        writer.writeheader()
        writer.writerows(rows)
    print(f"{args.out}: {len(rows)} rows from {len(args.tables)} table(s)")


if __name__ == "__main__":
    main()
