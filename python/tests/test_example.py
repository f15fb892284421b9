"""The example script solves both validation flows and writes its figure; the solved
velocity follows the simulated ensemble means within a few percent."""
import re
import subprocess
import sys


def test_validate_flow_example_writes_its_figure(root, tmp_path):
    png = tmp_path / "validate_flow.png"
    done = subprocess.run(
        [sys.executable, str(root / "python/examples/validate_flow.py"), str(png)],
        capture_output=True, text=True, cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    errors = [float(e) for e in re.findall(r"relative L2 error of u ([0-9.]+) %", done.stdout)]
    # Two flows, two closures; the seeds' solver reproduces u within a few percent.
    assert len(errors) == 4 and max(errors) < 5, done.stdout
