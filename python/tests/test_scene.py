"""read_scene and check against the command: a scene from a file and from a mapping with the
same keys are the same scene, bad input raises SceneError naming the field (a missing file FileError), and check()
states the numbers `suspflow simulate --check` prints."""
import re
import tomllib

import pytest

import suspflow

SCENE = "tests/scenes/good/tiny.toml"


def test_a_mapping_and_its_file_are_the_same_scene(root):
    from_file = suspflow.read_scene(root / SCENE)
    mapping = tomllib.loads((root / SCENE).read_text())
    from_mapping = suspflow.read_scene(mapping)
    assert from_mapping.to_json() == from_file.to_json()
    assert from_file.name == "tiny"


def test_bad_fields_are_refused_by_name():
    bad = {"name": "bad", "box": {"l_x": 8.0, "l_y": 12.0, "l_z": 8.0}, "particles": {"phi": 0.9},
           "fluid": {"profile": "0.1*sin(2*pi*y/L)"}}
    with pytest.raises(suspflow.SceneError, match="particles.phi"):
        suspflow.read_scene(bad)
    with pytest.raises(suspflow.SceneError, match="unknown field"):
        suspflow.read_scene({"name": "x", "boxx": {}})
    with pytest.raises(suspflow.FileError, match="no_such.toml"):
        suspflow.read_scene("no_such.toml")


def test_check_states_what_the_command_prints(root, run_suspflow):
    printed = run_suspflow("simulate", SCENE, "--check")
    c = suspflow.check(root / SCENE)
    n = int(re.search(r"particles: (\d+)", printed).group(1))
    bins = int(re.search(r"bins: (\d+)", printed).group(1))
    dt = float(re.search(r"dt = (\S+) set by", printed).group(1))
    assert (c["n_particles"], c["n_bins"]) == (n, bins)
    assert sum(c["species_counts"]) == n
    # The command prints dt with 4 significant digits.
    assert f"{c['dt']:.3e}" == f"{dt:.3e}"
    assert c["integrator"] in printed and c["dt_limit"] in printed


def test_the_version_is_the_commands(run_suspflow):
    """`suspflow.__version__` is the commit stamp the command line prints and results record."""
    printed = run_suspflow("--version").split()[-1]
    assert suspflow.__version__ == suspflow.CODE_VERSION == printed


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_a_non_finite_number_in_a_mapping_is_refused_by_name(value):
    # Issue 55, class 8: JSON has no NaN, and the native reader only said where in its text
    # it stopped ("expected value at line 1 column 141").
    scene = {"name": "x", "box": {"l_x": 8.0, "l_y": 12.0, "l_z": 8.0},
             "particles": {"phi": 0.5, "radii": [1.0, value]},
             "fluid": {"profile": "0.1*sin(2*pi*y/L)"}}
    with pytest.raises(suspflow.SuspflowError, match=r"`particles\.radii\[1\]`"):
        suspflow.read_scene(scene)
