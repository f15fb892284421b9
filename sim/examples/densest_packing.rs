//! The densest volume fraction the initial packing reaches, and how long it takes: the
//! measurement behind `scene_limits::PHI_MAX`.
//!
//! For each radii set (the default 1 : 1.4 in equal numbers, monodisperse, and the widest
//! size ratio a scene accepts in practice, 1 : 3), packs a cubic box at rising phi with
//! the run's own packer and gap (`random_packing`, `PACKING_GAP`) from three seeds, and
//! prints per phi the seeds that packed and the wall time of each.
//!
//! `cargo run --release -p sim --example densest_packing -- [box side] [phi step]`
//! (default 16 and 0.005, from phi 0.62).
use rand::{rngs::StdRng, SeedableRng};
use sim::input::initial_state::PACKING_GAP;
use sim::input::packing::random_packing;
use std::time::Instant;

const SEEDS: [u64; 3] = [1, 2, 3];

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let side: f64 = args.get(1).map_or(16.0, |a| a.parse().expect("box side"));
    let step: f64 = args.get(2).map_or(0.005, |a| a.parse().expect("phi step"));
    for radii_set in [[1.0, 1.4], [1.0, 1.0], [1.0, 3.0]] {
        println!("radii {radii_set:?} in equal numbers, box {side}^3");
        let mean_volume: f64 = radii_set
            .iter()
            .map(|a| 4.0 / 3.0 * std::f64::consts::PI * a * a * a)
            .sum::<f64>()
            / radii_set.len() as f64;
        let mut phi = 0.62;
        loop {
            let n = (phi * side.powi(3) / mean_volume).round() as usize;
            let radii: Vec<f64> = (0..n).map(|i| radii_set[i % radii_set.len()]).collect();
            let mut packed = 0;
            let mut times = Vec::new();
            for seed in SEEDS {
                let started = Instant::now();
                let ok = random_packing(
                    &radii,
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
                "  phi {phi:.3}, N = {n}: {packed} of {} seeds packed; {}",
                SEEDS.len(),
                times.join(", ")
            );
            if packed == 0 {
                break;
            }
            phi += step;
        }
    }
}
