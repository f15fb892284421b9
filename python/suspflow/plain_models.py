"""The shipped surrogate models (``models/<mapping>.json`` + ``<mapping>.meta.json``) with
plain Python ``xgboost`` and NumPy: no native build of suspflow is needed, and this file
imports nothing else from the package, so it also works copied on its own beside a script
(``from plain_models import PlainModel``).

The booster does not predict the outputs themselves. A model trained with the physics
backbone (``meta["backbone"]`` not null, all shipped models) predicts the min-max scaled
residual of each output from the local rheology at the row's J (docs/physics.md section 8,
eq 6.7: ``mu = A J^b``, ``phi_loc = phi_J - sqrt(J / (alpha mu))``); without it, the outputs
min-max scaled with ``meta["scaling"]``. Outputs are then clipped into their physical range
(``0 < phi_loc < 0.74``, ``mu >= 0``), as ``suspflow predict`` does. The result equals
``suspflow.predict``'s ``<output>_pred`` columns to float32 rounding of the trees' sums
(about 1e-7 relative); the training-domain check is not repeated here.
"""
from __future__ import annotations

import json
import pathlib
from typing import Dict, Union

import numpy as np

#: The densest packing of equal spheres, rounded down: phi_loc's upper bound.
PHI_LOC_MAX = 0.74

#: Closed ranges predictions are clipped into (strict bounds as the nearest float inside).
PHYSICAL_RANGE = {
    "phi_loc": (np.nextafter(0.0, 1.0), np.nextafter(PHI_LOC_MAX, 0.0)),
    "mu": (0.0, np.inf),
}


def _unscale(ranges, scaled: np.ndarray) -> np.ndarray:
    """``min + y' (max - min)`` per column (a zero span counts as 1, as in training)."""
    lo = np.array([r["min"] for r in ranges])
    hi = np.array([r["max"] for r in ranges])
    span = np.where(hi > lo, hi - lo, 1.0)
    return lo + scaled * span


def backbone(law: Dict[str, float], output: str, j: np.ndarray) -> np.ndarray:
    """The local rheology (eq 6.7) at viscous numbers ``j``: ``mu = A J^b`` (0 for J <= 0) and
    ``phi_loc = phi_J - sqrt(J / (alpha mu))`` (phi_J where mu = 0)."""
    j = np.asarray(j, dtype=float)
    positive = j > 0
    mu = np.where(positive, law["mu_prefactor"] * np.where(positive, j, 1.0) ** law["mu_exponent"], 0.0)
    if output == "mu":
        return mu
    if output == "phi_loc":
        safe_mu = np.where(mu > 0, mu, 1.0)
        return np.where(mu > 0, law["phi_j"] - np.sqrt(j / (law["alpha"] * safe_mu)), law["phi_j"])
    raise ValueError(f"the backbone predicts mu and phi_loc, not {output!r}")


class PlainModel:
    """One trained mapping read with ``xgboost.Booster``: ``PlainModel("models/dv")``."""

    def __init__(self, path: Union[str, pathlib.Path]):
        import xgboost  # imported here so that the module loads without it (e.g. for backbone)

        path = pathlib.Path(path)
        stem = path.parent / path.name.removesuffix(".json").removesuffix(".meta")
        self.meta = json.loads(pathlib.Path(f"{stem}.meta.json").read_text())
        self.booster = xgboost.Booster(model_file=f"{stem}.json")
        self.features = list(self.meta["features"])
        self.outputs = list(self.meta["outputs"])

    def predict(self, data) -> Dict[str, np.ndarray]:
        """Outputs in original units for every row of ``data`` (a pandas DataFrame or a
        mapping with the feature columns): ``{output: array}``."""
        import xgboost

        x = np.column_stack([np.asarray(data[f], dtype=float) for f in self.features])
        rows = xgboost.DMatrix(x.astype(np.float32), feature_names=self.features)
        scaled = self.booster.predict(rows)
        scaled = np.asarray(scaled, dtype=float).reshape(len(x), len(self.outputs))
        bb = self.meta.get("backbone")
        if bb is None:
            values = _unscale(self.meta["scaling"]["ranges"], scaled)
        else:
            j = x[:, self.features.index("J")]
            values = _unscale(bb["residual_scaling"]["ranges"], scaled) + np.column_stack(
                [backbone(bb["law"], o, j) for o in self.outputs]
            )
        result = {}
        for k, output in enumerate(self.outputs):
            lo, hi = PHYSICAL_RANGE.get(output, (-np.inf, np.inf))
            result[output] = np.clip(values[:, k], lo, hi)
        return result
