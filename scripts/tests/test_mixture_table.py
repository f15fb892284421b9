"""scripts/mixture_table.py, which writes reports/mixtures/viscosity.csv: a run found in two
tables is kept once, runs of one state by two codes, or with other contacts, are both kept,
two different runs of one state by one code are an error, rows are sorted by state, and
nothing is overwritten unasked."""
import csv

COLUMNS = [
    "alpha", "alpha_actual", "phi", "phi_actual", "peclet_c", "peclet_cg", "mu_p", "seed",
    "n_particles", "eta_r", "eta_r_se", "eta_r_contact", "eta_r_contact_se",
    "eta_r_hydrodynamic", "eta_r_hydrodynamic_se", "eta_r_brownian", "eta_r_brownian_se",
    "scene_id",
]


def run_row(alpha, peclet_c, seed, eta, code="0.1.0+gabc", mu_p=0.0, k_n=10000.0):
    row = {c: "1" for c in COLUMNS}
    row.update({"alpha": alpha, "phi": 0.565, "peclet_c": peclet_c, "mu_p": mu_p, "seed": seed,
                "n_particles": 980, "eta_r": eta, "scene_id": f"s{alpha}_{peclet_c}",
                "rho": 0.1, "dt": 0.001, "code_version": code, "kT": 0.1, "k_n": k_n,
                "xi_min": 0.001})
    return row


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_duplicates_once_codes_apart_and_sorted(tmp_path, write_csv, run_script):
    first = write_csv(tmp_path / "a.csv", [
        run_row(0.7, 1.0, 2, 50.0), run_row(0.5, 1.0, 1, 30.0), run_row(0.5, 0.1, 1, 40.0),
        {**run_row(0.5, 1.0, 1, 0.0), "alpha": ""},  # a monodisperse row: not a mixture's
    ])
    # The same run again, the same state by another code (another noise stream), and by the
    # same code with softer contacts.
    second = write_csv(tmp_path / "b.csv", [run_row(0.5, 1.0, 1, 30.0),
                                            run_row(0.5, 1.0, 1, 31.0, code="0.1.0+gdef"),
                                            run_row(0.5, 1.0, 1, 32.0, k_n=3000.0)])
    out = tmp_path / "viscosity.csv"
    status, stdout, err = run_script("mixture_table.py", first, second, "--out", out)
    assert status == 0, err
    rows = read(out)
    assert list(rows[0]) == COLUMNS + ["rho", "dt", "code_version", "k_n", "xi_min"]
    assert [(r["alpha"], r["peclet_c"], r["eta_r"], r["code_version"], r["k_n"])
            for r in rows] == [
        ("0.5", "0.1", "40.0", "0.1.0+gabc", "10000.0"),
        ("0.5", "1.0", "32.0", "0.1.0+gabc", "3000.0"),
        ("0.5", "1.0", "30.0", "0.1.0+gabc", "10000.0"),
        ("0.5", "1.0", "31.0", "0.1.0+gdef", "10000.0"),
        ("0.7", "1.0", "50.0", "0.1.0+gabc", "10000.0"),
    ]
    assert "5 rows from 2 table(s)" in stdout


def test_two_different_runs_of_one_state_by_one_code_are_an_error(tmp_path, write_csv, run_script):
    path = write_csv(tmp_path / "a.csv", [run_row(0.5, 1.0, 1, 30.0), run_row(0.5, 1.0, 1, 31.0)])
    status, _, err = run_script("mixture_table.py", path, "--out", tmp_path / "v.csv")
    assert status != 0
    assert "differ: eta_r 30.0 and 31.0" in err
    assert not (tmp_path / "v.csv").exists()


def test_an_existing_table_is_replaced_only_with_force(tmp_path, write_csv, run_script):
    path = write_csv(tmp_path / "a.csv", [run_row(0.5, 1.0, 1, 30.0)])
    out = tmp_path / "v.csv"
    out.write_text("kept\n")
    status, _, err = run_script("mixture_table.py", path, "--out", out)
    assert status != 0 and "--force" in err
    assert out.read_text() == "kept\n"
    status, _, err = run_script("mixture_table.py", path, "--out", out, "--force")
    assert status == 0, err
    assert read(out)[0]["eta_r"] == "30.0"


def test_a_table_of_another_version_is_refused(tmp_path, write_csv, run_script):
    rows = [run_row(0.5, 1.0, 1, 30.0)]
    del rows[0]["eta_r_brownian_se"]
    status, _, err = run_script("mixture_table.py", write_csv(tmp_path / "a.csv", rows),
                                "--out", tmp_path / "v.csv")
    assert status != 0
    assert "eta_r_brownian_se" in err
