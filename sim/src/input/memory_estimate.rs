//! Memory a run needs, estimated before anything is allocated, so that a scene too large
//! for the machine is refused with the figure instead of aborting on an allocation.
//!
//! A run holds, per particle, its state (position, velocity, spin, force, torque: five
//! 3-vectors; radius, mass, species, id), the neighbour list's reference positions and
//! neighbour indices, the force accumulator's per-thread buffers and the checkpoint's JSON
//! text while it is written; and one start index per cell of the cell list.
//! [`BYTES_PER_PARTICLE`] is the peak resident size per particle measured on dense scenes
//! (see its documentation); the estimate is meant to be right within a factor of about 2.
//! A scene carries its estimate; whether it fits is a property of the host, checked by
//! [`Scene::check_fits_here`](crate::input::scene::Scene::check_fits_here) where a run is about to start (or a command checks one), not when the
//! scene is read, so that one scene file is valid on every host.

/// Peak resident bytes per particle of `suspflow simulate`: 815 measured as
/// `(maxRSS(N = 11018) - maxRSS(N = 282)) / 10736` with `/usr/bin/time -v` on one thread
/// (phi 0.54, L_y = 16, L_x = L_z = 100 and 16, lubrication on, a checkpoint written every
/// snapshot), rounded up for the per-thread force buffers of parallel runs.
pub const BYTES_PER_PARTICLE: f64 = 1000.0;

/// Bytes per cell of the cell list (one start index).
const BYTES_PER_CELL: f64 = 8.0;

/// Estimated peak memory (bytes) of a run of `n_particles` in a box `box_len` whose cell
/// list uses cells at least `cell_width` wide (all lengths in `a`).
pub fn run_bytes(n_particles: usize, box_len: [f64; 3], cell_width: f64) -> f64 {
    let cells: f64 = box_len
        .iter()
        .map(|l| (l / cell_width).floor().max(1.0))
        .product();
    n_particles as f64 * BYTES_PER_PARTICLE + cells * BYTES_PER_CELL
}

/// Physical memory of this machine in bytes (`MemTotal` of `/proc/meminfo`), if known.
pub fn physical_bytes() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// `bytes` for people: `512 MB`, `3.2 GB`, `41000 GB`.
pub fn describe(bytes: f64) -> String {
    if bytes < 1e9 {
        format!("{:.0} MB", bytes / 1e6)
    } else {
        format!("{:.1} GB", bytes / 1e9)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grows_with_particles_and_cells() {
        let small = run_bytes(1000, [10.0; 3], 3.0);
        assert_eq!(small, 1000.0 * BYTES_PER_PARTICLE + 27.0 * BYTES_PER_CELL);
        assert!(run_bytes(2000, [10.0; 3], 3.0) > small);
        assert!(run_bytes(1000, [100.0; 3], 3.0) > small);
        assert_eq!(describe(5.12e8), "512 MB");
        assert_eq!(describe(4.1e13), "41000.0 GB");
    }
}
