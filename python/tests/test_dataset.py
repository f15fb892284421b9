"""read_dataset and read_ensemble: every cell as the file holds it (numbers exactly, empty
cells as NaN, seeds and replica counts as integers, text columns as strings) and the kind
of table."""
import csv
import math

import pytest

import suspflow


@pytest.mark.parametrize(
    "name, kind",
    [("datasets/validate.csv", "runs"), ("datasets/validate_ensemble.ensemble.csv", "ensemble")],
)
def test_cells_are_read_as_written(root, name, kind):
    frame = suspflow.read_dataset(root / name)
    with open(root / name, newline="") as f:
        rows = list(csv.reader(f))
    assert list(frame.columns) == rows[0]
    assert len(frame) == len(rows) - 1
    assert frame.attrs["kind"] == kind
    for j, column in enumerate(rows[0]):
        values = frame[column].tolist()
        cells = [r[j] for r in rows[1:]]
        if frame[column].dtype == float:
            for value, cell in zip(values, cells):
                assert math.isnan(value) if cell == "" else value == float(cell)
        elif frame[column].dtype == "int64":
            assert column in ("seed", "replicas")
            assert values == [int(c) for c in cells]
        else:
            assert values == cells
    assert frame["profile"].dtype == object and frame["y"].dtype == float
    integer = "seed" if kind == "runs" else "replicas"
    assert frame[integer].dtype == "int64"


def test_read_ensemble_refuses_a_per_run_table(root):
    assert suspflow.read_ensemble(root / "datasets/validate_ensemble.ensemble.csv").attrs["kind"] == "ensemble"
    with pytest.raises(suspflow.DataError, match="not an ensemble table"):
        suspflow.read_ensemble(root / "datasets/validate.csv")
