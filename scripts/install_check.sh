#!/usr/bin/env bash
# The README's install commands, then the installs used without their build: builds a wheel
# with `pip wheel ./python` (first, as in a fresh clone: pip's isolated build) and installs
# it into a fresh venv, installs the command with `cargo install --path .`, both from one
# scratch target directory, deletes that directory (what
# `cargo clean` does to a checkout's target/) and runs both from another folder: `suspflow
# --version`, a `predict` with the shipped models, the same from Python, and where each
# finds libxgboost.so (ldd). Not part of the test suite (two release builds); docs/python.md
# holds a run's output.
# Usage: scripts/install_check.sh [--cold]. By default the scratch target starts as a copy of
# the release build in $SEED_TARGET (default ./target; an incremental build, minutes);
# --cold starts from nothing (a first build, about 20 min on 2 cores). With XDG_DATA_HOME
# pointing at an empty folder, both builds install the pinned XGBoost wheel afresh (pip's
# isolated build included). KEEP_WHEEL=DIR keeps a copy of the wheel in DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
tmp=$(mktemp -d /tmp/suspflow-install.XXXXXX)
export CARGO_TARGET_DIR=$tmp/target
seed=${SEED_TARGET:-target}
if [ "${1:-}" != --cold ] && [ -d "$seed/release" ]; then
    echo "== seeding $CARGO_TARGET_DIR with a copy of $seed/release"
    mkdir -p "$CARGO_TARGET_DIR" && cp -r "$seed/release" "$CARGO_TARGET_DIR/release"
fi
echo "== pip wheel ./python -w $tmp/dist (then pip install it into a fresh venv)"
python3 -m venv "$tmp/venv"
nice -n 5 "$tmp/venv/bin/python" -m pip wheel --quiet --disable-pip-version-check --no-deps ./python -w "$tmp/dist"
"$tmp/venv/bin/python" -m pip install --quiet --disable-pip-version-check "$tmp"/dist/*.whl
ls -l "$tmp"/dist/*.whl
echo "== cargo install --locked --path . --root $tmp/root"
nice -n 5 cargo install --quiet --locked --path . --root "$tmp/root"
echo "== rm -rf $CARGO_TARGET_DIR (as cargo clean)"
rm -rf "$CARGO_TARGET_DIR"
cd "$tmp"
export PATH="$tmp/root/bin:$PATH" OMP_WAIT_POLICY=PASSIVE
echo "== suspflow from PATH: $(command -v suspflow)"
suspflow --version
ldd "$(command -v suspflow)" | grep xgboost
suspflow predict --model "$repo/models/dv" --input "$repo/datasets/validate_ensemble.ensemble.csv" | head -2
echo "== Python"
native=$("$tmp/venv/bin/python" -c "import suspflow._native as n; print(n.__file__)")
ldd "$native" | grep xgboost
"$tmp/venv/bin/python" - "$repo" <<'PY'
import sys, suspflow
repo = sys.argv[1]
p = suspflow.predict(f"{repo}/models/dv", f"{repo}/datasets/validate_ensemble.ensemble.csv")
print(suspflow.__version__, p[["phi_loc_pred", "mu_pred"]].iloc[0].to_dict())
PY
if [ -n "${KEEP_WHEEL:-}" ]; then mkdir -p "$KEEP_WHEEL" && cp "$tmp"/dist/*.whl "$KEEP_WHEEL"/; fi
rm -rf "$tmp"
echo "== ok"
