//! Snapshot frames read back: the extended-XYZ and LAMMPS-dump rows hold every particle's
//! state exactly (shortest round-trip decimals; the XYZ's momenta are mass x velocity), the
//! species as element symbols and types, the mass (XYZ), LAMMPS' ids from 1 and its column names,
//! and the cell of the box, sheared by the Lees-Edwards offset for a sheared scene.
use sim::input::initial_state::initial_particles;
use sim::input::scene::Scene;
use sim::integrate::simulation::Simulation;
use sim::output::snapshot_format::SnapshotFormat;
use std::path::PathBuf;

fn simulation(scene: &str) -> Simulation {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/scenes/good")
        .join(scene);
    let scene = Scene::from_path(&path, false).unwrap();
    let mut sim = Simulation::new(&scene, initial_particles(&scene).unwrap()).unwrap();
    sim.advance(20).unwrap();
    sim
}

fn numbers(fields: &[&str]) -> Vec<f64> {
    fields.iter().map(|f| f.parse().unwrap()).collect()
}

/// Every particle's identity, species, mass, radius, position, velocity and spin as written.
fn particle_state(sim: &Simulation, i: usize) -> Vec<f64> {
    let p = &sim.particles;
    let head = [p.id[i] as f64, p.species[i] as f64, p.mass[i], p.radius[i]];
    let vectors = [p.pos[i], p.vel[i], p.omega[i]];
    head.into_iter()
        .chain(vectors.iter().flat_map(|v| v.iter().copied()))
        .collect()
}

/// Checks an extended-XYZ frame of `sim` and returns the tilt its `Lattice` states.
fn check_xyz(sim: &Simulation) -> f64 {
    let text = SnapshotFormat::Xyz.frame(sim).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let n = sim.particles.len();
    assert_eq!(lines.len(), n + 2);
    assert_eq!(lines[0], n.to_string());
    let lattice = lines[1]
        .strip_prefix("Lattice=\"")
        .and_then(|l| l.split('"').next())
        .unwrap();
    let cell = numbers(&lattice.split(' ').collect::<Vec<_>>());
    let l = sim.pbox.len;
    assert_eq!([cell[0], cell[4], cell[8]], [l.x, l.y, l.z], "{}", lines[1]);
    assert!(lines[1].contains(
        "Properties=species:S:1:pos:R:3:id:I:1:species_index:I:1:radius:R:1:masses:R:1:momenta:R:3:velo:R:3:omega:R:3"
    ));
    assert!(lines[1].contains(&format!("Time={} Step={}", sim.time, sim.step)));
    let mut symbols = std::collections::BTreeSet::new();
    for (i, row) in lines[2..].iter().enumerate() {
        let f: Vec<&str> = row.split(' ').collect();
        assert_eq!(f.len(), 17);
        let v = numbers(&f[1..]);
        // Columns: symbol, pos, id, species_index, radius, masses, momenta, velo, omega.
        let (m, momenta) = (v[6], &v[7..10]);
        let reordered = [&[v[3], v[4], m, v[5]][..], &v[0..3], &v[10..16]].concat();
        let expected = particle_state(sim, i);
        assert_eq!(reordered, expected, "row {i}");
        for (q, v) in momenta.iter().zip(&v[10..13]) {
            // momenta / masses gives the velocity back to the last bit or two.
            assert!((q / m - v).abs() <= 4.0 * f64::EPSILON * v.abs(), "row {i}");
        }
        let expected = ["H", "He"][sim.particles.species[i] as usize];
        assert_eq!(f[0], expected);
        symbols.insert(f[0]);
    }
    assert_eq!(symbols.len(), 2, "the scenes are bidisperse");
    cell[3]
}

/// Checks a LAMMPS dump frame of `sim` and returns its tilt (None for an orthogonal box).
fn check_lammps(sim: &Simulation) -> Option<f64> {
    let text = SnapshotFormat::Lammps.frame(sim).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let n = sim.particles.len();
    assert_eq!(lines.len(), n + 9);
    assert_eq!(lines[0], "ITEM: TIMESTEP");
    assert_eq!(lines[1], sim.step.to_string());
    assert_eq!(lines[3], n.to_string());
    assert_eq!(
        lines[8],
        "ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz"
    );
    let l = sim.pbox.len;
    let bounds: Vec<Vec<f64>> = lines[5..8]
        .iter()
        .map(|b| numbers(&b.split(' ').collect::<Vec<_>>()))
        .collect();
    assert_eq!([bounds[1][1], bounds[2][1]], [l.y, l.z]);
    for (i, row) in lines[9..].iter().enumerate() {
        let mut v = numbers(&row.split(' ').collect::<Vec<_>>());
        // LAMMPS ids and types start at 1; the dump has no mass column.
        v[0] -= 1.0;
        v[1] -= 1.0;
        v.insert(2, sim.particles.mass[i]);
        assert_eq!(v, particle_state(sim, i), "row {i}");
    }
    match lines[4] {
        "ITEM: BOX BOUNDS pp pp pp" => {
            assert_eq!(bounds[0], vec![0.0, l.x]);
            None
        }
        "ITEM: BOX BOUNDS xy xz yz pp pp pp" => {
            let t = bounds[0][2];
            // x bounds of the tilted cell: its corners lie at x = 0, L_x, t and L_x + t.
            assert_eq!(bounds[0][0], t.min(0.0));
            assert_eq!(bounds[0][1], l.x + t.max(0.0));
            assert_eq!([bounds[1][2], bounds[2][2]], [0.0, 0.0]);
            Some(t)
        }
        other => panic!("unexpected box header {other}"),
    }
}

#[test]
fn unsheared_frames_have_a_rectangular_cell() {
    let sim = simulation("tiny.toml");
    assert_eq!(check_xyz(&sim), 0.0);
    assert_eq!(check_lammps(&sim), None);
}

#[test]
fn sheared_frames_carry_the_lees_edwards_offset_as_tilt() {
    let mut sim = simulation("tiny_shear.toml");
    // gdot L_y t = 0.02 * 10 * t: offset 3 at t = 15 (kept), 8 at t = 40 (8 - L_x = -1).
    for (t, tilt) in [(15.0, 3.0), (40.0, -1.0)] {
        sim.pbox.set_time(t);
        assert!((check_xyz(&sim) - tilt).abs() < 1e-9, "t = {t}");
        assert!((check_lammps(&sim).unwrap() - tilt).abs() < 1e-9, "t = {t}");
    }
}

#[test]
fn snapshot_formats_parse_by_name() {
    assert_eq!(
        "xyz".parse::<SnapshotFormat>().unwrap(),
        SnapshotFormat::Xyz
    );
    assert_eq!(
        "lammps".parse::<SnapshotFormat>().unwrap(),
        SnapshotFormat::Lammps
    );
    assert!("pdb".parse::<SnapshotFormat>().is_err());
}
