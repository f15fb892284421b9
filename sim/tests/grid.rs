//! Grid expansion: the Cartesian product of [vary] times the [[cases]], in the documented
//! order, with every scene validated and named so that ids sort in grid order; replicas
//! from seed lists or a `replicas` count, and clear refusals of bad ones.
use sim::input::grid::Grid;

const BASE: &str = r#"
name = "g"
[scene]
box = { l_x = 8.0, l_y = 12.0, l_z = 8.0 }
particles = { phi = 0.5 }
fluid = { profile = "0.1*sin(2*pi*y/L)" }
"#;

#[test]
fn cases_times_product_in_order() {
    let text = format!(
        r#"{BASE}
[vary]
seed = [1, 2, 3]
"particles.phi" = [0.45, 0.5]
[[cases]]
"box.l_y" = 12.0
[[cases]]
"box.l_y" = 16.0
"fluid.profile" = "0.1*sin(2*pi*y/L)^3"
"#
    );
    let grid = Grid::from_toml(&text, false).unwrap();
    assert_eq!(grid.runs.len(), 2 * 2 * 3);
    let got: Vec<(f64, f64, u64)> = grid
        .runs
        .iter()
        .map(|s| {
            (
                s.scene.box_len[1],
                s.scene.file.particles.phi,
                s.scene.file.seed,
            )
        })
        .collect();
    // Keys alphabetical ("particles.phi" < "seed"), the last fastest; cases outermost.
    assert_eq!(
        &got[..4],
        &[
            (12.0, 0.45, 1),
            (12.0, 0.45, 2),
            (12.0, 0.45, 3),
            (12.0, 0.5, 1)
        ]
    );
    assert_eq!(got[6], (16.0, 0.45, 1));
    assert_eq!(grid.runs[6].scene.file.fluid.profile, "0.1*sin(2*pi*y/L)^3");
    assert_eq!(grid.runs[0].scene.file.fluid.profile, "0.1*sin(2*pi*y/L)");
    let ids: Vec<&str> = grid.runs.iter().map(|s| s.id.as_str()).collect();
    assert_eq!(ids[0], "g_000");
    assert_eq!(ids[11], "g_011");
    assert!(
        ids.windows(2).all(|w| w[0] < w[1]),
        "ids sort in grid order"
    );
    assert!(grid.runs.iter().all(|s| s.scene.file.name == s.id));
}

#[test]
fn shards_are_disjoint_and_cover_the_grid() {
    let text = format!("{BASE}\n[vary]\nseed = [1, 2, 3, 4, 5, 6, 7]\n");
    let grid = Grid::from_toml(&text, false).unwrap();
    let mut seen: Vec<usize> = (0..3)
        .flat_map(|i| grid.shard(i, 3).unwrap().into_iter().map(|s| s.index))
        .collect();
    seen.sort_unstable();
    assert_eq!(seen, (0..7).collect::<Vec<_>>());
    assert!(grid.shard(3, 3).is_err());
    // With replicas the shards split runs, not scenes: 2 scenes x 3 seeds over 4 shards.
    let text = format!(
        "{}\n[vary]\nseed = [1, 2]\n",
        BASE.replace("[scene]", "replicas = 3\n[scene]")
    );
    let grid = Grid::from_toml(&text, false).unwrap();
    let mut seen: Vec<(usize, u64)> = (0..4)
        .flat_map(|i| grid.shard(i, 4).unwrap())
        .map(|r| (r.index, r.seed()))
        .collect();
    assert_eq!(grid.shard(0, 4).unwrap().len(), 2);
    seen.sort_unstable();
    let mut all: Vec<(usize, u64)> = grid.runs.iter().map(|r| (r.index, r.seed())).collect();
    all.sort_unstable();
    assert_eq!(seen, all);
    assert_eq!(all.len(), 6);
}

#[test]
fn stokes_sets_the_density_from_the_profile() {
    // gdot_max = 0.1 * 2 pi / 12; St = rho a^2 gdot_max / eta with a = 1.
    let text = format!("{BASE}\n[vary]\n\"particles.stokes\" = [0.05]\n");
    let scene = &Grid::from_toml(&text, false).unwrap().runs[0].scene;
    let gdot = 0.1 * 2.0 * std::f64::consts::PI / 12.0;
    assert!(
        (scene.rho - 0.05 / gdot).abs() < 1e-9 * scene.rho,
        "rho = {}",
        scene.rho
    );
    assert!((scene.stokes - 0.05).abs() < 1e-12);
}

#[test]
fn a_grid_without_vary_or_cases_is_one_scene() {
    let grid = Grid::from_toml(BASE, false).unwrap();
    assert_eq!(grid.runs.len(), 1);
    assert_eq!(grid.runs[0].id, "g_000");
}

#[test]
fn a_seed_list_gives_one_run_per_seed_under_the_scene_id() {
    let text =
        format!("{BASE}\n[[cases]]\nseed = [7, 3, 5]\n[[cases]]\n\"particles.phi\" = 0.45\n");
    let grid = Grid::from_toml(&text, false).unwrap();
    assert_eq!(grid.scene_count(), 2);
    let runs: Vec<(&str, u64)> = grid
        .runs
        .iter()
        .map(|r| (r.id.as_str(), r.seed()))
        .collect();
    // The second case keeps the default seed, 1; the list's order is kept.
    assert_eq!(
        runs,
        [("g_000", 7), ("g_000", 3), ("g_000", 5), ("g_001", 1)]
    );
    assert!(grid.runs.iter().all(|r| r.scene.file.name == r.id));
    assert_eq!(grid.runs[1].label(), "g_000_seed3");
    // A list in [scene] applies to every scene.
    let text = BASE.replace("[scene]", "[scene]\nseed = [2, 4]");
    let grid = Grid::from_toml(
        &format!("{text}[vary]\n\"particles.phi\" = [0.45, 0.5]\n"),
        false,
    )
    .unwrap();
    let phis: Vec<(f64, u64)> = grid
        .runs
        .iter()
        .map(|r| (r.scene.file.particles.phi, r.seed()))
        .collect();
    assert_eq!(phis, [(0.45, 2), (0.45, 4), (0.5, 2), (0.5, 4)]);
}

#[test]
fn a_replicas_count_derives_distinct_seeds_from_the_scene_seed() {
    let grid = |replicas: i64, seed: u64| {
        let text = BASE.replace(
            "[scene]",
            &format!("replicas = {replicas}\n[scene]\nseed = {seed}"),
        );
        Grid::from_toml(&text, false).unwrap()
    };
    let three = grid(3, 9);
    let seeds: Vec<u64> = three.runs.iter().map(|r| r.seed()).collect();
    assert_eq!(seeds.len(), 3);
    assert_eq!(seeds[0], 9, "replica 0 is the scene itself");
    assert!(
        seeds[1] != seeds[2] && !seeds[1..].contains(&9),
        "{seeds:?}"
    );
    assert!(three.runs.iter().all(|r| r.id == "g_000"));
    // Deterministic, and a prefix for fewer replicas.
    assert_eq!(
        grid(2, 9).runs.iter().map(|r| r.seed()).collect::<Vec<_>>(),
        seeds[..2]
    );
    assert_eq!(grid(1, 9).runs.len(), 1);
    assert_ne!(grid(3, 10).runs[1].seed(), seeds[1]);
}

#[test]
fn bad_seed_lists_and_counts_are_refused() {
    let refusal = |text: String| {
        Grid::from_toml(&text, false)
            .err()
            .unwrap_or_else(|| panic!("accepted {text}"))
            .to_string()
    };
    let with_scene = |line: &str| BASE.replace("[scene]", &format!("[scene]\n{line}"));
    let with_top = |line: &str| BASE.replace("[scene]", &format!("{line}\n[scene]"));
    for (text, expected) in [
        (
            with_scene("seed = []"),
            "scene g_000: `seed = []` lists no seed",
        ),
        (
            with_scene("seed = [1, 2, 1]"),
            "scene g_000: `seed` lists 1 twice",
        ),
        (
            with_scene("seed = [1, -2]"),
            "seed -2 is not a non-negative integer",
        ),
        (
            with_scene("seed = [1, \"x\"]"),
            "seed \"x\" is not a non-negative integer",
        ),
        (
            with_top("replicas = 0"),
            "`replicas = 0`: a scene needs at least one replica",
        ),
        (with_top("replicas = -3"), "`replicas = -3`"),
        (
            with_scene("replicas = 3"),
            "`replicas` is a key of the grid, not of a scene",
        ),
        (
            with_top("replicas = 2").replace("[scene]", "[scene]\nseed = [1, 2]"),
            "`seed` lists 2 seeds and the grid sets `replicas`",
        ),
        (
            with_top("replicas = 9223372036854775807"),
            "expands to 9.223372036854776e18 runs (1 case(s) x 1.0 [vary] combinations",
        ),
        (
            with_top("replicas = 100000000"),
            "expands to 1e8 runs (1 case(s) x 1.0 [vary] combinations x 100000000 replica(s)), \
             more than 100000",
        ),
        (
            // 20 lists of 10 values: 1e20 scenes, refused before any is built.
            format!(
                "{BASE}\n[vary]\n{}",
                (0..20)
                    .map(|k| format!("\"run.x{k}\" = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]\n"))
                    .collect::<String>()
            ),
            "expands to 1e20 runs (1 case(s) x 1e20 [vary] combinations",
        ),
    ] {
        let message = refusal(text);
        assert!(
            message.contains(expected),
            "{message} should say {expected}"
        );
    }
}

#[test]
fn duplicate_scenes_are_refused() {
    let refusal = |extra: &str| {
        Grid::from_toml(&format!("{BASE}\n{extra}"), false)
            .unwrap_err()
            .to_string()
    };
    let message = refusal("[vary]\nseed = [1, 2, 1]\n");
    assert!(message.contains("vary.\"seed\" lists 1 twice"), "{message}");
    let message = refusal("[[cases]]\nseed = 2\n[[cases]]\nseed = 3\n[[cases]]\nseed = 2\n");
    assert!(
        message.contains("cases[0] and cases[2] are the same case"),
        "{message}"
    );
    let message = refusal("[[cases]]\nname = \"x\"\n");
    assert!(message.contains("cases[0] sets `name`"), "{message}");
    // Issue 31, class 15: one scene spelled two ways is one scene, refused as twice.
    for (extra, expected) in [
        (
            "[vary]\n\"box.l_y\" = [12, 12.0]\n",
            "scenes g_000 and g_001 are the same scene (seed 1) with values spelled two ways",
        ),
        (
            "[[cases]]\nfluid = { profile = \"0.1*sin(2*pi*y/L)\" }\n\
             [[cases]]\nfluid = { profile = \"0.1*sin(2*pi*y/L) \" }\n",
            "scenes g_000 and g_001 are the same scene",
        ),
        (
            "[[cases]]\nfluid.profile = \"0.1 * sin(2*pi*y/L)\"\n\
             [[cases]]\nfluid = { profile = \"0.1*sin(2*pi*y/L)\" }\n",
            "scenes g_000 and g_001 are the same scene",
        ),
        (
            "[[cases]]\nseed = [3]\n[[cases]]\nseed = 3\n",
            "scenes g_000 and g_001 are the same scene (seed 3)",
        ),
        ("[vary]\nname = [\"a\", \"b\"]\n", "[vary] lists `name`"),
    ] {
        let message = refusal(extra);
        assert!(message.contains(expected), "{extra}: {message}");
    }
}

#[test]
fn every_shipped_grid_expands_into_valid_scenes() {
    // The grids in grids/ (the SLURM ones included) are read by commands a user runs days
    // later: each must still parse and every scene validate with the current code.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../grids");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let grid =
                Grid::from_path(&path, false).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(!grid.runs.is_empty(), "{}", path.display());
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} grids");
}

/// A grid on a base: the base's `[scene]` (through its own base) with this grid's entries set
/// on it section by section gives the scenes the whole scene written out gives; the base's
/// name, [vary] and cases are not taken; a base not found, a cycle of bases and a base in
/// text read without its file are refused.
#[test]
fn a_grid_on_a_base_is_the_grid_written_out() {
    let dir = std::env::temp_dir().join(format!("grid-base-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(
        dir.join("root.toml"),
        format!(
            "{BASE}run = {{ sample_strain = 0.02, window_strain = 0.2 }}\n[vary]\nseed = [7, 8]\n"
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/middle.toml"),
        "name = \"m\"\nbase = \"../root.toml\"\n[scene]\nparticles = { phi = 0.45 }\n",
    )
    .unwrap();
    let child = dir.join("child.toml");
    std::fs::write(
        &child,
        "name = \"c\"\nbase = \"sub/middle.toml\"\n[scene]\nrun = { window_strain = 0.4 }\n\
         [vary]\n\"box.l_y\" = [12.0, 16.0]\n",
    )
    .unwrap();
    let written_out = r#"
name = "c"
[scene]
box = { l_x = 8.0, l_y = 12.0, l_z = 8.0 }
particles = { phi = 0.45 }
fluid = { profile = "0.1*sin(2*pi*y/L)" }
run = { sample_strain = 0.02, window_strain = 0.4 }
[vary]
"box.l_y" = [12.0, 16.0]
"#;
    let on_base = Grid::from_path(&child, false).unwrap();
    let whole = Grid::from_toml(written_out, false).unwrap();
    assert_eq!(on_base.runs.len(), 2, "the base's seeds are not taken");
    for (a, b) in on_base.runs.iter().zip(&whole.runs) {
        assert_eq!(a.id, b.id);
        assert_eq!(
            serde_json::to_string(&a.scene.file).unwrap(),
            serde_json::to_string(&b.scene.file).unwrap()
        );
    }
    assert_eq!(on_base.runs[0].scene.file.run.sample_strain, 0.02);
    assert_eq!(on_base.runs[1].scene.file.particles.phi, 0.45);

    let text = std::fs::read_to_string(&child).unwrap();
    let refused = Grid::from_toml(&text, false).unwrap_err().to_string();
    assert!(refused.contains("read the grid from its file"), "{refused}");
    let refusal = |name: &str, base: &str| {
        let path = dir.join(name);
        std::fs::write(&path, format!("name = \"r\"\nbase = \"{base}\"\n")).unwrap();
        Grid::from_path(&path, false).unwrap_err().to_string()
    };
    let refused = refusal("lost.toml", "nowhere.toml");
    assert!(refused.contains("nowhere.toml"), "{refused}");
    let refused = refusal("loop.toml", "loop.toml");
    assert!(refused.contains("a cycle?"), "{refused}");
    std::fs::remove_dir_all(&dir).ok();
}
