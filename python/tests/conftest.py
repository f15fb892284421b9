"""Shared fixtures: the repository root and the `suspflow` binary the Python results are
compared with (`SUSPFLOW_BIN`, else the release build under `target/`), and an exact CSV
reader."""
import csv
import io
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


def exact_csv(text):
    """A CSV text as a DataFrame whose numbers are exactly the decimals written (each cell
    through Python's float(), empty cells NaN), other columns as strings: the package's own
    reader of the tables it returns as text."""
    import suspflow

    return suspflow._exact_table(text)


def without_code_version(path):
    """The rows of a profile table without the code_version column (the binary and the
    module may be built from different commits)."""
    rows = list(csv.reader(io.StringIO(path.read_text())))
    k = rows[0].index("code_version")
    return [r[:k] + r[k + 1 :] for r in rows]
