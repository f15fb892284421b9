"""Shared fixtures: the repository root and the `suspflow` binary the Python results are
compared with (`SUSPFLOW_BIN`, else the release build under `target/`), an exact CSV
reader and a small training table of four profile families."""
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
