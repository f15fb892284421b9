"""predict and validate with the shipped models give the numbers of `suspflow predict` and
`suspflow validate --json` exactly (every printed digit: the command prints shortest
round-trip decimals), domain flags included, from a path and from a DataFrame."""
import json

import numpy as np
import pandas as pd
import pytest

import suspflow
from conftest import exact_csv

DATA = "datasets/validate_ensemble.ensemble.csv"


@pytest.mark.parametrize("mapping", ["mu", "theta", "dv"])
def test_predict_matches_the_command(root, run_suspflow, mapping):
    printed = exact_csv(run_suspflow("predict", "--model", f"models/{mapping}", "--input", DATA))
    with pytest.warns(UserWarning) as caught:
        from_path = suspflow.predict(root / "models" / mapping, root / DATA)
    assert any("outside the training domain" in str(w.message) for w in caught)
    with pytest.warns(UserWarning):
        from_frame = suspflow.predict(root / "models", suspflow.read_dataset(root / DATA), mapping)
    predicted = [c for c in printed.columns if c.endswith("_pred")]
    assert predicted and len(from_path) == len(printed) == 90
    for result in [from_path, from_frame]:
        for column in predicted + ["domain_distance"]:
            np.testing.assert_array_equal(result[column].to_numpy(), printed[column].to_numpy())
        assert [str(b).lower() for b in result["in_domain"]] == list(printed["in_domain"])
    # The validation flows reach beyond the training domain in a few rows.
    assert 0 < (~from_path["in_domain"]).sum() < 10


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
    from_frame = suspflow.validate(root / "models", suspflow.read_dataset(root / DATA), ["dv"])
    dv = errors[errors.mapping == "dv"].reset_index(drop=True)
    pd.testing.assert_frame_equal(from_frame, dv)


def test_a_missing_model_is_an_error_naming_it(root):
    with pytest.raises(suspflow.ModelError, match="nope"):
        suspflow.predict(root / "models" / "nope", root / DATA)
