//! Brownian forces (docs/physics.md section 11) against the equilibrium they must sample:
//! free spheres (kinetic temperature and long-time diffusion, thesis eq 4.1), and
//! equipartition in a dense suspension at the automatic time step. Seeded, so they cannot
//! flake; each tolerance is stated from its sample size.
use sim::input::initial_state::initial_particles;
use sim::input::scene::Scene;
use sim::integrate::simulation::Simulation;
use sim::Vec3;

/// Thesis Table 4.1 units: a = 1, rho = eta = 0.1, kT = 0.017 (tau_B = 5.9, tau_I = 1).
const TABLE_4_1: &str = "[fluid]\neta = 0.1\nkT = 0.017\n";

fn scene(box_len: f64, phi: f64, extra: &str) -> Scene {
    let text = format!(
        "seed = 3\n[box]\nl_x = {box_len}\nl_y = {box_len}\nl_z = {box_len}\n[particles]\n\
         phi = {phi}\nradii = [1.0]\nrho = 0.1\n{TABLE_4_1}{extra}"
    );
    Scene::from_toml(&text, false).expect("valid test scene")
}

/// Runs `steps` steps after `warmup`, returning the mean kinetic temperatures over kT and
/// every particle's unwrapped displacement since the end of the warm-up at each multiple
/// of `every` steps (by identity).
fn sample(s: &mut Simulation, kt: f64, warmup: u64, steps: u64, every: u64) -> Sampled {
    s.advance(warmup).expect("stable warm-up");
    let n = s.particles.len();
    let mut unwrapped = vec![Vec3::zeros(); n];
    let mut last = vec![Vec3::zeros(); n];
    for (id, x) in s.particles.id.iter().zip(&s.particles.pos) {
        last[*id as usize] = *x;
    }
    let (mut trans, mut rot) = (0.0, 0.0);
    let mut tracks = Vec::new();
    for k in 1..=steps {
        s.step().expect("stable run");
        let (t, r) = s.particles.kinetic_temperatures(kt);
        trans += t;
        rot += r;
        for (id, x) in s.particles.id.iter().zip(&s.particles.pos) {
            let id = *id as usize;
            unwrapped[id] += s.pbox.separation(&last[id], x);
            last[id] = *x;
        }
        if k % every == 0 {
            tracks.push(unwrapped.clone());
        }
    }
    Sampled {
        trans: trans / steps as f64,
        rot: rot / steps as f64,
        tracks,
    }
}

struct Sampled {
    trans: f64,
    rot: f64,
    /// Displacements of every particle at each sampling time.
    tracks: Vec<Vec<Vec3>>,
}

impl Sampled {
    /// Per-component mean squared displacement over `lag` sampling intervals, averaged
    /// over every window start and particle.
    fn msd(&self, lag: usize) -> f64 {
        let mut sum = 0.0;
        let mut count = 0;
        for start in 0..self.tracks.len() - lag {
            for (a, b) in self.tracks[start].iter().zip(&self.tracks[start + lag]) {
                sum += (b - a).norm_squared();
                count += 3;
            }
        }
        sum / count as f64
    }
}

/// Per-component mean squared displacement of a free Langevin sphere (thesis eq 4.1,
/// paper eq 3.1): `2 kT (m / gamma^2) (gamma t / m - 1 + exp(-gamma t / m))`.
fn free_msd(kt: f64, m: f64, gamma: f64, t: f64) -> f64 {
    let s = gamma * t / m;
    2.0 * kt * m / (gamma * gamma) * (s - 1.0 + (-s).exp())
}

/// Free spheres (drag only: 190 of them in a box of 20, no contacts, no lubrication), in
/// Table 4.1 units (kT = 0.017, eta = 0.1) at three inertia-diffusion ratios
/// tau_I/tau_B = 0.017, 0.17, 1.7 (rho = 0.01, 0.1, 1: the step dt = 0.1 is then 2.2, 0.22
/// and 0.022 velocity relaxation times m / (6 pi eta a)): the kinetic temperatures are kT
/// and the long-time diffusion is kT / (6 pi eta a) at any step (the trapezoidal rule is
/// exact for a constant resistance), and the mean squared displacement follows eq 4.1 from
/// the ballistic to the diffusive regime where the step resolves it. Sample sizes: 570
/// components over 4000 time units; the temperature's standard error is below 0.3 %,
/// tolerance 1 %; the diffusion's (slope of the MSD from 10 to 40) about 0.7 %, tolerance 2 %; eq 4.1, 3 %.
#[test]
fn free_spheres_have_the_bath_temperature_and_stokes_einstein_diffusion() {
    let (eta, a, kt, dt) = (0.1, 1.0, 0.017, 0.1);
    let gamma = 6.0 * std::f64::consts::PI * eta * a;
    for rho in [0.01, 0.1, 1.0] {
        let m = 4.0 / 3.0 * std::f64::consts::PI * rho;
        let text = format!(
            "seed = 3\n[box]\nl_x = 20\nl_y = 20\nl_z = 20\n[particles]\nphi = 0.1\n\
             radii = [1.0]\nrho = {rho}\n[fluid]\neta = {eta}\nkT = {kt}\n[forces]\n\
             contact = false\nlubrication = false\n[run]\ndt = {dt}\n"
        );
        let sc = Scene::from_toml(&text, false).unwrap();
        let mut s = Simulation::new(&sc, initial_particles(&sc).unwrap()).unwrap();
        let got = sample(&mut s, kt, 200, 40_000, 5);
        let interval = 5.0 * dt;
        // The long-time slope, past the velocity relaxation (at most 2.2 time units).
        let d = (got.msd(80) - got.msd(20)) / (2.0 * 60.0 * interval);
        let d0 = kt / gamma;
        println!(
            "rho {rho}: T/kT {:.4} {:.4}, D/D0 {:.4}",
            got.trans,
            got.rot,
            d / d0
        );
        assert!((got.trans - 1.0).abs() < 0.01, "translation {}", got.trans);
        assert!((got.rot - 1.0).abs() < 0.01, "rotation {}", got.rot);
        assert!((d / d0 - 1.0).abs() < 0.02, "diffusion {}", d / d0);
        for lag in [1, 4, 20, 80] {
            let t = lag as f64 * interval;
            let (msd, expected) = (got.msd(lag), free_msd(kt, m, gamma, t));
            println!("  t {t}: MSD / eq 4.1 = {:.4}", msd / expected);
            if gamma * dt / m < 1.0 {
                assert!(
                    (msd / expected - 1.0).abs() < 0.03,
                    "rho {rho}: MSD at t = {t} is {msd:e}, eq 4.1 gives {expected:e}"
                );
            }
        }
    }
}

/// A dense suspension (phi 0.45, monodisperse, Table 4.1 state, no flow; 107 spheres) at
/// the automatic time step: translational and rotational kinetic temperatures within 2 %
/// of kT, over 10000 steps after 2000 (the per-step estimate over 321 degrees of freedom
/// has a spread of 8 %, correlated over a few steps: standard error about 0.2 %).
#[test]
fn dense_suspension_is_at_the_bath_temperature() {
    let sc = scene(10.0, 0.45, "");
    let mut s = Simulation::new(&sc, initial_particles(&sc).unwrap()).unwrap();
    let got = sample(&mut s, 0.017, 2000, 10000, 100);
    println!(
        "dt {:e} ({}), N {}: T/kT {:.4} {:.4}",
        s.timestep.dt,
        s.timestep.limit,
        s.particles.len(),
        got.trans,
        got.rot
    );
    assert!((got.trans - 1.0).abs() < 0.02, "translation {}", got.trans);
    assert!((got.rot - 1.0).abs() < 0.02, "rotation {}", got.rot);
}

/// A colloid-grain mixture at rest (radii 1 and 5, the size ratio of thesis chapter 5;
/// alpha = 0.8, phi = 0.35 in a 36^3 box: about 780 colloids and 25 grains; Table 4.1 state, all
/// forces on) at the automatic time step: each species at the bath temperature, in
/// translation and rotation. A grain's noise comes mostly from the colloids in lubrication
/// range of it (pairs of size ratio 5), so an error in those pairs' fluctuation-dissipation
/// balance shows on the grains first. dt = 3.4e-3; 30000 steps (100 time units) after
/// 1000, sampled every 10 steps. The grains' per-sample estimate over 75 degrees of freedom
/// spreads by sqrt(2/75) = 16 %, correlated over half their velocity relaxation time (free
/// drag: m / 6 pi eta a = 5.6 time units; lubrication only shortens it): at least 18
/// independent samples, a standard error of at most 3.8 %, tolerance 12 % (3 standard
/// errors). The colloids' (2340 degrees of freedom, relaxation 0.22) has a standard error
/// near 0.15 %; their tolerance, 2 %, is the step's as for the dense suspension above.
/// Shown to fail: with every pair's noise amplitude 1.2x the colloids read 1.037 and the
/// grains 1.21, six times as far off.
#[test]
fn a_colloid_grain_mixture_is_at_the_bath_temperature_in_each_species() {
    let text = format!(
        "seed = 3\n[box]\nl_x = 36.0\nl_y = 36.0\nl_z = 36.0\n[particles]\nphi = 0.35\n\
         rho = 0.1\nmixture = {{ alpha = 0.8, colloid_radii = [1.0], grain_radii = [5.0] }}\n\
         {TABLE_4_1}"
    );
    let sc = Scene::from_toml(&text, false).expect("valid test scene");
    let mut s = Simulation::new(&sc, initial_particles(&sc).unwrap()).unwrap();
    s.advance(1000).expect("stable warm-up");
    let (mut colloids, mut grains, mut samples) = ([0.0; 2], [0.0; 2], 0.0);
    for k in 1..=30000 {
        s.step().expect("stable run");
        if k % 10 == 0 {
            let c = s.particles.kinetic_temperatures_of(0.017, |a| a < 2.0);
            let g = s.particles.kinetic_temperatures_of(0.017, |a| a > 2.0);
            for (sum, t) in [(&mut colloids, c), (&mut grains, g)] {
                sum[0] += t.0;
                sum[1] += t.1;
            }
            samples += 1.0;
        }
    }
    let (colloids, grains) = (colloids.map(|t| t / samples), grains.map(|t| t / samples));
    println!(
        "dt {:e} ({}), counts {:?}: colloids T/kT {colloids:.4?}, grains {grains:.4?}",
        s.timestep.dt, s.timestep.limit, sc.counts
    );
    for t in colloids {
        assert!((t - 1.0).abs() < 0.02, "colloids {colloids:?}");
    }
    for t in grains {
        assert!((t - 1.0).abs() < 0.12, "grains {grains:?}");
    }
}

/// The potential of mean force of two spheres (paper Fig. 2a,b; thesis Fig. 4.1) in a
/// small periodic cube, all forces on, no flow, at the automatic time step: `-ln g(r)`
/// in shells from contact to past the lubrication cut-off, for radii 1 : 1 and 1 : 1.4.
/// Flat within 0.05 kT (plus twice each shell's standard error from 10 blocks): 4e7
/// steps, about 140 time units of relative diffusion across the box per block.
#[test]
#[ignore = "long: 3-5 minutes per radius pair; run with --ignored"]
fn two_spheres_have_a_flat_potential_of_mean_force() {
    let steps: u64 = std::env::var("PMF_STEPS").map_or(40_000_000, |s| s.parse().unwrap());
    let cases = [("[1.0]", 4.4, 0.0), ("[1.0, 1.4]", 6.0, 0.0)];
    let only: usize = std::env::var("PMF_CASES").map_or(2, |s| s.parse().unwrap());
    for &(radii, box_len, phi) in &cases[..only] {
        let volume: f64 = box_len * box_len * box_len;
        let a: Vec<f64> = if radii == "[1.0]" {
            vec![1.0, 1.0]
        } else {
            vec![1.0, 1.4]
        };
        let solid: f64 = a
            .iter()
            .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r * r * r)
            .sum();
        let phi = if phi > 0.0 { phi } else { solid / volume };
        let text = format!(
            "seed = 5\n[box]\nl_x = {box_len}\nl_y = {box_len}\nl_z = {box_len}\n[particles]\n\
             phi = {phi}\nradii = {radii}\nrho = 0.1\n{TABLE_4_1}[run]\nbin_width = {}\nintegrator = \"{}\"\ndt_factor = {}\n",
            box_len / 4.0,
            std::env::var("INTEGRATOR").unwrap_or("implicit".into()),
            std::env::var("DTF").unwrap_or("1".into())
        );
        let sc = Scene::from_toml(&text, false).unwrap();
        let mut s = Simulation::new(&sc, initial_particles(&sc).unwrap()).unwrap();
        assert_eq!(s.particles.len(), 2);
        let contact = a[0] + a[1];
        // Shell edges in the gap xi = 2 (r - contact) / contact.
        let edges_xi = [
            -0.004, 0.0, 0.001, 0.003, 0.006, 0.01, 0.02, 0.035, 0.05, 0.065, 0.08, 0.1, 0.13, 0.16,
        ];
        let edges: Vec<f64> = edges_xi.iter().map(|x| contact * (1.0 + 0.5 * x)).collect();
        let blocks = 10;
        let mut counts = vec![vec![0u64; edges.len() - 1]; blocks];
        for step in 0..steps {
            s.step().unwrap();
            let r = s
                .pbox
                .separation(&s.particles.pos[0], &s.particles.pos[1])
                .norm();
            if let Some(k) = (0..edges.len() - 1).find(|&k| r >= edges[k] && r < edges[k + 1]) {
                counts[(step * blocks as u64 / steps) as usize][k] += 1;
            }
        }
        println!(
            "radii {radii}: dt {:e} ({})",
            s.timestep.dt, s.timestep.limit
        );
        // -ln g per shell over the whole run, and its standard error from the blocks.
        let per_block = steps as f64 / blocks as f64;
        let mut levels = Vec::new();
        for k in 0..edges.len() - 1 {
            let shell =
                4.0 / 3.0 * std::f64::consts::PI * (edges[k + 1].powi(3) - edges[k].powi(3));
            let ideal = shell / volume;
            let g: Vec<f64> = counts
                .iter()
                .map(|c| c[k] as f64 / (per_block * ideal))
                .collect();
            let mean = g.iter().sum::<f64>() / blocks as f64;
            let sd =
                (g.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (blocks - 1) as f64).sqrt();
            let se = sd / (blocks as f64).sqrt() / mean;
            println!(
                "  xi {:>7.4}..{:>7.4}: counts {:>9}, -ln g = {:+.3} +- {:.3}",
                edges_xi[k],
                edges_xi[k + 1],
                counts.iter().map(|c| c[k]).sum::<u64>(),
                -mean.ln(),
                se
            );
            levels.push((edges_xi[k], -mean.ln(), se));
        }
        let outside: Vec<_> = levels.iter().filter(|l| l.0 >= 0.0).collect();
        let reference = outside.iter().map(|l| l.1).sum::<f64>() / outside.len() as f64;
        for (xi, level, se) in &outside {
            assert!(
                (level - reference).abs() < 0.05 + 2.0 * se,
                "radii {radii}: -ln g at xi {xi} is {level:+.3} +- {se:.3}, the mean {reference:+.3}"
            );
        }
    }
}

/// Hard-sphere structure at equilibrium (BROWNIAN.md V4): monodisperse spheres at phi 0.30
/// and 0.40, no flow, Table 4.1 state (k_n = 1e4 a kT / 0.017: overlaps of order 1e-3 a),
/// 1000 spheres, 20 tau_B of averaging. Three estimates of the contact value against
/// Carnahan-Starling, g(sigma) = (1 - phi/2) / (1 - phi)^3, each within 10 %:
/// - g(sigma+) from a histogram of the pair distances over [sigma, 1.1 sigma], extrapolated
///   to contact by a straight line through ln g (independent of the stress code);
/// - the structural Brownian pressure (thesis eq 3.54, `P_brownian` of the run's summary),
///   whose expected value is the contact virial `4 phi g(sigma) n kT`;
/// - the contact springs' pressure (`P_contact`), the same virial measured by the forces.
///
/// About 900 pairs per snapshot fall in the histogram's range and 200 in the shell, over
/// 400 snapshots 0.05 tau_B apart: the sampling error of each estimate is about 1-2 %.
#[test]
#[ignore = "long: about 2 minutes per volume fraction on a quiet core; run with --ignored"]
fn equilibrium_structure_matches_carnahan_starling() {
    use sim::run::{run, RunOptions};
    let n: f64 = std::env::var("V4_N").map_or(1000.0, |s| s.parse().unwrap());
    for phi in [0.30, 0.40] {
        let l = (n * 4.0 / 3.0 * std::f64::consts::PI / phi).cbrt();
        let text = format!(
            "name = \"hs{phi}\"\nseed = 9\n[box]\nl_x = {l}\nl_y = {l}\nl_z = {l}\n[particles]\n\
             phi = {phi}\nradii = [1.0]\nrho = 0.1\n{TABLE_4_1}[run]\nbin_width = {}\n\
             sample_strain = 0.05\nwindow_strain = 2.0\nmax_strain = 40.0\nsteady_chi2 = 1e9\n\
             snapshots = 400\nblocks = 10\n",
            l / 4.0
        );
        let sc = Scene::from_toml(&text, false).unwrap();
        let (sigma, width, bins) = (2.0, 0.2, 20);
        let mut hist = vec![0u64; bins];
        let mut snapshots = 0;
        let outcome = run(&sc, &RunOptions::default(), &mut |p, s| {
            if p.phase != sim::run::Phase::Averaging || p.snapshots <= snapshots {
                return;
            }
            snapshots = p.snapshots;
            let pos = &s.particles.pos;
            for i in 0..pos.len() {
                for j in i + 1..pos.len() {
                    let d = s.pbox.separation(&pos[i], &pos[j]).norm();
                    let k = ((d - sigma) / width * bins as f64).floor();
                    if (0.0..bins as f64).contains(&k) {
                        hist[k as usize] += 1;
                    }
                }
            }
        })
        .expect("equilibrium run");
        let count = sc.counts.iter().sum::<usize>() as f64;
        let density = count / (l * l * l);
        let dr = width / bins as f64;
        // ln g at each shell's centre, fitted by least squares and evaluated at contact.
        let points: Vec<(f64, f64)> = hist
            .iter()
            .enumerate()
            .map(|(k, &c)| {
                let (lo, hi) = (sigma + k as f64 * dr, sigma + (k + 1) as f64 * dr);
                let shell = 4.0 / 3.0 * std::f64::consts::PI * (hi.powi(3) - lo.powi(3));
                let ideal = 0.5 * count * density * shell * snapshots as f64;
                (0.5 * (lo + hi) - sigma, (c as f64 / ideal).ln())
            })
            .collect();
        let m = points.len() as f64;
        let (sx, sy) = points
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        let (mx, my) = (sx / m, sy / m);
        let slope = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum::<f64>()
            / points.iter().map(|(x, _)| (x - mx).powi(2)).sum::<f64>();
        let g_histogram = (my - slope * mx).exp();
        let cs = (1.0 - phi / 2.0) / (1.0 - phi).powi(3);
        let phi_actual = sc.phi_actual;
        let virial = |key: &str| {
            outcome.summary.stress_parts[key].mean / (density * 0.017) / (4.0 * phi_actual)
        };
        let (g_brownian, g_contact) = (virial("P_brownian"), virial("P_contact"));
        println!(
            "phi {phi} (actual {phi_actual:.4}, N {}, {snapshots} snapshots): g(sigma) \
             Carnahan-Starling {cs:.3}, histogram {g_histogram:.3}, structural Brownian \
             {g_brownian:.3}, contact {g_contact:.3}; P_brownian / nkT {:.3} (CS {:.3})",
            count,
            4.0 * phi_actual * g_brownian,
            4.0 * phi * cs
        );
        for (what, g) in [
            ("histogram", g_histogram),
            ("structural Brownian", g_brownian),
            ("contact", g_contact),
        ] {
            assert!(
                (g / cs - 1.0).abs() < 0.10,
                "phi {phi}: {what} contact value {g:.3} vs Carnahan-Starling {cs:.3}"
            );
        }
    }
}

/// Long-time self-diffusion against phi (BROWNIAN.md V5; paper Fig. 2f, thesis Fig. 4.2d):
/// bidisperse spheres (1 : 1.4, the default fractions), no flow, kT = 0.017, eta = 0.1, at
/// two inertia-diffusion ratios tau_I/tau_B = 0.17 (rho = 0.1, Table 4.1) and 0.017
/// (rho = 0.01), phi 0.1-0.5, 1000 spheres, at the automatic step. The small spheres'
/// diffusion D (slope of the per-component mean squared displacement between lags of 3 and
/// 9 tau_B, from every window start over 12 tau_B after 6 tau_B of warm-up: at phi 0.5 the
/// suspension still ages after 2 tau_B) over kT / (6 pi eta a): the two ratios agree within
/// 5 % at every phi, D falls with phi, and linearly (R^2 > 0.95). The sampling error of each D
/// is about 1.5 % (about 1400 small-sphere components, several independent 3-tau_B windows),
/// 2 % on the ratio. `V5_PHI`, `V5_WARMUP`, `V5_SPAN` (tau_B) change the defaults.
#[test]
#[ignore = "long: about 20-30 minutes on a quiet core; run with --ignored"]
fn self_diffusion_does_not_depend_on_inertia() {
    let n: f64 = std::env::var("V5_N").map_or(1000.0, |s| s.parse().unwrap());
    let (eta, kt) = (0.1, 0.017);
    let d0 = kt / (6.0 * std::f64::consts::PI * eta);
    let mut previous = f64::INFINITY;
    let mut curve = Vec::new();
    let env = |name: &str, default: &str| std::env::var(name).unwrap_or(default.into());
    let phis: Vec<f64> = env("V5_PHI", "0.1 0.2 0.3 0.4 0.5")
        .split_whitespace()
        .map(|p| p.parse().unwrap())
        .collect();
    // Warm-up and span of the tracks in tau_B; the slope is taken between lags of a quarter
    // and three quarters of the span.
    let warmup: u64 = env("V5_WARMUP", "6").parse().unwrap();
    let span: u64 = env("V5_SPAN", "12").parse().unwrap();
    for &phi in &phis {
        let mut ds = Vec::new();
        for rho in [0.1, 0.01] {
            // Mean sphere volume of the default 1 : 1.4 mixture at equal number fractions.
            let v = 0.5 * 4.0 / 3.0 * std::f64::consts::PI * (1.0 + 1.4f64.powi(3));
            let l = (n * v / phi).cbrt();
            let text = format!(
                "seed = 4\n[box]\nl_x = {l}\nl_y = {l}\nl_z = {l}\n[particles]\nphi = {phi}\n\
                 rho = {rho}\n[fluid]\neta = {eta}\nkT = {kt}\n[run]\nbin_width = {}\n",
                l / 4.0
            );
            let sc = Scene::from_toml(&text, false).unwrap();
            let tau_b = sc.thermal.unwrap().tau_b;
            let mut s = Simulation::new(&sc, initial_particles(&sc).unwrap()).unwrap();
            let per_tau = (tau_b / s.timestep.dt).round() as u64;
            let every = per_tau / 10;
            let got = sample(&mut s, kt, warmup * per_tau, span * per_tau, every);
            let mut small = vec![false; s.particles.len()];
            for (id, a) in s.particles.id.iter().zip(&s.particles.radius) {
                small[*id as usize] = *a < 1.2;
            }
            let msd = |lag: usize| {
                let (mut sum, mut count) = (0.0, 0);
                for start in 0..got.tracks.len() - lag {
                    for (k, (a, b)) in got.tracks[start]
                        .iter()
                        .zip(&got.tracks[start + lag])
                        .enumerate()
                    {
                        if small[k] {
                            sum += (b - a).norm_squared();
                            count += 3;
                        }
                    }
                }
                sum / count as f64
            };
            let interval = every as f64 * s.timestep.dt;
            let (short, long) = (span as usize * 10 / 4, span as usize * 30 / 4);
            let d = (msd(long) - msd(short)) / (2.0 * (long - short) as f64 * interval) / d0;
            println!(
                "phi {phi}, tau_I/tau_B {:.3}: N {}, dt {:.3e} ({} steps per tau_B), D/D0 {d:.4}, \
                 T/kT {:.4}",
                sc.thermal.unwrap().inertia_diffusion,
                s.particles.len(),
                s.timestep.dt,
                per_tau,
                got.trans
            );
            ds.push(d);
        }
        let ratio = ds[1] / ds[0];
        println!("phi {phi}: D(0.017) / D(0.17) = {ratio:.4}");
        assert!((ratio - 1.0).abs() < 0.05, "phi {phi}: ratio {ratio}");
        assert!(ds[0] < previous, "D does not fall with phi at {phi}");
        previous = ds[0];
        curve.push((phi, ds[0]));
    }
    // "Linearly decreasing" (paper section 3.1): the straight line through D(phi) explains
    // more than 95 % of its variance.
    if curve.len() < 3 {
        return;
    }
    let m = curve.len() as f64;
    let (mx, my) = (
        curve.iter().map(|c| c.0).sum::<f64>() / m,
        curve.iter().map(|c| c.1).sum::<f64>() / m,
    );
    let sxy: f64 = curve.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = curve.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let syy: f64 = curve.iter().map(|(_, y)| (y - my).powi(2)).sum();
    let r2 = sxy * sxy / (sxx * syy);
    println!(
        "D/D0 = {my:.3} + {:.3} (phi - {mx:.2}), R^2 {r2:.4}",
        sxy / sxx
    );
    assert!(r2 > 0.95, "R^2 of the linear fit {r2}");
}
