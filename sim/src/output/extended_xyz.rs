//! Extended-XYZ frames (the format of ASE's `extxyz` reader, also read by OVITO): per
//! particle the element symbol standing for its species ([`element_symbol`]), position
//! (units a), identity (from 0), species index, radius (units a), mass (`masses`, units
//! rho a^3), momentum (`momenta` = mass x velocity: the names ASE reads, so that its
//! `get_velocities()` and `get_masses()` are the simulator's velocities in a / time and
//! masses), velocity (`velo`, a / time, the name OVITO maps to its Velocity) and spin
//! (`omega`, 1 / time); the `Lattice` holds the cell's edges ([`SnapshotCell`], sheared for a
//! Lees-Edwards box), `Time` the simulated time and `Step` the step.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::element_symbol::element_symbol;
use crate::output::snapshot_cell::SnapshotCell;
use crate::output::snapshot_columns::push_vectors;
use std::fmt::Write as _;

/// The per-particle columns, in ASE's `name:type:count` notation.
pub const PROPERTIES: &str =
    "species:S:1:pos:R:3:id:I:1:species_index:I:1:radius:R:1:masses:R:1:momenta:R:3:velo:R:3:omega:R:3";

/// One frame of `sim`'s particles as extended XYZ.
pub fn frame(sim: &Simulation) -> Result<String, SimError> {
    let p = &sim.particles;
    let c = SnapshotCell::of(&sim.pbox);
    let [lx, ly, lz] = c.len;
    let mut s = String::with_capacity(p.len() * 160 + 256);
    let _ = writeln!(s, "{}", p.len());
    let _ = writeln!(
        s,
        "Lattice=\"{lx} 0 0 {} {ly} 0 0 0 {lz}\" Properties={PROPERTIES} Time={} Step={} pbc=\"T T T\"",
        c.tilt_xy, sim.time, sim.step
    );
    for i in 0..p.len() {
        s.push_str(element_symbol(p.species[i])?);
        push_vectors(&mut s, &[p.pos[i]]);
        let m = p.mass[i];
        let _ = write!(s, " {} {} {} {m}", p.id[i], p.species[i], p.radius[i]);
        push_vectors(&mut s, &[p.vel[i] * m, p.vel[i], p.omega[i]]);
        s.push('\n');
    }
    Ok(s)
}
