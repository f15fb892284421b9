"""scripts/flow_curve_minimum.py, which places thesis Fig. 5.3's viscosity minima: on an exact
parabola in log10 Pe_c its vertex is the parabola's, in Pe_c and in Pe_cg; seeds are averaged;
a curve whose lowest point is an end has no minimum; the drawn range is seeded."""
import math

PE = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0]


def curve(pe_min, se, alpha=0.5, ratio=4.0, seeds=(1,), offset=lambda seed: 0.0):
    """Rows of eta_r = 20 + 3 (log10 Pe_c - log10 pe_min)^2 (+ a seed's offset)."""
    rows = []
    for seed in seeds:
        for pe in PE:
            eta = 20 + 3 * (math.log10(pe) - math.log10(pe_min)) ** 2 + offset(seed)
            rows.append({"alpha": alpha, "phi": 0.565, "mu_p": 0.0, "seed": seed,
                         "peclet_c": pe, "peclet_cg": ratio * pe, "eta_r": eta, "eta_r_se": se})
    return rows


def table(out):
    """The printed rows after the header, as lists of cells."""
    return [[c.strip() for c in line.strip("|").split("|")] for line in out.splitlines()[2:]]


def test_the_vertex_of_an_exact_parabola_in_pe_c_and_pe_cg(tmp_path, write_csv, run_script):
    # Seeds 1 and 2 lie 1 above and below the parabola: their mean is on it.
    rows = curve(0.07, 1e-9, seeds=(1, 2), offset=lambda seed: 1.0 if seed == 1 else -1.0)
    rows += [{**r, "alpha": "", "peclet_c": ""} for r in curve(0.3, 1e-9)]  # not a mixture row
    status, out, err = run_script("flow_curve_minimum.py", write_csv(tmp_path / "c.csv", rows))
    assert status == 0, err
    [row] = table(out)
    assert row[:3] == ["0.5", "0.565", "0"]
    # Two seeds differ by 2 at every point: each mean's error is 1, and the range is wide.
    assert row[4].startswith("0.07 (")
    assert row[5].startswith("0.28 (")


def test_the_drawn_range_holds_the_vertex_and_is_the_same_on_a_rerun(tmp_path, write_csv, run_script):
    path = write_csv(tmp_path / "c.csv", curve(0.07, 0.2))
    runs = [run_script("flow_curve_minimum.py", path) for _ in range(2)]
    assert runs[0] == runs[1]
    [row] = table(runs[0][1])
    central, spread = row[4].split(" ")
    lo, hi = (float(x) for x in spread.strip("()").split("-"))
    assert float(central) == 0.07
    assert lo < 0.07 < hi
    # The points' errors (0.2 on a curvature of 3 per decade squared) move the vertex by much
    # less than the points' spacing (0.3-0.4 decade).
    assert math.log10(hi / lo) < 0.3


def test_a_lowest_point_at_an_end_is_no_minimum(tmp_path, write_csv, run_script):
    path = write_csv(tmp_path / "c.csv", curve(2.0, 1e-9))
    status, out, err = run_script("flow_curve_minimum.py", path)
    assert status == 0, err
    assert "no interior minimum" in out


def test_a_table_without_mixture_rows_is_an_error(tmp_path, write_csv, run_script):
    path = write_csv(tmp_path / "c.csv", [{**r, "alpha": ""} for r in curve(0.07, 0.1)])
    status, _, err = run_script("flow_curve_minimum.py", path)
    assert status != 0
    assert "no mixture rows" in err
