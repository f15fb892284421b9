//! Grid expansion: the Cartesian product of [vary] times the [[cases]], in the documented
//! order, with every scene validated and named so that ids sort in grid order.
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
    assert_eq!(grid.scenes.len(), 2 * 2 * 3);
    let got: Vec<(f64, f64, u64)> = grid
        .scenes
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
    assert_eq!(
        grid.scenes[6].scene.file.fluid.profile,
        "0.1*sin(2*pi*y/L)^3"
    );
    assert_eq!(grid.scenes[0].scene.file.fluid.profile, "0.1*sin(2*pi*y/L)");
    let ids: Vec<&str> = grid.scenes.iter().map(|s| s.id.as_str()).collect();
    assert_eq!(ids[0], "g_000");
    assert_eq!(ids[11], "g_011");
    assert!(
        ids.windows(2).all(|w| w[0] < w[1]),
        "ids sort in grid order"
    );
    assert!(grid.scenes.iter().all(|s| s.scene.file.name == s.id));
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
}

#[test]
fn stokes_sets_the_density_from_the_profile() {
    // gdot_max = 0.1 * 2 pi / 12; St = rho a^2 gdot_max / eta with a = 1.
    let text = format!("{BASE}\n[vary]\n\"particles.stokes\" = [0.05]\n");
    let scene = &Grid::from_toml(&text, false).unwrap().scenes[0].scene;
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
    assert_eq!(grid.scenes.len(), 1);
    assert_eq!(grid.scenes[0].id, "g_000");
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
}
