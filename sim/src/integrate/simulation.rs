//! The particle system in time: neighbour upkeep, force evaluation and the implicit or
//! velocity-Verlet step (docs/physics.md section 5), with blow-up detection.
use crate::error::SimError;
use crate::forces::force_accumulation::{ContactStats, ForceAccumulator, PairContext};
use crate::forces::force_field::ForceField;
use crate::forces::lubrication::gap;
use crate::forces::network_loads::{
    add_dissipative_loads, add_selected_pair_loads, brownian_loads, Draw,
};
use crate::forces::resistance_network::{Motion, ResistanceNetwork, ResistancePair};
use crate::forces::thermal_noise::ThermalNoise;
use crate::input::flow_profile::FlowProfile;
use crate::input::integrator::Integrator;
use crate::input::scene::Scene;
use crate::integrate::implicit_dissipation::{ImplicitDissipation, SolveSettings, SolveStats};
use crate::integrate::pass_times::PassTimes;
use crate::integrate::stage_timers::{Stage, StageTimers};
use crate::integrate::timestep::TimeStep;
use crate::neighbours::cell_list::CellList;
use crate::neighbours::size_classes::{self, CandidateCells};
use crate::neighbours::verlet_list::VerletList;
use crate::state::particle_ranges::each_range;
use crate::state::particles::{sphere_inertia, Particles};
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

/// What a Brownian scene's steps keep besides the particles: the keyed noise and the
/// per-particle arrays of the midpoint step (docs/physics.md section 11), reused every
/// step.
struct Thermal {
    noise: ThermalNoise,
    /// The step the noise is drawn for.
    noise_dt: f64,
    /// The step's Brownian loads (force, torque), drawn once and applied in both solves.
    kicks: Vec<Motion>,
    /// Velocities and spins at the start of the step.
    start: Vec<Motion>,
    /// The predictor's mean velocity over the step, which carried the positions to the
    /// midpoint.
    predicted: Vec<Vec3>,
    /// The predictor's mean velocity and spin, the corrector's warm start.
    guess: Vec<Motion>,
    /// Work space of the explicit step's dissipative loads.
    motion: Vec<Motion>,
    scratch: Vec<Motion>,
}

impl Thermal {
    /// Draws the Brownian loads of `step` from the resistance network at the current
    /// positions (one-body parts where the field has drag).
    fn draw(&mut self, network: &ResistanceNetwork, p: &Particles, field: &ForceField, step: u64) {
        self.kicks.resize(p.len(), Motion::default());
        let drag_eta = field.drag.then_some(field.eta);
        let draw = Draw {
            noise: &self.noise,
            particles: p,
            step,
        };
        brownian_loads(draw, network, drag_eta, &mut self.kicks);
    }

    /// Makes the step's Brownian loads those of the pairs inside the cut-off at the
    /// midpoint, where the corrector dissipates: the loads drawn at the start, less
    /// those of the start's pairs (`networks.0`) that have left the cut-off, plus those of
    /// the midpoint's pairs (`networks.1`) that were beyond it at the start, drawn from
    /// their resistance at the midpoint. A pair's noise and its dissipation then switch on
    /// and off together, at the midpoint of the step that crosses the cut-off.
    fn match_midpoint_pairs(
        &mut self,
        (start, midpoint): (&ResistanceNetwork, &ResistanceNetwork),
        p: &Particles,
        field: &ForceField,
        pbox: &PeriodicBox,
        step: u64,
    ) {
        let half = 0.5 * self.noise_dt;
        let predicted = &self.predicted;
        // Whether the pair's gap, with particle j at `shift` from its midpoint place
        // relative to i, is beyond the cut-off.
        let beyond = |pair: &ResistancePair, shift: &dyn Fn(i32) -> Vec3| {
            let (i, j) = (pair.i as usize, pair.j as usize);
            let (r, image) = pbox.image(&p.pos[i], &p.pos[j]);
            let c = field.constants(p.species[i], p.species[j]);
            let lub = c.lubrication.as_ref().expect("network pairs lubricate");
            gap((r + shift(image)).norm(), p.radius[i], p.radius[j]) >= lub.xi_end()
        };
        let left = |pair: &ResistancePair| beyond(pair, &|_| Vec3::zeros());
        let entered = |pair: &ResistancePair| {
            let (i, j) = (pair.i as usize, pair.j as usize);
            beyond(pair, &|image| {
                (predicted[j] - predicted[i] + pbox.image_velocity(image)) * -half
            })
        };
        let draw = Draw {
            noise: &self.noise,
            particles: p,
            step,
        };
        add_selected_pair_loads(draw, start, -1.0, &left, &mut self.kicks);
        add_selected_pair_loads(draw, midpoint, 1.0, &entered, &mut self.kicks);
    }

    /// Adds the drawn Brownian loads to the particles' loads.
    fn add_kicks(&self, p: &mut Particles) {
        for ((f, t), k) in p.force.iter_mut().zip(p.torque.iter_mut()).zip(&self.kicks) {
            *f += k[0];
            *t += k[1];
        }
    }

    /// Keeps the velocities and spins at the start of the step.
    fn keep_start(&mut self, p: &Particles) {
        self.start.clear();
        self.start
            .extend(p.vel.iter().zip(&p.omega).map(|(v, w)| [*v, *w]));
    }

    /// Keeps the predictor's mean velocities and spins (in `p.vel`, `p.omega`) as the
    /// corrector's warm start.
    fn keep_guess(&mut self, p: &Particles) {
        self.guess.clear();
        self.guess
            .extend(p.vel.iter().zip(&p.omega).map(|(v, w)| [*v, *w]));
    }

    /// Sets the velocities and spins back to those at the start of the step.
    fn restore_start(&self, p: &mut Particles) {
        for ((v, w), s) in p.vel.iter_mut().zip(p.omega.iter_mut()).zip(&self.start) {
            (*v, *w) = (s[0], s[1]);
        }
    }

    /// Moves the particles by `half` (dt / 2) times the predictor's mean velocity (in
    /// `p.vel`, which it keeps) into the box at the midpoint time. A particle that leaves
    /// through a y face of a sheared box becomes its sliding image, and every velocity
    /// of the step kept for it is remapped with it.
    fn move_to_midpoint(&mut self, p: &mut Particles, pbox: &PeriodicBox, half: f64) {
        self.predicted.clear();
        self.predicted.extend_from_slice(&p.vel);
        for ((x, w), s) in p
            .pos
            .iter_mut()
            .zip(&mut self.predicted)
            .zip(&mut self.start)
        {
            *x += *w * half;
            let before = s[0];
            pbox.wrap(x, &mut s[0]);
            *w += s[0] - before;
        }
        p.vel.copy_from_slice(&self.predicted);
    }

    /// The end of the step from the corrector's mean velocity `W` (in `p.vel`, spins in
    /// `p.omega`): positions `x + dt W` (from the midpoint, `+ dt W - dt/2 W_predicted`),
    /// wrapped into the box at the end time, velocities `2 W - V` (remapped with the
    /// position), spins likewise.
    fn move_to_end(&self, p: &mut Particles, pbox: &PeriodicBox, dt: f64) {
        let moves = p
            .pos
            .iter_mut()
            .zip(p.vel.iter_mut())
            .zip(p.omega.iter_mut());
        for (((x, v), w), (s, wp)) in moves.zip(self.start.iter().zip(&self.predicted)) {
            *x += *v * dt - *wp * (0.5 * dt);
            *v = *v * 2.0 - s[0];
            *w = *w * 2.0 - s[1];
            pbox.wrap(x, v);
        }
    }
}

/// Particles, their neighbour list and forces, advanced by the implicit step or by
/// velocity Verlet.
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
    /// Iterations and residual of the last implicit solve.
    last_solve: SolveStats,
    /// Implicit solves and their iterations since the start (or the restart).
    solver_totals: (u64, u64),
    accumulator: ForceAccumulator,
    /// Lubrication resistances at the current positions (implicit step and Brownian
    /// scenes only).
    network: ResistanceNetwork,
    /// The Brownian forces' source and work arrays (scenes with `kT > 0` only).
    thermal: Option<Thermal>,
    /// The Brownian step's network at the start of the step, kept while the midpoint's
    /// is built.
    midpoint_network: ResistanceNetwork,
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
        let field = scene.force_field.clone();
        let timestep = scene.timestep;
        if !(timestep.dt.is_finite() && timestep.dt > 0.0) {
            return Err(SimError::field(
                "run.dt",
                "no force term limits the time step: set run.dt",
            ));
        }
        let u_max = scene.profile.max_abs_u().max(1e-12);
        // Streaming energy plus, in a Brownian scene, the thermal 3 kT of each particle
        // (translation and rotation).
        let kt = scene.thermal.map_or(0.0, |t| t.kt);
        let kinetic_scale = particles
            .mass
            .iter()
            .map(|m| 0.5 * m * u_max * u_max + 3.0 * kt)
            .sum();
        let thermal = scene.thermal.map(|t| Thermal {
            noise: ThermalNoise::new(t.kt, timestep.dt, scene.file.seed),
            noise_dt: timestep.dt,
            kicks: Vec::new(),
            start: Vec::new(),
            predicted: Vec::new(),
            guess: Vec::new(),
            motion: Vec::new(),
            scratch: Vec::new(),
        });
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
            thermal,
            midpoint_network: ResistanceNetwork::default(),
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
    fn build_list(&mut self, reference: Vec<Vec3>, old_index: &[u32]) {
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
    /// step solves with it, and a Brownian scene's noise is drawn from it.
    fn uses_network(&self) -> bool {
        self.timestep.integrator == Integrator::Implicit || self.thermal.is_some()
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
    fn evaluate_loads(&mut self, spring_dt: f64, noise_step: u64) {
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
        if let (Integrator::Explicit, Some(th)) = (self.timestep.integrator, &mut self.thermal) {
            let (network, p) = (&self.network, &mut self.particles);
            add_dissipative_loads(
                network,
                &self.field,
                &self.profile,
                p,
                (&mut th.motion, &mut th.scratch),
            );
            th.draw(network, p, &self.field, noise_step);
            th.add_kicks(p);
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
    /// both integrators' steps. The explicit step's Brownian loads are those of the
    /// evaluation after step `self.step` (the first evaluation, at the start, is 0).
    fn drift_and_reload(&mut self) {
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
        match (self.timestep.integrator, self.thermal.is_some()) {
            (Integrator::Implicit, false) => self.implicit_step(),
            (Integrator::Implicit, true) => self.brownian_step(at_midpoint),
            (Integrator::Explicit, _) => self.verlet_step(),
        }
    }

    /// One implicit step (docs/physics.md section 5): drift with the last velocities,
    /// conservative loads and lubrication resistances at the new positions, then the
    /// backward-Euler solve for the new velocities under those loads, drag and
    /// lubrication. The loads a snapshot evaluates afterwards (lubrication at the new
    /// velocities) are the ones the step applied.
    fn implicit_step(&mut self) -> Result<(), SimError> {
        self.drift_and_reload();
        let solved = self.solve_dissipation(self.timestep.dt, None);
        self.step += 1;
        self.time += self.timestep.dt;
        solved?;
        self.check()
    }

    /// The implicit step of a Brownian scene (docs/physics.md section 11): the
    /// dissipative loads by the trapezoidal rule and the positions at the midpoint of the
    /// step's mean velocity `W = (V + V') / 2`, which solves
    /// `(M + dt/2 (D + R)) W = M V + dt/2 (F_c + D V_inf + F_B)`. A predictor solves it
    /// with the loads and resistance at the start `x`, the corrector at
    /// `x + dt/2 W_predicted` with the same Brownian loads `F_B` (drawn once from `R(x)`);
    /// then `x' = x + dt W`, `V' = 2 W - V`. For a frozen resistance this keeps the
    /// velocities at `kT / m` and the long-time diffusion at `kT / R` at any `dt`, and the
    /// midpoint gives the stochastic drift `kT div R^-1` where the step overdamps the
    /// lubricated pairs.
    fn brownian_step(&mut self, at_midpoint: &mut dyn FnMut(&Simulation)) -> Result<(), SimError> {
        let (dt, half) = (self.timestep.dt, 0.5 * self.timestep.dt);
        if self.list.stale(&self.particles.pos, &self.pbox) {
            self.rebuild_list();
        }
        // Springs are advanced once, by the corrector's evaluation.
        self.evaluate_loads(0.0, self.step);
        let t = self.timers.start();
        let th = self
            .thermal
            .as_mut()
            .expect("a Brownian step has its noise");
        th.draw(&self.network, &self.particles, &self.field, self.step);
        th.keep_start(&self.particles);
        th.add_kicks(&mut self.particles);
        self.timers.stop(Stage::Integration, t);
        self.solve_dissipation(half, None)?;
        let t = self.timers.start();
        self.pbox.set_time(self.time + half);
        let th = self
            .thermal
            .as_mut()
            .expect("a Brownian step has its noise");
        th.move_to_midpoint(&mut self.particles, &self.pbox, half);
        self.timers.stop(Stage::Integration, t);
        if self.list.stale(&self.particles.pos, &self.pbox) {
            // No re-sorting: the step's arrays keep their order.
            let identity: Vec<u32> = (0..self.particles.len() as u32).collect();
            self.build_list(self.particles.pos.clone(), &identity);
        }
        // The loads and resistances at the midpoint, the start's network kept aside.
        std::mem::swap(&mut self.network, &mut self.midpoint_network);
        self.evaluate_loads(dt, self.step);
        let th = self
            .thermal
            .as_mut()
            .expect("a Brownian step has its noise");
        th.match_midpoint_pairs(
            (&self.midpoint_network, &self.network),
            &self.particles,
            &self.field,
            &self.pbox,
            self.step,
        );
        th.add_kicks(&mut self.particles);
        th.keep_guess(&self.particles);
        th.restore_start(&mut self.particles);
        let guess = std::mem::take(&mut th.guess);
        let solved = self.solve_dissipation(half, Some(&guess));
        if let Some(th) = self.thermal.as_mut() {
            th.guess = guess;
        }
        solved?;
        let t = self.timers.start();
        at_midpoint(self);
        self.timers.stop(Stage::Sampling, t);
        let t = self.timers.start();
        self.pbox.set_time(self.time + dt);
        let th = self
            .thermal
            .as_ref()
            .expect("a Brownian step has its noise");
        th.move_to_end(&mut self.particles, &self.pbox, dt);
        self.step += 1;
        self.time += dt;
        self.timers.stop(Stage::Integration, t);
        self.check()
    }

    /// Replaces the velocities and spins by the solution of the implicit system with
    /// step `dt` (docs/physics.md section 5), under the loads in `p.force`, `p.torque`.
    /// `guess`: the solve's warm start, when better than the current velocities.
    fn solve_dissipation(&mut self, dt: f64, guess: Option<&[Motion]>) -> Result<(), SimError> {
        let t = self.timers.start();
        let drag = self.field.drag.then_some((self.field.eta, &self.profile));
        let solved = self.dissipation.solve(
            &mut self.particles,
            &self.network,
            drag,
            (dt, self.solver),
            guess,
        );
        self.timers.stop(Stage::Integration, t);
        match solved {
            Ok(stats) => {
                self.last_solve = stats;
                self.solver_totals.0 += 1;
                self.solver_totals.1 += stats.iterations as u64;
                Ok(())
            }
            Err(failure) => Err(self.blow_up(
                failure.particle,
                format!(
                    "the implicit solve stopped at relative residual {:.3e} after {} iterations (largest residual on this particle)",
                    failure.stats.residual, failure.stats.iterations
                ),
                "the system is ill-conditioned or not finite: lower run.dt_safety or run.dt, or raise run.solver_tolerance",
            )),
        }
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
        if self.field.contact.is_some() && self.contacts.max_overlap_ratio > MAX_OVERLAP_RATIO {
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
