"""cross_validate gives the record `suspflow cross-validate` writes to cv.json, every number
equal, on four synthetic profile families of a power law; its errors are the package's
exception classes."""
import json

import pytest

import suspflow
from conftest import power_law_families


@pytest.fixture(scope="module")
def trained(tmp_path_factory, run_suspflow):
    """The families' table and untuned `dv` and `mu` models trained on it by the command."""
    root = tmp_path_factory.mktemp("family_cv")
    data = power_law_families(root / "families.csv")
    models = root / "models"
    run_suspflow(
        "train", "--data", data, "--out", models, "--no-tune", "--force",
        "--mapping", "dv", "--mapping", "mu",
    )
    return data, models


def test_the_record_is_the_commands(trained, run_suspflow, tmp_path):
    data, models = trained
    out = tmp_path / "cv"
    run_suspflow(
        "cross-validate", "--data", data, "--models", models, "--out", out,
        "--mapping", "dv", "--mapping", "mu", "--learning-curve", "1,2", "--draws", "2",
    )
    written = json.loads((out / "cv.json").read_text())
    record = suspflow.cross_validate(
        data, models, ["dv", "mu"], learning_curve=[1, 2], draws=2
    )
    for r in (written, record):
        assert r.pop("seconds") > 0
    assert record == written
    assert [cv["mapping"] for cv in record["mappings"]] == ["dv", "mu"]
    assert len(record["families"]) == 4 and len(record["learning_curves"]) == 2
    # From a DataFrame the same folds give the same errors (the source's name differs).
    framed = suspflow.cross_validate(suspflow.read_dataset(data), models, ["dv"])
    assert framed["mappings"][0]["folds"] == record["mappings"][0]["folds"]
    assert "learning_curves" not in framed


def test_a_table_without_families_is_a_data_error(trained, tmp_path):
    data, models = trained
    table = suspflow.read_dataset(data).drop(columns="profile")
    with pytest.raises(suspflow.DataError, match="profile"):
        suspflow.cross_validate(table, models, ["dv"])


def test_a_model_not_trained_is_named(trained):
    data, models = trained
    with pytest.raises(suspflow.FileError, match="hyper-parameters of `theta`"):
        suspflow.cross_validate(data, models, ["theta"])
