"""simulate writes the command's files: the same profile as `suspflow simulate` with the
same thread count, every cell's text identical but the code version; refuses a directory holding a run unless resume or force; and a
Ctrl-C (SIGINT) during the run checkpoints and raises KeyboardInterrupt, after which
resume=True finishes with the profile of an uninterrupted run."""
import signal

import pytest

import suspflow
from conftest import without_code_version

SCENE = "tests/scenes/good/tiny.toml"


@pytest.fixture(scope="module")
def command_run(run_suspflow, tmp_path_factory):
    out = tmp_path_factory.mktemp("command")
    run_suspflow("simulate", SCENE, "--out", out, "--threads", 1)
    return out


def test_the_profile_is_the_commands(root, command_run, tmp_path):
    reports = []
    summary = suspflow.simulate(root / SCENE, tmp_path, threads=1, progress=reports.append)
    assert without_code_version(tmp_path / "profile.csv") == without_code_version(
        command_run / "profile.csv"
    )
    assert suspflow.CODE_VERSION in (tmp_path / "profile.csv").read_text()
    assert summary["n_particles"] == suspflow.check(root / SCENE)["n_particles"]
    phases = {r["phase"] for r in reports}
    assert phases == {"equilibrating", "averaging"}
    assert reports[-1]["snapshots"] == reports[-1]["snapshots_target"] == 40


def test_an_earlier_run_is_kept_unless_force(root, tmp_path):
    suspflow.simulate(root / SCENE, tmp_path, threads=1, progress=False)
    with pytest.raises(suspflow.FileError, match="earlier run"):
        suspflow.simulate(root / SCENE, tmp_path, threads=1, progress=False)
    suspflow.simulate(root / SCENE, tmp_path, threads=1, progress=False, force=True)
    with pytest.raises(suspflow.FileError, match="is a file"):
        suspflow.simulate(root / SCENE, tmp_path / "profile.csv", progress=False)
    with pytest.raises(suspflow.SuspflowError, match="snapshot format"):
        suspflow.simulate(root / SCENE, tmp_path / "x", snapshot=1, snapshot_format="pdb")


@pytest.fixture
def python_handles_sigint():
    """Python's own SIGINT handler for the test: a shell that starts a job in the background
    without job control (`cmd &` in a script, as CI runners may) starts it with SIGINT
    ignored, and Python then never turns the signal into a KeyboardInterrupt."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_ctrl_c_checkpoints_and_resume_finishes_the_run(
    root, command_run, tmp_path, python_handles_sigint
):
    def interrupt_at_the_fifth_report(report, seen=[]):
        seen.append(report)
        if len(seen) == 5:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt, match="resume=True"):
        suspflow.simulate(
            root / SCENE, tmp_path, threads=1, snapshot=4, progress=interrupt_at_the_fifth_report
        )
    assert (tmp_path / "checkpoint.json").exists()
    assert not (tmp_path / "profile.csv").exists()
    frames_before = (tmp_path / "frames.xyz").read_text()
    suspflow.simulate(root / SCENE, tmp_path, threads=1, snapshot=4, resume=True, progress=False)
    assert without_code_version(tmp_path / "profile.csv") == without_code_version(
        command_run / "profile.csv"
    )
    # The resumed run appends its frames to those written before the interrupt.
    assert (tmp_path / "frames.xyz").read_text().startswith(frames_before)


def test_an_exception_in_the_progress_callable_stops_the_run(root, tmp_path):
    def fail(report):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        suspflow.simulate(root / SCENE, tmp_path, threads=1, progress=fail)
    assert not (tmp_path / "profile.csv").exists()


def test_progress_off_a_terminal_is_a_line_every_ten_percent(root, tmp_path, capfd):
    """stderr captured (not a terminal): the default progress writes whole lines, one at
    each phase's start and every 10 % of it, each with the step and the time left, and no
    carriage return."""
    suspflow.simulate(root / SCENE, tmp_path, threads=1)
    err = capfd.readouterr().err
    assert "\r" not in err
    lines = [l for l in err.splitlines() if "%)" in l]
    equilibrating = [l for l in lines if l.startswith("equilibrating")]
    averaging = [l for l in lines if l.startswith("averaging")]
    assert 2 <= len(averaging) <= 12 and equilibrating, err
    assert all(", step " in l and " in this phase" in l for l in lines)
    assert any(" left" in l for l in averaging)


def test_threads_beyond_the_commands_cap_are_refused(root, tmp_path):
    # Issue 55, class 7: the command's cap (8 per core) holds here too; 5000 threads were
    # started before.
    with pytest.raises(suspflow.SuspflowError, match="5000 threads on"):
        suspflow.simulate(root / SCENE, tmp_path, threads=5000, progress=False)
    assert not (tmp_path / "checkpoint.json").exists()


def test_a_folder_another_writer_holds_is_refused(root, tmp_path):
    # Issue 55, class 4: the one lock of every writer of a run folder (run.lock, an flock).
    import fcntl

    with open(tmp_path / "run.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(suspflow.SuspflowError, match="in use by another"):
            suspflow.simulate(root / SCENE, tmp_path, threads=1, progress=False)
