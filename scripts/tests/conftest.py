"""Shared helpers of the analysis scripts' tests: each script is run as a user runs it (a
subprocess of this Python on files written into a temporary folder), so what is checked is
its printed or written table, not its internals."""
import csv
import pathlib
import subprocess
import sys

import pytest

SCRIPTS = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture
def run_script():
    """Runs `scripts/NAME ARGS...`; returns (exit status, standard output, standard error)."""

    def run(name, *args):
        done = subprocess.run([sys.executable, str(SCRIPTS / name), *map(str, args)],
                              capture_output=True, text=True)
        return done.returncode, done.stdout, done.stderr

    return run


@pytest.fixture
def write_csv():
    """Writes a list of dicts as a CSV table (columns: the union of their keys, in order)."""

    def write(path, rows):
        columns = list(dict.fromkeys(k for r in rows for k in r))
        with open(path, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns)
            writer.writeheader()
            writer.writerows(rows)
        return path

    return write
