"""Shared fixtures: the repository root and the `suspflow` binary the Python results are
compared with (`SUSPFLOW_BIN`, else the release build under `target/`)."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def suspflow_bin():
    path = pathlib.Path(os.environ.get("SUSPFLOW_BIN", ROOT / "target" / "release" / "suspflow"))
    if not path.is_file():
        pytest.fail(f"{path} does not exist: build it with `cargo build --release` or set SUSPFLOW_BIN")
    return path


@pytest.fixture(scope="session")
def run_suspflow(suspflow_bin):
    """Runs `suspflow ARGS...` in the repository root and returns its standard output."""

    def run(*args):
        done = subprocess.run(
            [str(suspflow_bin), *map(str, args)], cwd=ROOT, capture_output=True, text=True
        )
        assert done.returncode == 0, done.stderr
        return done.stdout

    return run
