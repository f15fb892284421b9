"""The snapshot files of `suspflow simulate --snapshot N` read by ASE itself: every frame,
every particle, the positions as the simulator wrote them, and the cell (sheared by the
Lees-Edwards offset in a sheared scene)."""
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
    for fmt in ["xyz", "lammps"]:
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
