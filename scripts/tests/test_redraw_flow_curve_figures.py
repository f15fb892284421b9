"""scripts/redraw_flow_curve_figures.py's reading of a report's recorded command: the runs
(one folder per shard), an earlier table the runs updated and `--local` are dropped, the
Green-Kubo runs kept, and the folder's own table, folder and `--force` put in."""
import importlib.util

from conftest import SCRIPTS

spec = importlib.util.spec_from_file_location("redraw", SCRIPTS / "redraw_flow_curve_figures.py")
redraw = importlib.util.module_from_spec(spec)
spec.loader.exec_module(redraw)


def test_runs_of_several_shards_and_an_earlier_table_are_dropped(tmp_path):
    recorded = ["flow-curves", "grids/g.toml", "--table", "reports/old/flow_curves.csv", "--runs", "w0", "w1",
                "--green-kubo", "gk0", "gk1", "--local", "d.csv", "--out", "reports/new"]
    assert redraw.redraw_arguments(recorded, tmp_path) == [
        "flow-curves", "grids/g.toml", "--green-kubo", "gk0", "gk1",
        "--table", str(tmp_path / "flow_curves.csv"), "--out", str(tmp_path), "--force"]


def test_the_recorded_command_is_read_from_the_readme(tmp_path):
    (tmp_path / "README.md").write_text(
        "# Flow curves\n\n```\nsuspflow flow-curves grids/g.toml --runs w --out o\n```\n")
    assert redraw.recorded_command(tmp_path) == [
        "flow-curves", "grids/g.toml", "--runs", "w", "--out", "o"]
