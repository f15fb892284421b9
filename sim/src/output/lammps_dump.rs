//! LAMMPS text dump frames (`ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz`,
//! the names of LAMMPS' `dump custom`, so that OVITO names every column and LAMMPS'
//! `read_dump ... add keep` takes the particles back), read by LAMMPS, OVITO, ASE
//! (`lammps-dump-text`) and MDAnalysis. `id` is the particle's identity + 1 (LAMMPS ids start
//! at 1; the extended-XYZ frames' `id` is the same identity from 0), `type` its species + 1
//! (LAMMPS types start at 1; ASE reads a type as the atomic number, matching
//! [`element_symbol`](crate::output::element_symbol)); no `mass` column, from which ASE
//! would guess the elements (the masses are in the extended-XYZ and GSD frames); lengths in
//! units a, velocities in a / time, spins in 1 / time. No `ITEM: TIME` header (LAMMPS'
//! `dump_modify time yes`): MDAnalysis' reader expects `ITEM: TIMESTEP` on a frame's first
//! line and fails on it; the time is the step times the run's `dt` (`summary.json`), which
//! MDAnalysis applies given `dt=`, and the extended-XYZ frames state it. A Lees-Edwards box is
//! written with the triclinic header `BOX BOUNDS xy xz yz pp pp pp` and the tilt of
//! [`SnapshotCell`], an unsheared one with `BOX BOUNDS pp pp pp`.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::snapshot_cell::SnapshotCell;
use crate::output::snapshot_columns::push_vectors;
use std::fmt::Write as _;

/// The per-particle columns of the `ITEM: ATOMS` line.
pub const COLUMNS: &str = "id type radius x y z vx vy vz omegax omegay omegaz";

/// One frame of `sim`'s particles as a LAMMPS text dump.
pub fn frame(sim: &Simulation) -> Result<String, SimError> {
    let p = &sim.particles;
    let c = SnapshotCell::of(&sim.pbox);
    let [lx, ly, lz] = c.len;
    let mut s = String::with_capacity(p.len() * 160 + 256);
    let _ = writeln!(s, "ITEM: TIMESTEP\n{}", sim.step);
    let _ = writeln!(s, "ITEM: NUMBER OF ATOMS\n{}", p.len());
    if c.sheared {
        // The bounding box of the tilted cell along x, then the tilts xy, xz, yz.
        let t = c.tilt_xy;
        let _ = writeln!(s, "ITEM: BOX BOUNDS xy xz yz pp pp pp");
        let _ = writeln!(s, "{} {} {t}", t.min(0.0), lx + t.max(0.0));
        let _ = writeln!(s, "0 {ly} 0\n0 {lz} 0");
    } else {
        let _ = writeln!(s, "ITEM: BOX BOUNDS pp pp pp");
        let _ = writeln!(s, "0 {lx}\n0 {ly}\n0 {lz}");
    }
    let _ = writeln!(s, "ITEM: ATOMS {COLUMNS}");
    for i in 0..p.len() {
        let _ = write!(
            s,
            "{} {} {}",
            u64::from(p.id[i]) + 1,
            u32::from(p.species[i]) + 1,
            p.radius[i]
        );
        push_vectors(&mut s, &[p.pos[i], p.vel[i], p.omega[i]]);
        s.push('\n');
    }
    Ok(s)
}
