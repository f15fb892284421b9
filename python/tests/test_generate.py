"""generate runs a grid as `suspflow generate` does: over the command's work folder it runs
nothing and writes the same tables byte for byte; its shards run every run once and give
the command's rows; tables of another grid are refused unless force."""
import csv
import io

import pytest

import suspflow
from conftest import without_code_version

GRID = "tests/grids/tiny.toml"


@pytest.fixture(scope="module")
def command_run(tmp_path_factory, run_suspflow):
    """The grid run by the command: its dataset (with run and ensemble tables) and work."""
    root = tmp_path_factory.mktemp("generate")
    out = root / "bins.csv"
    run_suspflow("generate", GRID, "--out", out, "--jobs", "2", "--threads", "1")
    return out


def test_over_the_commands_runs_nothing_runs_and_the_tables_are_the_same(root, command_run, tmp_path):
    out = tmp_path / "bins.csv"
    ended = []
    counts = suspflow.generate(
        root / GRID, out, work=f"{command_run}.work", progress=ended.append
    )
    assert counts == {"done": 4, "failed": 0, "pending": 0} and ended == []
    assert out.read_bytes() == command_run.read_bytes()
    for suffix in [".scenes.csv", ".ensemble.csv", ".ensemble.json"]:
        ours, theirs = (p.with_name(p.stem + suffix) for p in (out, command_run))
        assert ours.exists() == theirs.exists(), suffix
        assert not ours.exists() or ours.read_bytes() == theirs.read_bytes(), suffix


def test_shards_run_each_run_once_with_the_commands_rows(root, command_run, tmp_path):
    work = tmp_path / "work"
    ended = []
    parts = []
    for i in range(2):
        part = tmp_path / f"part{i}.csv"
        suspflow.generate(
            root / GRID, part, shard=(i, 2), work=work, jobs=2, threads=1, progress=ended.append
        )
        parts.append(part)
    labels = [label for label, how, _ in ended]
    assert sorted(labels) == sorted(set(labels)) and len(labels) == 4
    assert all(how == "finished" for _, how, _ in ended)
    # Shards write no ensemble table.
    assert not any(p.with_name(p.stem + ".ensemble.csv").exists() for p in parts)
    header, *expected = without_code_version(command_run)
    rows = []
    for part in parts:
        part_header, *part_rows = without_code_version(part)
        assert part_header == header
        rows += part_rows
    assert sorted(rows) == sorted(expected)


def test_another_grids_table_is_kept_unless_force(root, tmp_path):
    out = tmp_path / "bins.csv"
    out.write_text("not this grid's\n")
    with pytest.raises(suspflow.FileError, match="force=True"):
        suspflow.generate(root / GRID, out, progress=False)
    assert out.read_text() == "not this grid's\n"


def test_a_bad_shard_is_refused(root, tmp_path):
    with pytest.raises(suspflow.SuspflowError, match="shard|part"):
        suspflow.generate(root / GRID, tmp_path / "bins.csv", shard=(2, 2), progress=False)
