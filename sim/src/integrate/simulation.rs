//! The particle system in time: neighbour upkeep, force evaluation and the implicit or
//! velocity-Verlet step (docs/physics.md section 5), with blow-up detection.
use crate::error::SimError;
use crate::forces::force_accumulation::{ContactStats, ForceAccumulator};
use crate::forces::force_field::ForceField;
use crate::forces::resistance_network::ResistanceNetwork;
use crate::input::flow_profile::FlowProfile;
use crate::input::scene::Scene;
use crate::integrate::implicit_dissipation::{ImplicitDissipation, SolveSettings, SolveStats};
use crate::integrate::integrator::Integrator;
use crate::integrate::particle_ranges::each_range;
use crate::integrate::particles::{sphere_inertia, Particles};
use crate::integrate::pass_times::PassTimes;
use crate::integrate::periodic_box::PeriodicBox;
use crate::integrate::stage_timers::{Stage, StageTimers};
use crate::integrate::timestep::TimeStep;
use crate::neighbours::cell_list::CellList;
use crate::neighbours::verlet_list::VerletList;
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Overlap ratio (overlap / smaller radius) beyond which a run is declared blown up.
pub const MAX_OVERLAP_RATIO: f64 = 0.1;
/// Kinetic energy, in units of the streaming kinetic energy `sum m u_max^2 / 2`, beyond
/// which a run is declared blown up.
pub const MAX_KINETIC_RATIO: f64 = 1e4;
/// Steps between kinetic-energy checks.
const ENERGY_CHECK_EVERY: u64 = 64;
/// Conjugate-gradient iterations after which the implicit step is declared failed.
const MAX_SOLVER_ITERATIONS: usize = 2000;

/// What a checkpoint keeps of a [`Simulation`]: particles (with their current forces),
/// the positions the neighbour list was built from (and, in a sheared box, the image offset
/// then), the contact springs and the clock (which sets the image offset now).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SystemState {
    pub particles: Particles,
    pub list_reference: Vec<Vec3>,
    #[serde(default)]
    pub list_reference_offset: f64,
    pub springs: Vec<Vec3>,
    pub step: u64,
    pub time: f64,
    pub list_builds: u64,
}

/// Particles, their neighbour list and forces, advanced by the implicit step or by
/// velocity Verlet.
pub struct Simulation {
    pub particles: Particles,
    pub pbox: PeriodicBox,
    pub field: ForceField,
    pub profile: FlowProfile,
    pub timestep: TimeStep,
    pub list: VerletList,
    /// Tangential contact springs, one per listed pair (frictional scenes only).
    pub springs: Vec<Vec3>,
    pub step: u64,
    pub time: f64,
    /// Overlaps at the last force evaluation.
    pub contacts: ContactStats,
    pub timers: StageTimers,
    pub list_builds: u64,
    /// Constant external force on each particle (empty = none): a probe for tests and
    /// driven scenes; never evaluated when empty.
    pub body_force: Vec<Vec3>,
    /// Iterations and residual of the last implicit solve.
    pub last_solve: SolveStats,
    /// Implicit solves and their iterations since the start (or the restart).
    pub solver_totals: (u64, u64),
    accumulator: ForceAccumulator,
    /// Lubrication resistances at the current positions (implicit step only).
    network: ResistanceNetwork,
    dissipation: ImplicitDissipation,
    solver: SolveSettings,
    skin: f64,
    kinetic_scale: f64,
}

impl Simulation {
    /// A system at `particles` in `scene`, with forces evaluated at the start state.
    pub fn new(scene: &Scene, particles: Particles) -> Result<Self, SimError> {
        let mut sim = Self::bare(scene, particles)?;
        sim.rebuild_list();
        sim.compute_forces();
        Ok(sim)
    }

    /// The system without neighbour list or forces.
    fn bare(scene: &Scene, particles: Particles) -> Result<Self, SimError> {
        let field = ForceField::from_scene(scene);
        let timestep = TimeStep::choose(scene, &field);
        if !(timestep.dt.is_finite() && timestep.dt > 0.0) {
            return Err(SimError::field(
                "run.dt",
                "no force term limits the time step: set run.dt",
            ));
        }
        let u_max = scene.profile.max_abs_u().max(1e-12);
        let kinetic_scale = particles.mass.iter().map(|m| 0.5 * m * u_max * u_max).sum();
        let pbox = match scene.shear_rate() {
            Some(gdot) => PeriodicBox::sheared(scene.box_len, gdot),
            None => PeriodicBox::new(scene.box_len),
        };
        Ok(Simulation {
            pbox,
            field,
            profile: scene.profile.clone(),
            timestep,
            list: VerletList::default(),
            springs: Vec::new(),
            step: 0,
            time: 0.0,
            contacts: ContactStats::default(),
            timers: StageTimers::default(),
            list_builds: 0,
            body_force: Vec::new(),
            last_solve: SolveStats::default(),
            solver_totals: (0, 0),
            accumulator: ForceAccumulator::default(),
            network: ResistanceNetwork::default(),
            dissipation: ImplicitDissipation::default(),
            solver: SolveSettings {
                tolerance: scene.file.run.solver_tolerance,
                max_iterations: MAX_SOLVER_ITERATIONS,
            },
            skin: scene.file.run.skin,
            kinetic_scale,
            particles,
        })
    }

    /// The state a checkpoint needs to continue this system bit for bit.
    pub fn state(&self) -> SystemState {
        SystemState {
            particles: self.particles.clone(),
            list_reference: self.list.reference.clone(),
            list_reference_offset: self.list.reference_offset,
            springs: self.springs.clone(),
            step: self.step,
            time: self.time,
            list_builds: self.list_builds,
        }
    }

    /// A system continued from a checkpoint: the neighbour list is rebuilt around the
    /// saved reference positions and the saved forces are kept, so the continuation is
    /// bitwise identical to the uninterrupted run.
    pub fn restore(scene: &Scene, state: SystemState) -> Result<Self, SimError> {
        let mut sim = Self::bare(scene, state.particles)?;
        let identity: Vec<u32> = (0..sim.particles.len() as u32).collect();
        sim.pbox = sim.pbox.with_offset(state.list_reference_offset);
        sim.build_list(state.list_reference, &identity);
        sim.pbox.set_time(state.time);
        sim.springs = state.springs;
        // The ranges of particles the evaluation that made the saved forces used.
        sim.accumulator
            .split(&sim.list, sim.timestep.integrator == Integrator::Implicit);
        sim.step = state.step;
        sim.time = state.time;
        sim.list_builds = state.list_builds;
        Ok(sim)
    }

    /// Re-sorts the particles into cell order and rebuilds the neighbour list from the
    /// current positions, carrying contact springs over.
    pub fn rebuild_list(&mut self) {
        let t = self.timers.start();
        let reach = self.field.max_cutoff + self.skin;
        let order = CellList::build(&self.particles.pos, &self.pbox, reach)
            .order()
            .to_vec();
        self.particles.permute(&order);
        if !self.body_force.is_empty() {
            self.body_force = order.iter().map(|&o| self.body_force[o as usize]).collect();
        }
        self.timers.stop(Stage::Neighbours, t);
        let reference = self.particles.pos.clone();
        self.build_list(reference, &order);
    }

    /// Rebuilds the neighbour list around `reference` positions without reordering (a
    /// checkpoint restores the exact list of the interrupted run this way).
    fn build_list(&mut self, reference: Vec<Vec3>, old_index: &[u32]) {
        let t = self.timers.start();
        let field = &self.field;
        let species = &self.particles.species;
        let cells = CellList::build(&reference, &self.pbox, field.max_cutoff + self.skin);
        let list = VerletList::build(&reference, &self.pbox, &cells, self.skin, |i, j| {
            field.cutoff(species[i], species[j])
        });
        if field.frictional() {
            self.springs = list.carry_over(&self.list, &self.springs, old_index, |s| -s);
        }
        self.list = list;
        self.list_builds += 1;
        self.timers.stop(Stage::Neighbours, t);
    }

    /// Evaluates the loads at the current state: every force and torque for the explicit
    /// scheme; for the implicit one the conservative loads, with the lubrication
    /// resistances kept for the solve.
    pub fn compute_forces(&mut self) {
        let t = self.timers.start();
        let network = match self.timestep.integrator {
            Integrator::Implicit => Some(&mut self.network),
            Integrator::Explicit => None,
        };
        self.contacts = self.accumulator.evaluate(
            &self.field,
            &mut self.particles,
            &self.list,
            &mut self.springs,
            &self.pbox,
            &self.profile,
            self.timestep.dt,
            network,
        );
        for (f, b) in self.particles.force.iter_mut().zip(&self.body_force) {
            *f += b;
        }
        self.timers.stop(Stage::Forces, t);
    }

    /// Half a kick `v += F dt / (2 m)`, `omega += T dt / (2 I)`.
    fn half_kick(&mut self) {
        let h = 0.5 * self.timestep.dt;
        let p = &mut self.particles;
        let (force, torque, mass, radius) = (&p.force, &p.torque, &p.mass, &p.radius);
        each_range(
            self.accumulator.bounds(),
            (&mut p.vel[..], &mut p.omega[..]),
            &|_, first, (vel, omega)| {
                for (m, (v, w)) in vel.iter_mut().zip(omega.iter_mut()).enumerate() {
                    let i = first + m;
                    *v += force[i] * (h / mass[i]);
                    *w += torque[i] * (h / sphere_inertia(mass[i], radius[i]));
                }
            },
        );
    }

    /// Drift `x += v dt`, wrapped into the box as it is at the end of the step (with the
    /// Lees-Edwards remap across the y faces of a sheared box).
    fn drift(&mut self) {
        let dt = self.timestep.dt;
        self.pbox.set_time(self.time + dt);
        let pbox = self.pbox;
        let p = &mut self.particles;
        each_range(
            self.accumulator.bounds(),
            (&mut p.pos[..], &mut p.vel[..]),
            &|_, _, (pos, vel)| {
                for (x, v) in pos.iter_mut().zip(vel.iter_mut()) {
                    *x += *v * dt;
                    pbox.wrap(x, v);
                }
            },
        );
    }

    /// Drift, neighbour-list upkeep and the loads at the new positions: the middle of
    /// both integrators' steps.
    fn drift_and_reload(&mut self) {
        let t = self.timers.start();
        self.drift();
        self.timers.stop(Stage::Integration, t);
        if self.list.stale(&self.particles.pos, &self.pbox) {
            self.rebuild_list();
        }
        self.compute_forces();
    }

    /// One step of the scene's integrator, then the blow-up checks.
    pub fn step(&mut self) -> Result<(), SimError> {
        match self.timestep.integrator {
            Integrator::Implicit => self.implicit_step(),
            Integrator::Explicit => self.verlet_step(),
        }
    }

    /// One implicit step (docs/physics.md section 5): drift with the last velocities,
    /// conservative loads and lubrication resistances at the new positions, then the
    /// backward-Euler solve for the new velocities under those loads, drag and
    /// lubrication. The loads a snapshot evaluates afterwards (lubrication at the new
    /// velocities) are the ones the step applied.
    fn implicit_step(&mut self) -> Result<(), SimError> {
        self.drift_and_reload();
        let t = self.timers.start();
        let drag = self.field.drag.then_some((self.field.eta, &self.profile));
        let solved = self.dissipation.solve(
            &mut self.particles,
            &mut self.network,
            drag,
            self.timestep.dt,
            self.solver,
        );
        self.timers.stop(Stage::Integration, t);
        self.step += 1;
        self.time += self.timestep.dt;
        match solved {
            Ok(stats) => {
                self.last_solve = stats;
                self.solver_totals.0 += 1;
                self.solver_totals.1 += stats.iterations as u64;
            }
            Err(failure) => {
                return Err(self.blow_up(
                    failure.particle,
                    format!(
                        "the implicit solve stopped at relative residual {:.3e} after {} iterations (largest residual on this particle)",
                        failure.stats.residual, failure.stats.iterations
                    ),
                    "the system is ill-conditioned or not finite: lower run.dt_safety or run.dt, or raise run.solver_tolerance",
                ));
            }
        }
        self.check()
    }

    /// One velocity-Verlet step (forces at the new positions with the half-step
    /// velocities, as in the seeds' LAMMPS scheme), then the blow-up checks.
    fn verlet_step(&mut self) -> Result<(), SimError> {
        let t = self.timers.start();
        self.half_kick();
        self.timers.stop(Stage::Integration, t);
        self.drift_and_reload();
        let t = self.timers.start();
        self.half_kick();
        self.step += 1;
        self.time += self.timestep.dt;
        self.timers.stop(Stage::Integration, t);
        self.check()
    }

    /// Time of the implicit solve's parallel passes since the start (zero with the
    /// explicit step).
    pub fn solve_pass_times(&self) -> PassTimes {
        self.dissipation.times
    }

    /// Advances `n` steps.
    pub fn advance(&mut self, n: u64) -> Result<(), SimError> {
        for _ in 0..n {
            self.step()?;
        }
        Ok(())
    }

    fn blow_up(&self, particle: usize, what: String, cause: &str) -> SimError {
        SimError::BlowUp {
            step: self.step,
            time: self.time,
            particle,
            what,
            cause: cause.to_string(),
        }
    }

    /// Overlap every step; non-finite state and runaway kinetic energy every few steps.
    fn check(&self) -> Result<(), SimError> {
        // Built only on failure: this runs every step.
        let dt_hint = || {
            format!(
                "time step {:.3e} (set by {}) too large for the stiffest term; lower run.dt_safety or run.dt",
                self.timestep.dt, self.timestep.limit
            )
        };
        if self.contacts.max_overlap_ratio > MAX_OVERLAP_RATIO {
            let (i, j) = self.contacts.max_pair;
            return Err(self.blow_up(i, format!(
                "overlap with particle {j} is {:.3} of the smaller radius (limit {MAX_OVERLAP_RATIO})",
                self.contacts.max_overlap_ratio), &format!("contacts too soft for the stress (raise forces.k_n) or {}", dt_hint())));
        }
        if !self.step.is_multiple_of(ENERGY_CHECK_EVERY) {
            return Ok(());
        }
        let p = &self.particles;
        if let Some(i) = (0..p.len()).find(|&i| {
            !(p.pos[i].iter().all(|c| c.is_finite())
                && p.vel[i].iter().all(|c| c.is_finite())
                && p.omega[i].iter().all(|c| c.is_finite()))
        }) {
            return Err(self.blow_up(i, "position or velocity is not finite".into(), &dt_hint()));
        }
        let kinetic = p.kinetic_energy();
        if kinetic > MAX_KINETIC_RATIO * self.kinetic_scale {
            let i = (0..p.len())
                .max_by(|&a, &b| p.vel[a].norm_squared().total_cmp(&p.vel[b].norm_squared()))
                .unwrap_or(0);
            return Err(self.blow_up(i, format!(
                "kinetic energy {kinetic:.3e} is {:.1e} times the streaming energy (fastest particle)",
                kinetic / self.kinetic_scale), &dt_hint()));
        }
        Ok(())
    }
}
