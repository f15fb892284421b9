//! The densest volume fraction the initial packing reaches, and how long it takes: the
//! measurement behind `scene_limits::PHI_MAX` and `scene_limits::MIXTURE_PHI_MAX`.
//!
//! For each radii set (the default 1 : 1.4 in equal numbers, monodisperse, and the widest
//! size ratio a scene accepts in practice, 1 : 3), packs a cubic box at rising phi with
//! the run's own packer and gap (`random_packing`, `PACKING_GAP`) from three seeds, and
//! prints per phi the seeds that packed and the wall time of each. With `mixture` and grain
//! shares `alpha`, packs the colloid-grain mixtures of `[particles.mixture]` (its default
//! species, radii 1 : 1.4 and 5 : 7, each radius an equal share of its species' volume)
//! instead, from phi 0.64 and from one seed (a box of the thesis' size takes seconds to
//! pack and minutes to give up).
//!
//! `cargo run --release -p sim --example densest_packing -- [box side] [phi step]`
//! (default 16 and 0.005, from phi 0.62);
//! `cargo run --release -p sim --example densest_packing -- 66 0.02 mixture 0.4 0.6 0.7`.
use rand::{rngs::StdRng, SeedableRng};
use sim::input::initial_state::PACKING_GAP;
use sim::input::packing::random_packing;
use sim::input::scene_file::MixtureSection;
use std::f64::consts::PI;
use std::time::Instant;

const SEEDS: [u64; 3] = [1, 2, 3];

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let side: f64 = args.get(1).map_or(16.0, |a| a.parse().expect("box side"));
    let step: f64 = args.get(2).map_or(0.005, |a| a.parse().expect("phi step"));
    if args.get(3).map(String::as_str) == Some("mixture") {
        for alpha in &args[4..] {
            let mixture: MixtureSection =
                toml::from_str(&format!("alpha = {alpha}")).expect("grain share alpha");
            let (radii, fractions) = mixture.species();
            println!("alpha {alpha}: radii {radii:?}, number fractions {fractions:?}");
            pack_rising(&radii, &fractions, side, (0.64, step), &SEEDS[..1]);
        }
        return;
    }
    for radii_set in [[1.0, 1.4], [1.0, 1.0], [1.0, 3.0]] {
        println!("radii {radii_set:?} in equal numbers, box {side}^3");
        pack_rising(&radii_set, &[0.5, 0.5], side, (0.62, step), &SEEDS);
    }
}

/// Packs `radii` in the number `fractions` into a cubic box of `side` at phi rising from
/// `start` by `step`, from each of `seeds`, until no seed packs; prints each phi's outcome.
fn pack_rising(
    radii: &[f64],
    fractions: &[f64],
    side: f64,
    (start, step): (f64, f64),
    seeds: &[u64],
) {
    let mean_volume: f64 = radii
        .iter()
        .zip(fractions)
        .map(|(a, f)| f * 4.0 / 3.0 * PI * a * a * a)
        .sum();
    let mut phi = start;
    loop {
        let n = phi * side.powi(3) / mean_volume;
        let placed: Vec<f64> = radii
            .iter()
            .zip(fractions)
            .flat_map(|(&a, f)| std::iter::repeat_n(a, (f * n).round() as usize))
            .collect();
        let mut packed = 0;
        let mut times = Vec::new();
        for &seed in seeds {
            let started = Instant::now();
            let ok = random_packing(
                &placed,
                [side; 3],
                &mut StdRng::seed_from_u64(seed),
                PACKING_GAP,
            )
            .is_ok();
            times.push(format!(
                "{:.2} s{}",
                started.elapsed().as_secs_f64(),
                if ok { "" } else { " (jammed)" }
            ));
            packed += usize::from(ok);
        }
        println!(
            "  phi {phi:.3}, N = {}: {packed} of {} seeds packed; {}",
            placed.len(),
            seeds.len(),
            times.join(", ")
        );
        if packed == 0 {
            break;
        }
        phi += step;
    }
}
