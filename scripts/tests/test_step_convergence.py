"""scripts/step_convergence.py, the script behind issue 50's convergence tables: its pairing
of runs (each against the shortest step of its state and seed), its pooled difference and
standard error (the larger of the seeds' scatter and the combined block errors) and its
verdict (within 5 % and 2 standard errors). Every expected figure is computed here by hand
from the synthetic runs, not by the script's functions."""
import math
import statistics

PARTS = ["eta_r", "eta_r_contact", "eta_r_hydrodynamic", "eta_r_brownian"]


def run_row(scene_id, seed, eta, se, phi=0.45, peclet=1.0, mu_p=0.0, alpha=""):
    """One flow-curves row: eta_r = eta with block error se, its parts a fixed split of it."""
    row = {"scene_id": scene_id, "seed": seed, "phi": phi, "rho": 0.5, "peclet": peclet,
           "mu_p": mu_p, "alpha": alpha}
    for part, share in zip(PARTS, [1.0, 0.5, 0.3, 0.2]):
        row[part] = eta * share
        row[part + "_se"] = se * share
    return row


def step_row(scene_id, dt, status="done", limit="diffusion"):
    return {"scene_id": scene_id, "status": status, "dt": dt, "dt_limit": limit}


def pooled(text):
    """The pooled table as a list of dicts, one per (state, step, part)."""
    lines = text.split("Pooled over seeds:")[1].strip().split("\n\n")[0].splitlines()
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    return [dict(zip(header, (c.strip() for c in line.strip("|").split("|")))) for line in lines[2:]]


def convergence(tmp_path, write_csv, run_script, curves, steps, *extra):
    write_csv(tmp_path / "flow_curves.csv", curves)
    write_csv(tmp_path / "bins.scenes.csv", steps)
    status, out, err = run_script("step_convergence.py", "--set", tmp_path / "flow_curves.csv",
                                  tmp_path / "bins.scenes.csv", *extra)
    assert status == 0, err
    return out


def test_pooled_difference_takes_the_seeds_scatter_when_it_exceeds_the_blocks(tmp_path, write_csv, run_script):
    at_dt = [10.2, 9.9, 10.5]
    curves, steps = [], []
    for seed, eta in enumerate(at_dt, start=1):
        curves += [run_row(f"a{seed}", seed, eta, 0.1), run_row(f"b{seed}", seed, 10.0, 0.1)]
        steps += [step_row(f"a{seed}", 0.03), step_row(f"b{seed}", 0.01)]
    out = convergence(tmp_path, write_csv, run_script, curves, steps)
    row = next(r for r in pooled(out) if r["part"] == "eta_r")
    diffs = [e - 10.0 for e in at_dt]
    scatter = statistics.stdev(diffs) / math.sqrt(3)  # 0.173
    blocks = math.sqrt(3 * 2 * 0.1 ** 2) / 3  # 0.082
    assert scatter > blocks
    assert row["seeds"] == "3"
    assert row["dt_ref"] == "1.000e-02"
    assert float(row["difference"]) == round(statistics.mean(diffs), 3)
    assert row["se (scatter, blocks)"] == f"{scatter:.3f} ({scatter:.3f}, {blocks:.3f})"
    assert row["/ value"] == f"{100 * statistics.mean(diffs) / 10.0:+.1f} %"
    assert row["/ se"] == f"{statistics.mean(diffs) / scatter:+.1f}"
    assert row["pass"] == "yes"
    assert "4 of 4 pooled comparisons" in out


def test_fails_beyond_two_standard_errors_though_within_five_percent(tmp_path, write_csv, run_script):
    # +3 % on every seed with tiny block errors and no scatter: within 5 %, 30 blocks' errors off.
    curves, steps = [], []
    for seed in (1, 2):
        curves += [run_row(f"a{seed}", seed, 10.3, 0.01), run_row(f"b{seed}", seed, 10.0, 0.01)]
        steps += [step_row(f"a{seed}", 0.03), step_row(f"b{seed}", 0.01)]
    rows = pooled(convergence(tmp_path, write_csv, run_script, curves, steps))
    assert [r["pass"] for r in rows] == ["**no**"] * 4
    assert rows[0]["/ value"] == "+3.0 %"


def test_fails_beyond_five_percent_though_within_two_standard_errors(tmp_path, write_csv, run_script):
    curves = [run_row("a", 1, 10.8, 1.0), run_row("b", 1, 10.0, 1.0)]
    steps = [step_row("a", 0.03), step_row("b", 0.01)]
    out = convergence(tmp_path, write_csv, run_script, curves, steps)
    row = pooled(out)[0]
    # One seed: the block errors alone, sqrt(1 + 1) = 1.414; 0.8 of it is 0.57 standard errors.
    assert row["se (scatter, blocks)"].startswith("1.414 (nan, 1.414)")
    assert row["/ se"] == "+0.6"
    assert row["pass"] == "**no**"
    assert "0 of 4 pooled comparisons" in out


def test_every_step_is_compared_with_the_shortest_of_its_seed(tmp_path, write_csv, run_script):
    # Rows in no particular order; three steps; the reference is 1/9 of the step.
    curves = [run_row("c", 1, 9.0, 0.1), run_row("a", 1, 11.0, 0.1), run_row("b", 1, 10.0, 0.1)]
    steps = [step_row("b", 0.01), step_row("c", 0.03 / 9), step_row("a", 0.03)]
    rows = [r for r in pooled(convergence(tmp_path, write_csv, run_script, curves, steps))
            if r["part"] == "eta_r"]
    assert [(r["dt (limit)"], r["dt_ref"], r["difference"]) for r in rows] == [
        ("3.000e-02 (diffusion)", "3.333e-03", "+2.000"),
        ("1.000e-02 (diffusion)", "3.333e-03", "+1.000"),
    ]


def test_states_and_unfinished_runs_are_kept_apart(tmp_path, write_csv, run_script):
    curves = [run_row("a", 1, 11.0, 0.1), run_row("b", 1, 10.0, 0.1),
              run_row("c", 1, 21.0, 0.1, phi=0.55), run_row("d", 1, 20.0, 0.1, phi=0.55),
              run_row("e", 1, 99.0, 0.1, phi=0.55)]
    steps = [step_row("a", 0.03), step_row("b", 0.01), step_row("c", 0.03),
             step_row("d", 0.01), step_row("e", 0.001, status="failed")]
    rows = [r for r in pooled(convergence(tmp_path, write_csv, run_script, curves, steps))
            if r["part"] == "eta_r"]
    assert [(r["phi"], r["at dt"], r["at dt_ref"]) for r in rows] == [
        ("0.45", "11.000", "10.000"), ("0.55", "21.000", "20.000")]


def test_scenes_whose_forces_differ_are_told_apart(tmp_path, write_csv, run_script):
    curves, steps = [], []
    for k_n, eta in ((3000.0, 12.0), (10000.0, 10.5)):
        for name, value, dt in (("a", eta, 0.03), ("b", 10.0, 0.01)):
            scene_id = f"{name}{int(k_n)}"
            curves.append(run_row(scene_id, 1, value, 0.1))
            steps.append(step_row(scene_id, dt))
            folder = tmp_path / "runs.done" / f"{scene_id}_seed1"
            folder.mkdir(parents=True)
            (folder / "scene.toml").write_text(f"[forces]\nk_n = {k_n}\nmu_p = 0.0\n")
    rows = [r for r in pooled(convergence(tmp_path, write_csv, run_script, curves, steps))
            if r["part"] == "eta_r"]
    assert {r["phi"]: r["difference"] for r in rows} == {
        "0.45 (k_n 3000.0)": "+2.000", "0.45 (k_n 10000.0)": "+0.500"}


def test_a_run_in_two_sets_counts_once(tmp_path, write_csv, run_script):
    curves = [run_row("a", 1, 10.2, 0.1), run_row("b", 1, 10.0, 0.1),
              run_row("a", 2, 10.4, 0.1), run_row("b", 2, 10.0, 0.1)]
    steps = [step_row("a", 0.03), step_row("b", 0.01)]
    write_csv(tmp_path / "again.csv", curves[:2])
    out = convergence(tmp_path, write_csv, run_script, curves, steps,
                      "--set", tmp_path / "again.csv", tmp_path / "bins.scenes.csv")
    row = pooled(out)[0]
    assert row["seeds"] == "2"
    assert row["difference"] == "+0.300"


def test_against_last_compares_with_the_last_sets_run_whatever_its_step(tmp_path, write_csv, run_script):
    (tmp_path / "old").mkdir()
    (tmp_path / "new").mkdir()
    write_csv(tmp_path / "old" / "flow_curves.csv", [run_row("x", 1, 8.0, 0.1)])
    write_csv(tmp_path / "old" / "bins.scenes.csv", [step_row("x", 0.01)])
    write_csv(tmp_path / "new" / "flow_curves.csv", [run_row("x", 1, 10.0, 0.1)])
    write_csv(tmp_path / "new" / "bins.scenes.csv", [step_row("x", 0.03)])
    status, out, err = run_script(
        "step_convergence.py", "--against-last",
        "--set", tmp_path / "old" / "flow_curves.csv", tmp_path / "old" / "bins.scenes.csv",
        "--set", tmp_path / "new" / "flow_curves.csv", tmp_path / "new" / "bins.scenes.csv")
    assert status == 0, err
    row = pooled(out)[0]
    assert (row["dt (limit)"], row["dt_ref"], row["difference"]) == (
        "1.000e-02 (diffusion)", "3.000e-02", "-2.000")


def test_steps_from_the_tables_own_dt_column(tmp_path, write_csv, run_script):
    curves = [{**run_row("a", 1, 11.0, 0.1), "dt": 0.03}, {**run_row("b", 1, 10.0, 0.1), "dt": 0.01}]
    write_csv(tmp_path / "flow_curves.csv", curves)
    status, out, err = run_script("step_convergence.py", "--set", tmp_path / "flow_curves.csv", "-")
    assert status == 0, err
    row = pooled(out)[0]
    assert (row["dt (limit)"], row["dt_ref"], row["difference"]) == ("3.000e-02 (?)", "1.000e-02", "+1.000")
    # A table without the steps is refused, naming the run.
    write_csv(tmp_path / "old.csv", [run_row("a", 1, 11.0, 0.1)])
    status, _, err = run_script("step_convergence.py", "--set", tmp_path / "old.csv", "-")
    assert status != 0 and "run a seed 1" in err


def summary(text):
    """The first table (one row per state and step) as a list of dicts."""
    lines = text.split("\n\n")[1].splitlines()
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    return [dict(zip(header, (c.strip() for c in line.strip("|").split("|")))) for line in lines[2:]]


def test_a_step_is_named_by_the_limit_a_run_records(tmp_path, write_csv, run_script):
    # Seed 1's steps from a table without its runs' limits (`-`), seeds 2 and 3's from run
    # tables: the state's step is named by the first limit recorded (seed 2's), each seed's
    # row by its own.
    (tmp_path / "a").mkdir()
    write_csv(tmp_path / "a" / "flow_curves.csv",
              [{**run_row("x", 1, 11.0, 0.1), "dt": 0.03}, {**run_row("y", 1, 10.0, 0.1), "dt": 0.01}])
    curves = [run_row("x", 2, 11.0, 0.1), run_row("y", 2, 10.0, 0.1)]
    (tmp_path / "c").mkdir()
    write_csv(tmp_path / "c" / "flow_curves.csv", [run_row("x", 3, 11.0, 0.1), run_row("y", 3, 10.0, 0.1)])
    write_csv(tmp_path / "c" / "bins.scenes.csv", [step_row("x", 0.03, limit="relaxation"),
                                                    step_row("y", 0.01)])
    out = convergence(tmp_path, write_csv, run_script, curves,
                      [step_row("x", 0.03, limit="friction"), step_row("y", 0.01, limit="user")],
                      "--set", tmp_path / "a" / "flow_curves.csv", "-",
                      "--set", tmp_path / "c" / "flow_curves.csv", tmp_path / "c" / "bins.scenes.csv")
    assert summary(out)[0]["dt (limit)"] == "3.00e-02 (friction)"
    assert pooled(out)[0]["dt (limit)"] == "3.000e-02 (friction)"
    per_seed = out.split("Per seed:")[1]
    assert "| 1 | 3.000e-02 (?) |" in per_seed and "| 2 | 3.000e-02 (friction) |" in per_seed
