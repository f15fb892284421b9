"""solve gives the profile of `suspflow solve` exactly, bands included, with every closure, for
the first validation flow given as a mapping; a homogeneous-shear scene has nothing to
solve."""
import json

import pandas as pd
import pytest

import suspflow
from conftest import exact_csv

FLOW = {
    "name": "validate_ensemble_000",
    "box": {"l_x": 17.0, "l_y": 80.0, "l_z": 17.0},
    "particles": {"phi": 0.54, "stokes": 0.09},
    "fluid": {"profile": "0.1*sin(2*pi*y/L) + 0.2*cos(2*pi*y/L)"},
}


@pytest.mark.parametrize("closure", ["learned", "local", "nonlocal", "extremum"])
def test_solve_matches_the_command(root, run_suspflow, tmp_path, closure):
    scene = tmp_path / "flow.toml"
    scene.write_text(
        'name = "validate_ensemble_000"\n[box]\nl_x = 17.0\nl_y = 80.0\nl_z = 17.0\n'
        "[particles]\nphi = 0.54\nstokes = 0.09\n"
        '[fluid]\nprofile = "0.1*sin(2*pi*y/L) + 0.2*cos(2*pi*y/L)"\n'
    )
    run_suspflow("solve", scene, "--closure", closure, "--out", tmp_path / "out")
    written = exact_csv((tmp_path / "out" / "profile.csv").read_text())
    written["in_domain"] = written["in_domain"] == "true"
    # The local rheology is fitted on the dv model's training data, as the command does.
    solved = suspflow.solve(FLOW, root / "models", closure)
    assert list(solved.columns) == list(written.columns)
    pd.testing.assert_frame_equal(solved, written, check_exact=True)
    assert solved.attrs["residual"] < 1e-9
    # mean(phi_loc) = phi closes the balance.
    assert abs(solved["phi_loc"].mean() - 0.54) < 1e-9
    # The bands hold the solved profile, and summary.json's account of them is the same.
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert solved.attrs["bands"] == summary["bands"]
    for observable in ["u", "phi_loc", "mu"]:
        assert (solved[f"{observable}_lower"] <= solved[observable]).all()
        assert (solved[observable] <= solved[f"{observable}_upper"]).all()


def test_a_shear_scene_has_nothing_to_solve(root):
    with pytest.raises(suspflow.SuspflowError, match="nothing to solve"):
        suspflow.solve(root / "scenes/shear.toml", root / "models")
    with pytest.raises(suspflow.SuspflowError, match="unknown closure"):
        suspflow.solve(FLOW, root / "models", "quadratic")
