"""predict and validate with the shipped models give the numbers of `suspflow predict` and
`suspflow validate --json` exactly (every printed digit: the command prints shortest
round-trip decimals), intervals and domain flags included, from a path and from a
DataFrame."""
import json

import numpy as np
import pandas as pd
import pytest

import suspflow
from conftest import exact_csv

DATA = "datasets/validate_ensemble.ensemble.csv"


@pytest.mark.parametrize("mapping", ["mu", "theta", "dv", "ext"])
def test_predict_matches_the_command(root, run_suspflow, mapping):
    printed = exact_csv(run_suspflow("predict", "--model", f"models/{mapping}", "--input", DATA))
    with pytest.warns(UserWarning) as caught:
        from_path = suspflow.predict(root / "models" / mapping, root / DATA)
    assert any("outside the training domain" in str(w.message) for w in caught)
    with pytest.warns(UserWarning):
        from_frame = suspflow.predict(root / "models", suspflow.read_dataset(root / DATA), mapping)
    predicted = [c for c in printed.columns if c.endswith(("_pred", "_lower", "_upper"))]
    assert len(predicted) == 3 * sum(c.endswith("_pred") for c in printed.columns)
    assert predicted and len(from_path) == len(printed) == 90
    for result in [from_path, from_frame]:
        assert list(result.columns) == list(printed.columns)
        for column in predicted + ["domain_distance"]:
            np.testing.assert_array_equal(result[column].to_numpy(), printed[column].to_numpy())
        assert [str(b).lower() for b in result["in_domain"]] == list(printed["in_domain"])
        # Every prediction lies inside its interval.
        for output in [c[: -len("_pred")] for c in predicted if c.endswith("_pred")]:
            assert (result[f"{output}_lower"] <= result[f"{output}_pred"]).all()
            assert (result[f"{output}_pred"] <= result[f"{output}_upper"]).all()
    assert from_path.attrs["level"] == 0.9
    # The validation flows reach beyond the training domain in a few rows (1-3 for the local
    # mappings, 10 for ext, whose d_ext axis is linear), most lie inside.
    assert 0 < (~from_path["in_domain"]).sum() < len(from_path) // 4


def test_validate_matches_the_command(root, run_suspflow, tmp_path):
    printed = json.loads(
        run_suspflow("validate", "--models", "models", "--data", DATA, "--json", "--plots", tmp_path)
    )
    errors = suspflow.validate(root / "models", root / DATA)
    assert len(errors) == len(printed) > 0
    for row, record in zip(errors.itertuples(), printed):
        assert (row.mapping, row.output, row.profile) == (
            record["mapping"], record["output"], record["profile"]
        )
        assert row.rel_l2 == record["rel_l2"]
        for field in ["beyond_noise", "coverage", "interval_width"]:
            assert getattr(row, field) == record[field], (field, record)
    # A lower level covers fewer rows.
    narrow = suspflow.validate(root / "models", root / DATA, ["dv"], level=0.5)
    dv_all = errors[(errors.mapping == "dv") & (errors.profile == "all")]
    assert (narrow[narrow.profile == "all"].coverage.to_numpy() < dv_all.coverage.to_numpy()).all()
    from_frame = suspflow.validate(root / "models", suspflow.read_dataset(root / DATA), ["dv"])
    dv = errors[errors.mapping == "dv"].reset_index(drop=True)
    pd.testing.assert_frame_equal(from_frame, dv)


def test_a_missing_model_is_an_error_naming_it(root):
    with pytest.raises(suspflow.ModelError, match="nope"):
        suspflow.predict(root / "models" / "nope", root / DATA)
