"""flow_curves gives the table `suspflow flow-curves` writes (every number equal) and fits
of the jamming law per convention, on a tiny homogeneous-shear grid the command generated;
its errors are the package's exception classes."""
import numpy as np
import pandas as pd
import pytest

import suspflow
from conftest import exact_csv

GRID = "tests/grids/tiny_shear.toml"


@pytest.fixture(scope="module")
def runs(tmp_path_factory, run_suspflow):
    """The grid run by `suspflow generate` (six short runs, two at a time)."""
    root = tmp_path_factory.mktemp("flow_curves")
    work = root / "runs"
    run_suspflow(
        "generate", GRID, "--out", root / "bins.csv", "--work", work,
        "--jobs", "2", "--threads", "1",
    )
    return work


def test_the_table_is_the_commands(root, runs, run_suspflow, tmp_path):
    out = tmp_path / "report"
    run_suspflow("flow-curves", GRID, "--runs", runs, "--out", out)
    written = exact_csv((out / "flow_curves.csv").read_text())
    table, fits = suspflow.flow_curves(root / GRID, runs)
    assert list(table.columns) == list(written.columns) and len(table) == 6
    for column in written.columns:
        np.testing.assert_array_equal(table[column].to_numpy(), written[column].to_numpy(), column)
    # One fit per convention of the one state; the report states the same numbers.
    assert len(fits) == 4 and pd.isna(fits["error"].iloc[0])
    box = fits.iloc[0]
    assert box["convention"] == "pair stresslets (box)" and box["dt_factor"] == 1.0
    assert pd.isna(box["dt"])
    readme = (out / "README.md").read_text()
    line = (
        f"| pair stresslets (box) | {box.phi_J:.4f} ± {box.phi_J_se:.4f} "
        f"| {box['lambda']:.3f} ± {box.lambda_se:.3f} |"
    )
    assert line in readme, readme


def test_a_grid_without_shear_is_a_scene_error(root, runs):
    with pytest.raises(suspflow.SuspflowError, match="shear_rate"):
        suspflow.flow_curves(root / "tests/grids/tiny.toml", runs)


def test_a_missing_green_kubo_folder_is_a_file_error(root, runs, tmp_path):
    with pytest.raises(suspflow.FileError):
        suspflow.flow_curves(root / GRID, runs, [tmp_path / "nowhere"])


def test_a_folder_given_twice_is_refused_and_a_list_of_one_is_the_folder(root, runs):
    # A grid run in shards (`generate --shard`) has one work folder per shard: `runs` takes
    # them as a list; the same folder twice would count its runs twice.
    table, _ = suspflow.flow_curves(root / GRID, [runs])
    alone, _ = suspflow.flow_curves(root / GRID, runs)
    pd.testing.assert_frame_equal(table, alone)
    with pytest.raises(suspflow.FileError, match="finished here and in"):
        suspflow.flow_curves(root / GRID, [runs, runs])
