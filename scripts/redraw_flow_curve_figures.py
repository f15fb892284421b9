#!/usr/bin/env python3
"""Draws the figures of every flow-curve report again from its table, without the runs.

Each folder under reports/ with a flow_curves.csv and a README.md written by
`suspflow flow-curves` names the command that produced it; this runs that command with
`--table <folder>/flow_curves.csv` in place of `--runs` (and without `--local`, which only
adds a section to the README), so the figures (SVG, with their data beside them as CSV), the
README and the table are those the current code writes from the table: its lines as they
are, with the columns added since that the grid gives (the contacts) filled in.

    python3 scripts/redraw_flow_curve_figures.py [--bin target/release/suspflow] [FOLDER ...]
"""
import argparse
import pathlib
import shlex
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def recorded_command(folder: pathlib.Path) -> list:
    """The `suspflow flow-curves` arguments recorded in the folder's README."""
    readme = folder / "README.md"
    for line in readme.read_text().splitlines():
        if line.startswith("suspflow flow-curves "):
            return shlex.split(line)[1:]
    raise ValueError(f"{readme} records no `suspflow flow-curves` command")


def redraw_arguments(args: list, folder: pathlib.Path) -> list:
    """`args` with the folder's own table for `--runs` (and for the earlier `--table` of a
    table updated by runs), no `--local`, `--out` the folder, and `--force`."""
    out, k = [], 0
    while k < len(args):
        flag = args[k]
        k += 1
        if flag in ("--runs", "--table", "--local", "--out"):
            # The flag and its values: `--runs` takes one folder per shard.
            while k < len(args) and not args[k].startswith("--"):
                k += 1
            continue
        out.append(flag)
    return out + ["--table", str(folder / "flow_curves.csv"), "--out", str(folder), "--force"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", default=str(ROOT / "target/release/suspflow"))
    parser.add_argument("folders", nargs="*", type=pathlib.Path)
    options = parser.parse_args()
    folders = options.folders or sorted(
        p.parent for p in (ROOT / "reports").rglob("flow_curves.csv")
        if (p.parent / "README.md").exists()
    )
    failed = 0
    for folder in folders:
        try:
            args = redraw_arguments(recorded_command(folder), folder)
        except ValueError as e:
            print(f"skipped: {e}", file=sys.stderr)
            continue
        ran = subprocess.run([options.bin, *args], cwd=ROOT, capture_output=True, text=True)
        status = "ok" if ran.returncode == 0 else "FAILED"
        print(f"{status}: {folder.relative_to(ROOT) if folder.is_absolute() else folder}")
        if ran.returncode != 0:
            failed += 1
            print(ran.stderr, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
