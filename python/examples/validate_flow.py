"""Solves the two validation flows of the seeds (docs/physics.md section 8: phi = 0.54,
`0.1 sin(2 pi y/L) + 0.2 cos(2 pi y/L)` at L_y = 80 and `0.1 sin(2 pi y/L)^3` at L_y = 100)
from their forcing alone, with the learned `dv` closure and the local rheology, and plots
u, phi_loc and mu along y against the simulated ensemble means (3 seeds each, error bars of
one standard error between the replicas) of datasets/validate_ensemble.ensemble.csv.

    python3 python/examples/validate_flow.py [OUT.png]    (default validate_flow.png)
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import suspflow  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
MODELS = ROOT / "models"
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "validate_flow.png")

simulated = suspflow.read_ensemble(ROOT / "datasets" / "validate_ensemble.ensemble.csv")
scenes = simulated.groupby("scene_id", sort=True)
columns = [("u", "u (a / time)"), ("phi_loc", "phi_loc"), ("mu", "mu")]
fig, axes = plt.subplots(len(scenes), len(columns), figsize=(13, 3.6 * len(scenes)), squeeze=False)
for row, (scene_id, rows) in enumerate(scenes):
    first = rows.iloc[0]
    # The scene as a mapping: the same keys as a scene file (grids/validate_ensemble.toml).
    scene = {
        "name": scene_id,
        "box": {"l_x": 17.0, "l_y": float(first["L_y"]), "l_z": 17.0},
        "particles": {"phi": float(first["phi"]), "stokes": 0.09},
        "fluid": {"profile": first["profile"]},
    }
    solved = {c: suspflow.solve(scene, MODELS, c) for c in ["learned", "local"]}
    for col, (name, label) in enumerate(columns):
        ax = axes[row][col]
        ax.errorbar(rows["y"], rows[name], yerr=rows[f"{name}_se"], fmt="o", ms=3,
                    color="black", label=f"simulated ({int(first['replicas'])} seeds)")
        for closure, style in [("learned", "-"), ("local", "--")]:
            s = solved[closure]
            ax.plot(s["y"], s[name], style, label=f"solve, {closure} closure")
        ax.set_xlabel("y (a)")
        ax.set_ylabel(label)
        if col == 0:
            ax.set_title(f"{first['profile']}, L_y = {first['L_y']:g}", loc="left", fontsize=10)
    axes[row][0].legend(fontsize=8)
    for closure, s in solved.items():
        err = ((s["u"] - rows["u"].to_numpy()) ** 2).sum() ** 0.5 / (rows["u"] ** 2).sum() ** 0.5
        print(f"{scene_id} {closure:>7}: {s.attrs['iterations']} Newton iterations, "
              f"P = {s.attrs['pressure']:.4f}, relative L2 error of u {100 * err:.1f} %")
fig.tight_layout()
fig.savefig(out, dpi=90)
print(f"figure: {out}")
