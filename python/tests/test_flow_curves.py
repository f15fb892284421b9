"""flow_curves gives the table `suspflow flow-curves` writes (every number equal) and fits
of the jamming law per convention, on a tiny homogeneous-shear grid the command generated;
its errors are the package's exception classes."""
import shutil

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


def test_a_table_with_part_of_the_grid_run_again_is_the_commands(root, runs, run_suspflow, tmp_path):
    # An earlier table whose lines are all marked "old", and two of the grid's runs copied
    # into a folder of their own (part of the grid run again): only those two lines take
    # the runs' code version, every line keeps its place and numbers (the same code ran
    # both), and every number is the command's `--table ... --runs ...`.
    first = tmp_path / "first"
    run_suspflow("flow-curves", GRID, "--runs", runs, "--out", first)
    lines = (first / "flow_curves.csv").read_text().splitlines()
    k = lines[0].split(",").index("code_version")
    marked = [lines[0]] + [
        ",".join("old" if j == k else c for j, c in enumerate(line.split(",")))
        for line in lines[1:]
    ]
    earlier_csv = tmp_path / "earlier.csv"
    earlier_csv.write_text("\n".join(marked) + "\n")
    earlier = exact_csv(earlier_csv.read_text())
    again = tmp_path / "again"
    again.mkdir()
    copied = sorted(p for p in runs.iterdir() if p.is_dir())[:2]
    for run in copied:
        shutil.copytree(run, again / run.name)
    rerun = {run.name.split("_seed")[0] for run in copied}
    out = tmp_path / "updated"
    run_suspflow("flow-curves", GRID, "--table", earlier_csv, "--runs", again, "--out", out)
    written = exact_csv((out / "flow_curves.csv").read_text())
    table, fits = suspflow.flow_curves(root / GRID, again, table=earlier_csv)
    pd.testing.assert_frame_equal(table, written)
    assert len(table) == len(earlier) == 6
    assert list(table["scene_id"]) == list(earlier["scene_id"])
    assert set(table.loc[table["code_version"] != "old", "scene_id"]) == rerun
    numbers = [c for c in table.columns if c != "code_version"]
    pd.testing.assert_frame_equal(table[numbers], earlier[numbers])
    # The table alone (no runs) gives the same curves: its lines, and the fits of the runs.
    alone, alone_fits = suspflow.flow_curves(root / GRID, [], table=earlier_csv)
    pd.testing.assert_frame_equal(alone, exact_csv(earlier_csv.read_text()))
    _, from_runs = suspflow.flow_curves(root / GRID, runs)
    pd.testing.assert_frame_equal(alone_fits, from_runs)
    pd.testing.assert_frame_equal(fits, from_runs)


def test_the_table_of_another_grid_is_a_scene_error(root, runs, run_suspflow, tmp_path):
    run_suspflow("flow-curves", GRID, "--runs", runs, "--out", tmp_path / "first")
    with pytest.raises(suspflow.SuspflowError, match="does not have"):
        suspflow.flow_curves(root / "tests/grids/tiny.toml", [], table=tmp_path / "first" / "flow_curves.csv")
