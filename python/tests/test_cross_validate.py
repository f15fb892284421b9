"""cross_validate gives the record `suspflow cross-validate` writes to cv.json, every number
equal, on four synthetic profile families of a power law; its errors are the package's
exception classes."""
import json

import pytest

import suspflow


def power_law_families(path):
    """Four forcing amplitudes (the families) at two phi, 20 bins each: mu = 3.6 J^0.44,
    phi_loc from the jamming law, Delta_v a ramp with a little structure (the command's
    test table)."""
    lines = ["scene_id,profile,phi,seed,J,Delta_v,phi_loc,mu"]
    for k, amplitude in enumerate(["0.05", "0.1", "0.2", "0.4"]):
        for s, phi in enumerate([0.50, 0.56]):
            for b in range(20):
                t = (b + 0.5 * s) / 20.0
                j = 1e-3 * 2.5**k * 10.0**t
                mu = 3.6 * j**0.44
                phi_loc = 0.66 - (j / (2.0 * mu)) ** 0.5
                delta_v = 0.02 + 0.5 * j + 0.01 * ((3 * b) % 7)
                lines.append(
                    f'f{k}_{s},"{amplitude}*sin(2*pi*y/L)",{phi},1,{j!r},{delta_v!r},'
                    f"{phi_loc!r},{mu!r}"
                )
    path.write_text("\n".join(lines) + "\n")
    return path


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
