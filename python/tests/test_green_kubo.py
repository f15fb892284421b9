"""green_kubo gives the Green-Kubo result of `suspflow green-kubo` (every number equal, the
correlation table byte for byte) on the same scene and thread count; an earlier result is
kept unless force; what cannot give a result is refused before anything runs."""
import json

import pytest

import suspflow

SCENE = {
    "box": {"l_x": 10.0, "l_y": 10.0, "l_z": 10.0},
    "particles": {"phi": 0.3, "rho": 0.5},
    "fluid": {"kT": 0.2},
}
SHORT = {"warmup": 1.0, "span": 20.0, "max_lag": 0.5, "blocks": 5, "threads": 1}


def test_the_result_is_the_commands(run_suspflow, tmp_path):
    scene = tmp_path / "eq.toml"
    scene.write_text(
        "box = { l_x = 10.0, l_y = 10.0, l_z = 10.0 }\n"
        "particles = { phi = 0.3, rho = 0.5 }\nfluid = { kT = 0.2 }\n"
    )
    command = tmp_path / "command"
    run_suspflow(
        "green-kubo", scene, "--out", command, "--warmup", "1", "--span", "20",
        "--max-lag", "0.5", "--blocks", "5", "--threads", "1",
    )
    written = json.loads((command / "green_kubo.json").read_text())
    ours = tmp_path / "python"
    result = suspflow.green_kubo(SCENE, ours, progress=False, **SHORT)
    for r in (written, result):
        r.pop("code_version")
    assert result == written
    assert result["eta_brownian_over_eta"] > 0
    assert (ours / "green_kubo.csv").read_bytes() == (command / "green_kubo.csv").read_bytes()
    with pytest.raises(suspflow.FileError, match="force=True"):
        suspflow.green_kubo(SCENE, ours, progress=False, **SHORT)


def test_a_sheared_scene_is_refused_before_it_runs(tmp_path):
    sheared = {**SCENE, "fluid": {"kT": 0.2, "shear_rate": 0.01}}
    with pytest.raises(suspflow.SuspflowError, match="unsheared"):
        suspflow.green_kubo(sheared, tmp_path / "gk", progress=False, **SHORT)
    assert not (tmp_path / "gk" / "checkpoint.json").exists()
