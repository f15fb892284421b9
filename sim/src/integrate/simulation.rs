//! The particle system in time: its state and work arrays, neighbour upkeep, force
//! evaluation and the blow-up checks; each step is taken by the scene's stepper
//! (velocity Verlet, backward Euler or the Brownian midpoint step, docs/physics.md
//! sections 5 and 11).
use crate::error::SimError;
use crate::forces::force_accumulation::{ContactStats, ForceAccumulator, PairContext};
use crate::forces::force_field::ForceField;
use crate::forces::resistance_network::ResistanceNetwork;
use crate::input::flow_profile::FlowProfile;
use crate::input::scene::Scene;
use crate::integrate::implicit_dissipation::{ImplicitDissipation, SolveSettings, SolveStats};
use crate::integrate::midpoint_arrays::MidpointArrays;
use crate::integrate::pass_times::PassTimes;
use crate::integrate::stage_timers::{Stage, StageTimers};
use crate::integrate::stepper::Stepper;
use crate::integrate::thermal_kicks::Thermal;
use crate::integrate::timestep::TimeStep;
use crate::neighbours::cell_list::CellList;
use crate::neighbours::size_classes::{self, CandidateCells};
use crate::neighbours::verlet_list::VerletList;
use crate::state::particle_ranges::each_range;
use crate::state::particles::Particles;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;
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
    pub(crate) list_builds: u64,
}

/// Particles, their neighbour list and forces, and the work arrays of the steps, advanced
/// by the scene's stepper (velocity Verlet, backward Euler or the Brownian midpoint step).
pub struct Simulation {
    pub particles: Particles,
    pub pbox: PeriodicBox,
    pub(crate) field: ForceField,
    pub(crate) profile: FlowProfile,
    pub timestep: TimeStep,
    pub(crate) list: VerletList,
    /// Tangential contact springs, one per listed pair (frictional scenes only).
    pub(crate) springs: Vec<Vec3>,
    pub step: u64,
    pub time: f64,
    /// Overlaps at the last force evaluation.
    pub contacts: ContactStats,
    pub timers: StageTimers,
    pub(crate) list_builds: u64,
    /// Constant external force on each particle (empty = none): a probe for tests and
    /// driven scenes; never evaluated when empty.
    pub body_force: Vec<Vec3>,
    /// The scene's integrator.
    stepper: Stepper,
    /// Iterations and residual of the last implicit solve.
    pub(super) last_solve: SolveStats,
    /// Implicit solves and their iterations since the start (or the restart).
    pub(super) solver_totals: (u64, u64),
    pub(super) accumulator: ForceAccumulator,
    /// Lubrication resistances at the current positions (implicit step and Brownian
    /// scenes only).
    pub(super) network: ResistanceNetwork,
    /// The Brownian loads' thermal energy, noise and work arrays: `Some` exactly in a
    /// scene with `kT > 0`, the one answer to "is this scene Brownian?".
    pub(super) thermal: Option<Thermal>,
    /// The Brownian midpoint step's arrays (empty for the other steppers).
    pub(super) midpoint: MidpointArrays,
    pub(super) dissipation: ImplicitDissipation,
    pub(super) solver: SolveSettings,
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
        let field = scene.force_field.clone();
        let timestep = scene.timestep;
        if !(timestep.dt.is_finite() && timestep.dt > 0.0) {
            return Err(SimError::field(
                "run.dt",
                "no force term limits the time step: set run.dt",
            ));
        }
        let thermal = scene
            .thermal
            .map(|t| Thermal::new(t.kt, timestep.dt, scene.file.seed));
        let u_max = scene.profile.max_abs_u().max(1e-12);
        // Streaming energy plus, in a Brownian scene, the thermal 3 kT of each particle
        // (translation and rotation).
        let kt = thermal.as_ref().map_or(0.0, Thermal::kt);
        let kinetic_scale = particles
            .mass
            .iter()
            .map(|m| 0.5 * m * u_max * u_max + 3.0 * kt)
            .sum();
        let stepper = Stepper::of(timestep.integrator, thermal.is_some());
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
            stepper,
            last_solve: SolveStats::default(),
            solver_totals: (0, 0),
            accumulator: ForceAccumulator::default(),
            network: ResistanceNetwork::default(),
            thermal,
            midpoint: MidpointArrays::default(),
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
        let network = sim.uses_network();
        sim.accumulator.split(&sim.list, network);
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
    pub(super) fn build_list(&mut self, reference: Vec<Vec3>, old_index: &[u32]) {
        let t = self.timers.start();
        let field = &self.field;
        let species = &self.particles.species;
        let (large, reaches) =
            size_classes::classify(field.n_species(), self.skin, |s, t| field.cutoff(s, t));
        let is_large: Vec<bool> = species.iter().map(|&s| large[s as usize]).collect();
        let cells = CandidateCells::build(&reference, &self.pbox, is_large, reaches);
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

    /// Whether the loads are evaluated with the resistance network kept: the implicit
    /// steps solve with it, and a Brownian scene's noise is drawn from it.
    fn uses_network(&self) -> bool {
        self.stepper != Stepper::Verlet || self.thermal.is_some()
    }

    /// The thermal energy kT of a Brownian scene, `None` without thermal noise.
    pub fn kt(&self) -> Option<f64> {
        self.thermal.as_ref().map(Thermal::kt)
    }

    /// Evaluates the loads at the current state: every force and torque for the explicit
    /// scheme (with the Brownian loads of evaluation `self.step` in a Brownian scene);
    /// for the implicit one the conservative loads, with the lubrication resistances
    /// kept for the solve.
    pub fn compute_forces(&mut self) {
        self.evaluate_loads(self.timestep.dt, self.step);
    }

    /// [`Simulation::compute_forces`] with the contact springs advanced by `spring_dt`
    /// and the explicit step's Brownian loads drawn for `noise_step`.
    pub(super) fn evaluate_loads(&mut self, spring_dt: f64, noise_step: u64) {
        let t = self.timers.start();
        let with_network = self.uses_network();
        let pairs = PairContext {
            field: &self.field,
            list: &self.list,
            pbox: &self.pbox,
            profile: &self.profile,
            spring_dt,
        };
        let (p, springs) = (&mut self.particles, &mut self.springs[..]);
        self.contacts = if with_network {
            self.accumulator
                .known_loads(&pairs, p, springs, &mut self.network)
        } else {
            self.accumulator.all_loads(&pairs, p, springs)
        };
        if with_network {
            self.network.index_crossings();
        }
        for (f, b) in self.particles.force.iter_mut().zip(&self.body_force) {
            *f += b;
        }
        if let (Stepper::Verlet, Some(th)) = (self.stepper, &mut self.thermal) {
            th.add_explicit_fluid_loads(
                &self.network,
                (&self.field, &self.profile),
                &mut self.particles,
                noise_step,
            );
        }
        self.timers.stop(Stage::Forces, t);
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
    /// both integrators' steps. The explicit step's Brownian loads are those of the
    /// evaluation after step `self.step` (the first evaluation, at the start, is 0).
    pub(super) fn drift_and_reload(&mut self) {
        let t = self.timers.start();
        self.drift();
        self.timers.stop(Stage::Integration, t);
        if self.list.stale(&self.particles.pos, &self.pbox) {
            self.rebuild_list();
        }
        self.evaluate_loads(self.timestep.dt, self.step + 1);
    }

    /// One step of the scene's integrator, then the blow-up checks.
    pub fn step(&mut self) -> Result<(), SimError> {
        self.step_observed(&mut |_| {})
    }

    /// [`Self::step`], calling `at_midpoint` with the system at the midpoint of an
    /// implicit Brownian step, its velocities the step's mean velocity `W`, where its pair
    /// stress is sampled ([`crate::sampling::snapshot::StepPairSums`]); the other
    /// integrators never call it.
    pub fn step_observed(
        &mut self,
        at_midpoint: &mut dyn FnMut(&Simulation),
    ) -> Result<(), SimError> {
        match self.stepper {
            Stepper::Verlet => self.verlet_step(),
            Stepper::BackwardEuler => self.backward_euler_step(),
            Stepper::BrownianMidpoint => self.midpoint_step(at_midpoint),
        }
    }

    /// Iterations and residual of the last implicit solve.
    pub fn last_solve(&self) -> SolveStats {
        self.last_solve
    }

    /// Implicit solves and their conjugate-gradient iterations since the start (or the
    /// restart).
    pub fn solver_totals(&self) -> (u64, u64) {
        self.solver_totals
    }

    /// Mean conjugate-gradient iterations per implicit solve since the totals were
    /// `before` ([`Simulation::solver_totals`]); `None` when no solve ran (explicit step).
    pub fn iterations_per_solve_since(&self, before: (u64, u64)) -> Option<f64> {
        let solves = self.solver_totals.0 - before.0;
        (solves > 0).then(|| (self.solver_totals.1 - before.1) as f64 / solves as f64)
    }

    /// Switches on the timing of the implicit solve's parallel passes (off by default:
    /// it reads the clock twice per range and pass).
    pub fn time_solve_passes(&mut self) {
        self.dissipation
            .times
            .get_or_insert_with(PassTimes::default);
    }

    /// Time of the implicit solve's parallel passes since [`Self::time_solve_passes`]
    /// (zero with the explicit step), `None` when they are not timed.
    pub fn solve_pass_times(&self) -> Option<PassTimes> {
        self.dissipation.times
    }

    /// Advances `n` steps.
    pub fn advance(&mut self, n: u64) -> Result<(), SimError> {
        self.advance_observed(n, &mut |_| {})
    }

    /// Advances `n` steps, each by [`Self::step_observed`].
    pub fn advance_observed(
        &mut self,
        n: u64,
        at_midpoint: &mut dyn FnMut(&Simulation),
    ) -> Result<(), SimError> {
        for _ in 0..n {
            self.step_observed(at_midpoint)?;
        }
        Ok(())
    }

    pub(super) fn blow_up(&self, particle: usize, what: String, cause: &str) -> SimError {
        SimError::BlowUp {
            step: self.step,
            time: self.time,
            particle,
            what,
            cause: cause.to_string(),
        }
    }

    /// Overlap every step; non-finite state and runaway kinetic energy every few steps.
    pub(super) fn check(&self) -> Result<(), SimError> {
        // Built only on failure: this runs every step.
        let dt_hint = || {
            format!(
                "time step {:.3e} (set by {}) too large for the stiffest term; lower run.dt_safety or run.dt",
                self.timestep.dt, self.timestep.limit
            )
        };
        if self.field.contact.is_some() && self.contacts.max_overlap_ratio > MAX_OVERLAP_RATIO {
            let (i, j) = self.contacts.max_pair;
            return Err(self.blow_up(i, format!(
                "overlap with particle {j} is {:.3} of the smaller radius (limit {MAX_OVERLAP_RATIO})",
                self.contacts.max_overlap_ratio), &format!("contacts too soft for the stress (raise forces.k_n), a flow that jams (particles.phi at or \
                 above the jamming point of this friction and Peclet number, where the driven contacts load without bound: lower it) or {}", dt_hint())));
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
