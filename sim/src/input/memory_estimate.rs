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
//! [`check_fits_here`] where a run is about to start (or a command checks one), not when the
//! scene is read, so that one scene file is valid on every host.
use crate::error::SimError;
use crate::input::scene::Scene;

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

/// Fails when the run of `scene` needs more memory than this machine has (see
/// [`Scene::memory_bytes`]); passes when the machine's memory is unknown.
pub fn check_fits_here(scene: &Scene) -> Result<(), SimError> {
    match physical_bytes().filter(|&machine| scene.memory_bytes > machine) {
        None => Ok(()),
        Some(machine) => {
            let [l_x, l_y, l_z] = scene.box_len;
            Err(SimError::field(
                "box",
                format!(
                    "{} particles (phi = {} in a box of {l_x} x {l_y} x {l_z}) need about {} \
                     of memory, more than this machine's {}; use a smaller box",
                    scene.n_particles(),
                    scene.file.particles.phi,
                    describe(scene.memory_bytes),
                    describe(machine)
                ),
            ))
        }
    }
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

    /// A scene too large for any host is a valid scene (reading it does not depend on the
    /// host); the host's check refuses it, and passes a small one.
    #[test]
    fn the_host_check_is_separate_from_reading() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/scenes");
        let large = Scene::from_path(
            std::path::Path::new(&format!("{dir}/bad/box_too_large_for_memory.toml")),
            true,
        )
        .expect("a scene of 4e8 particles is read");
        assert!(large.memory_bytes > 4e11, "{}", large.memory_bytes);
        if physical_bytes().is_some_and(|m| m < large.memory_bytes) {
            let message = check_fits_here(&large).unwrap_err().to_string();
            assert!(message.contains("more than this machine's"), "{message}");
        }
        let quick = Scene::from_path(
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/quick.toml")),
            true,
        )
        .unwrap();
        assert!(check_fits_here(&quick).is_ok());
    }
}
