"""train writes the model files `suspflow train` writes, byte for byte, on four synthetic
profile families of a power law (tuned and untuned), returns the numbers the command
prints, and refuses to replace models or train an unknown mapping with the package's
exception classes."""
import json

import pytest

import suspflow
from conftest import power_law_families


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    return power_law_families(tmp_path_factory.mktemp("train") / "families.csv")


def model_files(folder):
    """The files of a model folder by name (the lock left aside), `tuning.json`'s wall time
    removed."""
    files = {}
    for path in sorted(folder.iterdir()):
        if path.name == "run.lock":
            continue
        if path.name.endswith(".tuning.json"):
            record = json.loads(path.read_text())
            assert record.pop("seconds") > 0
            files[path.name] = record
        else:
            files[path.name] = path.read_bytes()
    return files


def percent(fraction):
    return f"{100 * fraction:.2f} %"


@pytest.mark.parametrize("tune", [False, True])
def test_the_models_are_the_commands(data, run_suspflow, tune):
    command, python = data.parent / f"command_{tune}", data.parent / f"python_{tune}"
    flags = [] if tune else ["--no-tune"]
    printed = run_suspflow(
        "train", "--data", data, "--out", command, "--no-bands",
        "--mapping", "dv", "--mapping", "mu", *flags,
    )
    result = suspflow.train(data, python, ["dv", "mu"], tune=tune, bands=False)
    written = model_files(command)
    assert len(written) == 11 + (2 if tune else 0)
    assert model_files(python) == written
    assert [m["mapping"] for m in result["mappings"]] == ["dv", "mu"]
    assert result["bands"] == {"status": "skipped"}
    for m in result["mappings"]:
        assert m["rows"] == 160 and m["skipped_rows"] == 0 and not m["target_noise"]
        assert m["intervals"]["held_out"] == "profile families" and m["intervals"]["folds"] == 4
        # The command's lines, from the returned numbers.
        errors = ", ".join(
            f"{o} {percent(e)}" for o, e in zip(m["outputs"], m["training_error"])
        )
        assert f"training-set relative L2 error {errors}" in printed
        coverage = ", ".join(
            f"{o} {percent(c)}" for o, c in zip(m["outputs"], m["intervals"]["fold_coverage"])
        )
        assert f"held-out rows covered {coverage}" in printed
        if tune:
            t = m["tuning"]
            assert t["settings"] == 96 and t["left_out"] == "profile families"
            assert t["chosen"]["mean"] <= t["defaults"]["mean"]
            assert t["chosen"]["params"] == m["params"]
        else:
            assert m["tuning"] is None and m["params"]["n_estimators"] == 100


def test_a_dataframe_gives_the_same_trees(data, tmp_path):
    by_path, by_frame = tmp_path / "path", tmp_path / "frame"
    steps = []
    suspflow.train(data, by_path, ["mu"], tune=False, bands=False)
    suspflow.train(
        suspflow.read_dataset(data), by_frame, ["mu"], tune=False, bands=False,
        progress=steps.append,
    )
    assert steps == [("intervals", "mu"), ("trained", "mu")]
    for name in ["mu.json", "mu.quantiles_mu.json"]:
        assert (by_frame / name).read_bytes() == (by_path / name).read_bytes(), name
    # The sidecar names where the rows came from, and the hash of the bytes read (the
    # DataFrame's CSV text is not the file's).
    meta, from_file = (json.loads((d / "mu.meta.json").read_text()) for d in (by_frame, by_path))
    assert meta["training_data"]["source"] == "the DataFrame"
    assert from_file["training_data"]["source"] == str(data)
    assert meta["training_data"]["rows"] == from_file["training_data"]["rows"] == 160


def test_models_are_replaced_only_when_forced(data, tmp_path):
    out = tmp_path / "models"
    suspflow.train(data, out, ["mu"], tune=False, bands=False)
    trees = (out / "mu.json").read_bytes()
    with pytest.raises(
        suspflow.FileError,
        match=r"mu\.json already exists \(a trained `mu` model\); force=True replaces it",
    ):
        suspflow.train(data, out, ["mu"], tune=False, bands=False)
    assert (out / "mu.json").read_bytes() == trees
    # A lone sidecar is a user's file too.
    lone = tmp_path / "lone"
    lone.mkdir()
    (lone / "mu.meta.json").write_bytes((out / "mu.meta.json").read_bytes())
    with pytest.raises(suspflow.FileError, match=r"mu\.meta\.json already exists"):
        suspflow.train(data, lone, ["mu"], tune=False, bands=False)
    result = suspflow.train(data, out, ["mu"], tune=False, bands=False, force=True)
    assert result["mappings"][0]["mapping"] == "mu"


def test_an_unknown_mapping_is_a_model_error(data, tmp_path):
    out = tmp_path / "models"
    with pytest.raises(suspflow.ModelError, match="unknown mapping `nope`"):
        suspflow.train(data, out, ["nope"])
    assert not out.exists()


def test_a_table_without_an_output_is_a_data_error(data, tmp_path):
    table = suspflow.read_dataset(data).drop(columns="mu")
    with pytest.raises(suspflow.DataError, match="mu"):
        suspflow.train(table, tmp_path / "models", ["mu"], tune=False, bands=False)
