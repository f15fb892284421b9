//! Colloid-grain mixtures given by their composition (`[particles.mixture]`): a grid over
//! alpha at fixed liquid volume and at fixed phi, the scenes written back out and read
//! again, and the refusals naming the field.
use sim::input::grid::Grid;
use sim::input::initial_state::{initial_particles, PACKING_GAP};
use sim::input::scene::Scene;
use sim::state::periodic_box::PeriodicBox;

/// A sheared Brownian box wide enough for grains of radius 7 (three neighbour cells of
/// 14.8 a along y: the lubrication taper reaches 0.7 a past contact), Pe_c = 1.
const BASE: &str = r#"
[scene]
box = { l_x = 46.0, l_y = 46.0, l_z = 46.0 }
fluid = { shear_rate = 0.01, peclet = 1.0 }
[scene.particles]
rho = 0.1
"#;

#[test]
fn adding_grains_at_fixed_liquid_volume_follows_the_thesis_protocol() {
    let text = format!(
        "name = \"add\"\n{BASE}\n\
         [scene.particles.mixture]\ninitial = {{ species = \"colloids\", phi = 0.55 }}\n\
         [vary]\n\"particles.mixture.alpha\" = [0.0, 0.1, 0.3]\n"
    );
    let grid = Grid::from_toml(&text, false).unwrap();
    // Thesis section 5.1: 0.55, 0.576, 0.636 (three digits as printed).
    for (run, (alpha, phi)) in grid
        .runs
        .iter()
        .zip([(0.0, 0.55), (0.1, 0.576), (0.3, 0.636)])
    {
        let s = &run.scene;
        assert!(
            (s.file.particles.phi - phi).abs() < 6e-4,
            "{alpha}: {}",
            s.file.particles.phi
        );
        let c = s.composition.unwrap();
        assert_eq!(c.alpha, alpha);
        // The counts are integers, each species rounded on its own: its volume is off by
        // at most half a particle's, so alpha by half a grain of each radius over the
        // solid volume (0.02 at alpha 0.1, with 7 grains in this box) and phi by half a
        // particle of each radius over the box.
        let box_volume = 46.0f64.powi(3);
        let volume = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let alpha_bound = 0.5 * (volume(5.0) + volume(7.0)) / (phi * box_volume);
        let phi_bound = [1.0, 1.4, 5.0, 7.0].map(volume).iter().sum::<f64>() / (2.0 * box_volume);
        assert!((c.alpha_actual - alpha).abs() <= alpha_bound, "{c:?}");
        assert!((s.phi_actual - s.file.particles.phi).abs() <= phi_bound);
        // Pe_cg = Pe_c (a_cg / a_c)^3 with a_cg = (1 - alpha) + 5 alpha.
        let a_cg = 1.0 + 4.0 * alpha;
        assert!((c.peclet_c.unwrap() - 1.0).abs() < 1e-12);
        assert!((c.peclet_cg.unwrap() - a_cg.powi(3)).abs() < 1e-9 * a_cg.powi(3));
        let species = if alpha == 0.0 { 2 } else { 4 };
        assert_eq!(s.counts.len(), species, "{:?}", s.file.particles.radii);
    }
}

#[test]
fn the_peclet_number_of_a_mixture_is_the_colloids_even_without_colloids() {
    // alpha = 1 places only grains (radii 5 and 7), yet fluid.peclet is Pe_c: kT follows
    // from the colloid radius 1, kT = 6 pi eta a_c^3 gdot / Pe_c, not from the smallest
    // radius placed (which would give Pe_g = 125 Pe_c = 1).
    let text = format!(
        "name = \"grains\"\n{BASE}\n\
         [scene.particles.mixture]\nalpha = 1.0\ninitial = {{ species = \"grains\", phi = 0.55 }}\n"
    );
    let s = &Grid::from_toml(&text, false).unwrap().runs[0].scene;
    assert_eq!(s.file.particles.radii, vec![5.0, 7.0]);
    let kt = 6.0 * std::f64::consts::PI * 0.01;
    assert!(
        (s.file.fluid.kt - kt).abs() < 1e-12 * kt,
        "{}",
        s.file.fluid.kt
    );
    let c = s.composition.unwrap();
    assert!((c.peclet_c.unwrap() - 1.0).abs() < 1e-12);
    assert!((c.peclet_cg.unwrap() - 125.0).abs() < 1e-9);
}

#[test]
fn a_mixture_scene_written_out_reads_back_the_same() {
    // `generate` writes each scene's validated file into its work folder and `simulate`
    // reads it there: the expansion must find its own output consistent.
    let text = format!(
        "name = \"add\"\n{BASE}\n\
         [scene.particles.mixture]\nalpha = 0.7\ninitial = {{ species = \"grains\", phi = 0.55 }}\n"
    );
    let first = &Grid::from_toml(&text, false).unwrap().runs[0].scene;
    let written = toml::to_string(&first.file).unwrap();
    let again = Scene::from_toml(&written, false).unwrap();
    assert_eq!(again.file.particles.radii, first.file.particles.radii);
    assert_eq!(
        again.file.particles.fractions,
        first.file.particles.fractions
    );
    assert_eq!(again.file.particles.phi, first.file.particles.phi);
    assert_eq!(again.counts, first.counts);
    assert_eq!(again.composition, first.composition);
    assert!((first.file.particles.phi - 0.636).abs() < 6e-4);
}

#[test]
fn at_fixed_phi_alpha_changes_only_the_species() {
    let text = format!(
        "name = \"fixed\"\n{BASE}\n\
         [scene.particles.mixture]\nalpha = 0.5\n\
         [vary]\n\"particles.phi\" = [0.565]\n\"particles.mixture.alpha\" = [0.2, 0.5]\n"
    );
    let grid = Grid::from_toml(&text, false).unwrap();
    let shares: Vec<f64> = grid
        .runs
        .iter()
        .map(|r| {
            assert_eq!(r.scene.file.particles.phi, 0.565);
            r.scene.composition.unwrap().alpha_actual
        })
        .collect();
    assert!(
        (shares[0] - 0.2).abs() < 0.02 && (shares[1] - 0.5).abs() < 0.02,
        "{shares:?}"
    );
}

#[test]
fn contradictions_and_gaps_are_refused_naming_the_field() {
    let scene = |particles: &str| {
        Scene::from_toml(
            &format!(
                "[box]\nl_x = 46.0\nl_y = 46.0\nl_z = 46.0\n[fluid]\nshear_rate = 0.01\n\
                 [particles]\n{particles}\n"
            ),
            false,
        )
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    let cases = [
        ("", "particles.phi"),
        (
            "phi = 0.6\nmixture = { alpha = 0.7, initial = { species = \"grains\", phi = 0.55 } }",
            "particles.phi",
        ),
        (
            "phi = 0.5\nradii = [1.0, 2.0]\nmixture = { alpha = 0.3 }",
            "particles.radii",
        ),
        (
            "phi = 0.5\nmixture = { alpha = 1.2 }",
            "particles.mixture.alpha",
        ),
        (
            "phi = 0.5\nmixture = { alpha = 0.3, grain_radii = [1.2] }",
            "particles.mixture.grain_radii",
        ),
        (
            "mixture = { alpha = 0.6, initial = { species = \"colloids\", phi = 0.55 } }",
            "particles.mixture.alpha",
        ),
    ];
    for (particles, field) in cases {
        let message = scene(particles);
        assert!(
            message.contains(&format!("`{field}`")),
            "{particles}: {message}"
        );
    }
}

#[test]
fn a_mixture_packs_beyond_the_densest_single_species() {
    // Colloids added to grains at 0.55 until alpha = 0.6 (thesis Fig. 5.2): phi 0.671,
    // beyond the 0.64 at which one species jams. The scene is accepted and its packing is
    // made without a pair closer than the packing gap.
    let scene = |alpha: f64| {
        Scene::from_toml(
            &format!(
                "name = \"dense\"\n[box]\nl_x = 46.0\nl_y = 46.0\nl_z = 46.0\n\
                 [fluid]\nshear_rate = 0.01\n[particles]\nmixture = {{ alpha = {alpha}, \
                 initial = {{ species = \"grains\", phi = 0.55 }} }}\n"
            ),
            false,
        )
    };
    let s = scene(0.6).unwrap();
    assert!(
        (s.file.particles.phi - 0.671).abs() < 6e-4,
        "{}",
        s.file.particles.phi
    );
    let p = initial_particles(&s).unwrap();
    let periodic = PeriodicBox::new(s.box_len);
    let mut closest = f64::INFINITY;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let r = periodic.separation(&p.pos[i], &p.pos[j]).norm();
            closest = closest.min(r / (p.radius[i] + p.radius[j]));
        }
    }
    assert!(closest >= 1.0 + PACKING_GAP / 2.0 * 0.99, "{closest}");
    // The grains alone (alpha = 1 at phi 0.66) are one species again: refused.
    let alone = Scene::from_toml(
        "name = \"alone\"\n[box]\nl_x = 80.0\nl_y = 80.0\nl_z = 80.0\n[fluid]\n\
         shear_rate = 0.01\n[particles]\nphi = 0.66\nmixture = { alpha = 1.0 }\n",
        false,
    )
    .map(|_| ())
    .unwrap_err()
    .to_string();
    assert!(
        alone.contains("`particles.phi`") && alone.contains("0.64"),
        "{alone}"
    );
}
