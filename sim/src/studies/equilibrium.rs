//! What a Brownian scene at rest must sample (docs/physics.md section 11), measured on one
//! run: the pair structure from contact to past the lubrication cut-off (g of the
//! mean-radius gap `xi`, and the jump of `-ln g` across `xi_max`), the kinetic
//! temperatures of each species, and the pressures of the contact springs, the structural
//! Brownian shell and the lubrication against the Carnahan-Starling hard-sphere value.
//!
//! Three of these share no code with the stress sums: the pair histogram, the
//! temperatures and the Carnahan-Starling reference. The pressures are the run's own
//! stress parts (`P_contact`, `P_brownian`, `P_lubrication`).
use crate::input::scene::Scene;
use crate::integrate::simulation::Simulation;
use crate::run::{run, Phase, RunOptions};
use crate::sampling::block_sums::Estimate;
use crate::sampling::species_temperatures::SpeciesTemperature;
use crate::state::particles::sphere_volume;
use crate::SimError;
use serde::{Deserialize, Serialize};

/// Gap shells `xi` (mean-radius gap `2 (r - a_i - a_j) / (a_i + a_j)`) of the histogram:
/// the overlaps, the regularised gaps below `xi_min = 1e-3`, the lubricated ones, the
/// default taper from `xi_max = 0.05` to 0.1 and three shells beyond it.
pub const GAP_EDGES: [f64; 17] = [
    -0.01, 0.0, 0.001, 0.003, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.10, 0.11,
    0.12, 0.13,
];

/// The Carnahan-Starling contact value of hard spheres at volume fraction `phi`,
/// `g(sigma) = (1 - phi / 2) / (1 - phi)^3`.
pub fn carnahan_starling_contact(phi: f64) -> f64 {
    (1.0 - phi / 2.0) / (1.0 - phi).powi(3)
}

/// The Barker-Henderson diameter of spheres of diameter `sigma` joined by a Hookean
/// contact of stiffness `k_n` at thermal energy `kt`: `d = sigma - integral_0^inf
/// exp(-k_n delta^2 / (2 kT)) d delta = sigma - sqrt(pi kT / (2 k_n))`, the hard-sphere
/// diameter whose structure the soft contacts mimic (units of length).
pub fn barker_henderson_diameter(sigma: f64, kt: f64, k_n: f64) -> f64 {
    sigma - (std::f64::consts::PI * kt / (2.0 * k_n)).sqrt()
}

/// Width of the structural Brownian stress's shell in the gap (thesis eq 3.54: `Delta =
/// 0.05 a`, here in units of the pair's mean radius).
const BROWNIAN_SHELL: f64 = 0.05;

/// The mean of `g` over the structural Brownian stress's shell, overlaps included, over
/// the shell's width: `sum over shells with xi < 0.05 of g width / 0.05`, which eq 3.54
/// turns into `P_brownian / (4 phi n kT)` (for a flat `g` and no overlaps, `g` itself).
/// `g(k)` is the pair correlation of shell `k` of [`GAP_EDGES`].
pub fn shell_expectation(g: &dyn Fn(usize) -> f64) -> f64 {
    (0..GAP_EDGES.len() - 1)
        .filter(|&k| GAP_EDGES[k + 1] <= BROWNIAN_SHELL + 1e-12)
        .map(|k| g(k) * (GAP_EDGES[k + 1] - GAP_EDGES[k]))
        .sum::<f64>()
        / BROWNIAN_SHELL
}

/// Pair counts per gap shell, per block of snapshots.
#[derive(Clone, Debug, Default)]
struct GapCounts {
    /// `counts[block][shell]`.
    counts: Vec<Vec<u64>>,
    /// Snapshots per block.
    snapshots: Vec<u64>,
}

/// A gap shell's pair correlation.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Shell {
    pub xi_lo: f64,
    pub xi_hi: f64,
    /// Pairs counted over the run.
    pub count: u64,
    /// `g`, the count over the ideal-gas count of the same shell (all species pairs).
    pub g: f64,
    /// `-ln g` (units kT) with its standard error from the blocks.
    pub minus_ln_g: Estimate,
}

/// Everything the check measured.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EquilibriumCheck {
    pub dt: f64,
    pub dt_limit: String,
    pub steps: u64,
    pub shells: Vec<Shell>,
    /// At each gap where the lubrication changes form (`xi_max`, and the taper's end
    /// `xi_max + xi_taper` when there is a taper): `-ln g` just outside minus just inside,
    /// each side extrapolated to that gap by a straight line through its three shells
    /// (units kT). Zero where the noise and the dissipation switch off without a drift.
    pub jumps: Vec<(f64, Estimate)>,
    pub temperatures: Vec<SpeciesTemperature>,
    /// `P_contact`, `P_brownian`, `P_lubrication` over `n kT`.
    pub contact_pressure: Estimate,
    pub brownian_pressure: Estimate,
    pub lubrication_pressure: Estimate,
    /// The contact value `g(sigma)` from the histogram: a straight line through `ln g` of
    /// the shells between `xi_min` and 0.03, at contact (`xi = 0`).
    pub contact_value: Estimate,
    /// The structural Brownian pressure over `n kT` that the histogram implies, `4 phi`
    /// times [`shell_expectation`] (eq 3.54 counts every pair within 0.05 of contact,
    /// overlaps included): the stress code's `brownian_pressure` must equal it.
    pub shell_expectation: Estimate,
    /// Carnahan-Starling's contact value for hard spheres of the contacts' Barker-Henderson
    /// diameter ([`barker_henderson_diameter`]) at the scene's volume fraction, and the
    /// contact virial it implies, `4 phi g` over `n kT` (the reference of
    /// `contact_pressure`; monodisperse scenes only: the reference has one size).
    pub carnahan_starling: Option<(f64, f64)>,
}

/// Least-squares line through `(x, y)`, evaluated at `x0`.
fn line_at(points: &[(f64, f64)], x0: f64) -> f64 {
    let m = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / m, b + y / m));
    let slope = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum::<f64>()
        / points.iter().map(|(x, _)| (x - mx).powi(2)).sum::<f64>();
    my + slope * (x0 - mx)
}

/// Ideal-gas pair count of each gap shell per snapshot: over species pairs `(s, t)`, the
/// pairs per volume times the volume between `r = abar (2 + xi_lo)` and `abar (2 + xi_hi)`,
/// `abar = (a_s + a_t) / 2`.
fn ideal_counts(scene: &Scene, volume: f64) -> Vec<f64> {
    let radii = &scene.file.particles.radii;
    let counts = &scene.counts;
    GAP_EDGES
        .windows(2)
        .map(|e| {
            let mut ideal = 0.0;
            for s in 0..radii.len() {
                for t in s..radii.len() {
                    let abar = 0.5 * (radii[s] + radii[t]);
                    let shell =
                        sphere_volume(abar * (2.0 + e[1])) - sphere_volume(abar * (2.0 + e[0]));
                    let (ns, nt) = (counts[s] as f64, counts[t] as f64);
                    let pairs = if s == t {
                        0.5 * ns * (ns - 1.0)
                    } else {
                        ns * nt
                    };
                    ideal += pairs * shell / volume;
                }
            }
            ideal
        })
        .collect()
}

impl GapCounts {
    fn new(blocks: usize) -> Self {
        Self {
            counts: vec![vec![0; GAP_EDGES.len() - 1]; blocks],
            snapshots: vec![0; blocks],
        }
    }

    /// Adds every pair of `sim` with a gap inside the histogram to block `block`.
    fn add(&mut self, sim: &Simulation, block: usize) {
        let p = &sim.particles;
        let (lo, hi) = (GAP_EDGES[0], GAP_EDGES[GAP_EDGES.len() - 1]);
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let sum = p.radius[i] + p.radius[j];
                let r = sim.pbox.separation(&p.pos[i], &p.pos[j]).norm();
                let xi = 2.0 * (r - sum) / sum;
                if (lo..hi).contains(&xi) {
                    let k = GAP_EDGES.partition_point(|&e| e <= xi) - 1;
                    self.counts[block][k] += 1;
                }
            }
        }
        self.snapshots[block] += 1;
    }
}

/// Runs `scene` (a Brownian scene without flow) and measures its equilibrium, the pair
/// histogram in `blocks` blocks of its averaging snapshots. The pair histogram is taken at every averaging snapshot over
/// all pairs (O(N^2) per snapshot: meant for boxes of a few thousand spheres at most).
pub fn check(scene: &Scene, blocks: usize) -> Result<EquilibriumCheck, SimError> {
    let thermal = scene.thermal.ok_or_else(|| {
        SimError::field(
            "fluid.kT",
            "an equilibrium check needs a Brownian scene (kT > 0)",
        )
    })?;
    if scene.gdot_max() > 0.0 {
        return Err(SimError::field(
            "fluid",
            "an equilibrium check needs a scene at rest (no shear rate or profile)",
        ));
    }
    let kt = thermal.kt;
    let target = scene.file.run.snapshots;
    let mut gaps = GapCounts::new(blocks);
    let radii = scene.file.particles.radii.clone();
    let mut seen = 0;
    let outcome = run(scene, &RunOptions::default(), &mut |p, s| {
        if p.phase != Phase::Averaging || p.snapshots <= seen {
            return;
        }
        seen = p.snapshots;
        let block = ((p.snapshots - 1) * blocks / target).min(blocks - 1);
        gaps.add(s, block);
    })?;
    let summary = outcome.summary;
    let volume: f64 = scene.box_len.iter().product();
    let ideal = ideal_counts(scene, volume);
    let g_block =
        |b: usize, k: usize| gaps.counts[b][k] as f64 / (gaps.snapshots[b] as f64 * ideal[k]);
    let centre = |k: usize| 0.5 * (GAP_EDGES[k] + GAP_EDGES[k + 1]);
    let shells = (0..ideal.len())
        .map(|k| {
            let count: u64 = gaps.counts.iter().map(|c| c[k]).sum();
            let total: u64 = gaps.snapshots.iter().sum();
            let per_block: Vec<f64> = (0..blocks).map(|b| -g_block(b, k).ln()).collect();
            Shell {
                xi_lo: GAP_EDGES[k],
                xi_hi: GAP_EDGES[k + 1],
                count,
                g: count as f64 / (total as f64 * ideal[k]),
                minus_ln_g: Estimate::of_blocks(&per_block),
            }
        })
        .collect();
    let f = &scene.file.forces;
    let mut boundaries = vec![f.xi_max];
    if f.taper_width() > 0.0 {
        boundaries.push(f.xi_max + f.taper_width());
    }
    let jumps = boundaries
        .into_iter()
        .map(|xi_b| {
            let within = |lo: f64, hi: f64| -> Vec<usize> {
                (0..ideal.len())
                    .filter(|&k| GAP_EDGES[k] >= lo - 1e-12 && GAP_EDGES[k + 1] <= hi + 1e-12)
                    .collect()
            };
            let (inside, outside) = (within(xi_b - 0.03, xi_b), within(xi_b, xi_b + 0.03));
            let per_block: Vec<f64> = (0..blocks)
                .map(|b| {
                    let side = |ks: &[usize]| {
                        let pts: Vec<(f64, f64)> = ks
                            .iter()
                            .map(|&k| (centre(k), -g_block(b, k).ln()))
                            .collect();
                        line_at(&pts, xi_b)
                    };
                    side(&outside) - side(&inside)
                })
                .collect();
            let jump = if inside.len() >= 2 && outside.len() >= 2 {
                Estimate::of_blocks(&per_block)
            } else {
                Estimate {
                    mean: f64::NAN,
                    se: f64::NAN,
                }
            };
            (xi_b, jump)
        })
        .collect();
    let n_kt = scene.counts.iter().sum::<usize>() as f64 / volume * kt;
    let pressure = |key: &str| {
        let e = summary.stress_parts.get(key).copied().unwrap_or(Estimate {
            mean: f64::NAN,
            se: f64::NAN,
        });
        Estimate {
            mean: e.mean / n_kt,
            se: e.se / n_kt,
        }
    };
    let phi = scene.phi_actual;
    let carnahan_starling = (radii.len() == 1).then(|| {
        let sigma = 2.0 * radii[0];
        let d = barker_henderson_diameter(sigma, kt, scene.file.forces.k_n);
        let g = carnahan_starling_contact(phi * (d / sigma).powi(3));
        (g, 4.0 * phi * g)
    });
    /// A statistic of each block's shell correlations `g(k)`, as an estimate over blocks.
    type ShellStatistic<'a> = &'a dyn Fn(&dyn Fn(usize) -> f64) -> f64;
    let per_block = |f: ShellStatistic| -> Estimate {
        Estimate::of_blocks(
            &(0..blocks)
                .map(|b| f(&|k| g_block(b, k)))
                .collect::<Vec<_>>(),
        )
    };
    let contact_value = per_block(&|g| {
        let pts: Vec<(f64, f64)> = (0..ideal.len())
            .filter(|&k| GAP_EDGES[k] >= 0.001 - 1e-12 && GAP_EDGES[k + 1] <= 0.03 + 1e-12)
            .map(|k| (centre(k), g(k).ln()))
            .collect();
        line_at(&pts, 0.0).exp()
    });
    let shell_expectation = per_block(&|g| 4.0 * phi * shell_expectation(&|k| g(k)));
    Ok(EquilibriumCheck {
        dt: summary.dt,
        dt_limit: summary.dt_limit.clone(),
        steps: summary.steps,
        shells,
        jumps,
        temperatures: summary.temperatures.clone(),
        contact_pressure: pressure("P_contact"),
        brownian_pressure: pressure("P_brownian"),
        lubrication_pressure: pressure("P_lubrication"),
        contact_value,
        shell_expectation,
        carnahan_starling,
    })
}
