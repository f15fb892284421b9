//! GSD frames (`frames.gsd`): the binary trajectory format of HOOMD-blue (GSD file layer 2.0,
//! schema `hoomd` 1.4), read by OVITO, MDAnalysis (`format="GSD"`, with the `gsd` package)
//! and the `gsd` package itself. Chosen over H5MD because OVITO reads GSD and not H5MD, and
//! because its layout is simple enough to write here without an HDF5 library.
//!
//! Per frame: `configuration/step`, `configuration/box` (`[L_x, L_y, L_z, xy, 0, 0]`, the
//! HOOMD tilt factor `xy` = the [`SnapshotCell`]'s tilt / L_y), `particles/position` and
//! `particles/velocity` (float32, particles in order of identity), `log/particles/omega`
//! (float32 spins, 1 / time) and `log/time` (float64). The first frame also holds
//! `particles/N`, `particles/types` (the element symbols of [`element_symbol`]),
//! `particles/typeid` (the species), `particles/mass` (rho a^3) and `particles/diameter`
//! (2 x radius), which later frames take from it as the schema says. HOOMD's box is centred
//! on the origin: positions are the simulator's minus the centre of the cell (`(L_x + xy
//! L_y, L_y, L_z) / 2`). Lengths in units a, velocities in a / time. float32 keeps 7
//! digits: the text formats keep the state exactly. 36 bytes per particle and frame after
//! the first, against about 196 in extended XYZ.
//!
//! The file: a 256-byte header, a name list written once (a chunk's id is its name's place
//! in [`NAMES`]), the chunks' data appended frame after frame, and an index of 32-byte
//! entries sorted by frame and id, rewritten at the end of the file with twice the room
//! when full. A frame's data are written before its index entries, so an interrupted write
//! leaves the frames before it readable.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::element_symbol::element_symbol;
use crate::output::snapshot_cell::SnapshotCell;
use std::fs::File;
use std::os::unix::fs::FileExt;

const MAGIC: u64 = 0x65DF_65DF_65DF_65DF;
const HEADER_BYTES: u64 = 256;
const ENTRY_BYTES: usize = 32;
/// The name list's room, in GSD's units of 64 bytes.
const NAMELIST_ENTRIES: u64 = 8;
/// Index entries room at creation (doubled when full).
const INITIAL_INDEX_ENTRIES: u64 = 128;
/// The chunk names; a name's place is its id.
const NAMES: [&str; 11] = [
    "configuration/step",
    "configuration/box",
    "particles/N",
    "particles/types",
    "particles/typeid",
    "particles/mass",
    "particles/diameter",
    "particles/position",
    "particles/velocity",
    "log/particles/omega",
    "log/time",
];
/// The chunks only the first frame holds (by id).
const FIRST_FRAME_ONLY: [u16; 5] = [2, 3, 4, 5, 6];

/// GSD's data type codes.
#[derive(Clone, Copy)]
enum Kind {
    U32 = 3,
    U64 = 4,
    I8 = 5,
    F32 = 9,
    F64 = 10,
}

/// One chunk: its name's id, shape `n x m` and little-endian bytes.
struct Chunk {
    id: u16,
    n: u64,
    m: u32,
    kind: Kind,
    bytes: Vec<u8>,
}

fn version(major: u32, minor: u32) -> u32 {
    (major << 16) | minor
}

fn error(e: impl std::fmt::Display) -> SimError {
    SimError::Output {
        path: "frames.gsd".into(),
        message: e.to_string(),
    }
}

/// The index of an existing GSD file: where it lies, its room, its bytes and the entries
/// in use (the first `used`; they end at the first with location 0).
struct Index {
    location: u64,
    allocated: u64,
    entries: Vec<u8>,
    used: usize,
}

impl Index {
    fn read(file: &File) -> Result<Index, SimError> {
        let len = file.metadata().map_err(error)?.len();
        let mut header = [0u8; HEADER_BYTES as usize];
        file.read_exact_at(&mut header, 0).map_err(|_| {
            error(format!(
                "not a GSD file: {len} bytes, shorter than a GSD header"
            ))
        })?;
        let word =
            |k: usize| u64::from_le_bytes(header[8 * k..8 * k + 8].try_into().expect("8 bytes"));
        if word(0) != MAGIC {
            return Err(error("not a GSD file (no GSD header)"));
        }
        let (location, allocated) = (word(1), word(2));
        if location.saturating_add(allocated.saturating_mul(ENTRY_BYTES as u64)) > len {
            return Err(error(format!(
                "a damaged GSD file: its index ({allocated} entries at byte {location}) \
                 lies beyond its {len} bytes"
            )));
        }
        let mut entries = vec![0u8; allocated as usize * ENTRY_BYTES];
        file.read_exact_at(&mut entries, location).map_err(error)?;
        let mut index = Index {
            location,
            allocated,
            entries,
            used: 0,
        };
        index.used = (0..allocated as usize)
            .find(|&i| index.data_location(i) == 0)
            .unwrap_or(allocated as usize);
        Ok(index)
    }

    /// The frame of entry `i`.
    fn frame(&self, i: usize) -> u64 {
        u64::from_le_bytes(self.entries[i * ENTRY_BYTES..][..8].try_into().expect("8"))
    }

    /// Where the data of entry `i` lie (0: an unused entry).
    fn data_location(&self, i: usize) -> u64 {
        i64::from_le_bytes(
            self.entries[i * ENTRY_BYTES + 16..][..8]
                .try_into()
                .expect("8"),
        ) as u64
    }

    /// The number of frames: the last entry's frame plus one.
    fn frames(&self) -> u64 {
        match self.used {
            0 => 0,
            n => self.frame(n - 1) + 1,
        }
    }
}

/// Checks, before a resumed run appends to it, that `file` is empty or a GSD file whose
/// index can be read.
pub fn check_continuable(file: &File) -> Result<(), SimError> {
    if file.metadata().map_err(error)?.len() == 0 {
        return Ok(());
    }
    Index::read(file).map(|_| ()).map_err(|e| match e {
        SimError::Output { path, message } => SimError::Output {
            path,
            message: format!(
                "{message}: the resumed run cannot continue its frames; move it away to \
                 write them afresh"
            ),
        },
        other => other,
    })
}

/// Keeps the first `frames` frames of the GSD file `file` (all of them when it has fewer):
/// the index entries of the later frames are cleared and their data cut off, so that the
/// next frame appended is frame number `frames`. The index moves to the cut when it lay
/// beyond it (it is rewritten at the end of the file when it grows).
pub fn keep_frames(file: &File, frames: u64) -> Result<(), SimError> {
    if file.metadata().map_err(error)?.len() == 0 {
        return Ok(());
    }
    let index = Index::read(file)?;
    let Some(first_cut) = (0..index.used).find(|&i| index.frame(i) >= frames) else {
        return Ok(());
    };
    if first_cut == 0 {
        // No frame is kept: an empty file, created again by the next frame.
        return file.set_len(0).map_err(error);
    }
    // Frames are written in order, their chunks in the order of their entries.
    let cut = index.data_location(first_cut);
    let mut block = index.entries[..first_cut * ENTRY_BYTES].to_vec();
    block.resize(index.entries.len(), 0);
    if index.location < cut {
        file.write_all_at(&block, index.location).map_err(error)?;
        file.set_len(cut).map_err(error)?;
    } else {
        file.write_all_at(&block, cut).map_err(error)?;
        file.write_all_at(&cut.to_le_bytes(), 8).map_err(error)?;
        file.set_len(cut + block.len() as u64).map_err(error)?;
    }
    Ok(())
}

/// Appends a frame of `sim` to the GSD file `file` (created when empty).
pub fn append_frame(file: &File, sim: &Simulation) -> Result<(), SimError> {
    let mut end = file.metadata().map_err(error)?.len();
    if end == 0 {
        end = create(file)?;
    }
    let index = Index::read(file)?;
    let (used, frame) = (index.used, index.frames());
    // The data, then the entries that point at them.
    let chunks = frame_chunks(sim, frame == 0)?;
    let mut data = Vec::new();
    let mut new_entries = Vec::new();
    for c in &chunks {
        new_entries.extend_from_slice(&frame.to_le_bytes());
        new_entries.extend_from_slice(&c.n.to_le_bytes());
        new_entries.extend_from_slice(&((end + data.len() as u64) as i64).to_le_bytes());
        new_entries.extend_from_slice(&c.m.to_le_bytes());
        new_entries.extend_from_slice(&c.id.to_le_bytes());
        new_entries.extend_from_slice(&[c.kind as u8, 0]);
        data.extend_from_slice(&c.bytes);
    }
    file.write_all_at(&data, end).map_err(error)?;
    end += data.len() as u64;
    let needed = (used + chunks.len()) as u64;
    if needed <= index.allocated {
        let at = index.location + (used * ENTRY_BYTES) as u64;
        file.write_all_at(&new_entries, at).map_err(error)?;
    } else {
        // A larger index at the end of the file, then the header that points at it.
        let allocated = needed.max(2 * index.allocated);
        let mut block = index.entries[..used * ENTRY_BYTES].to_vec();
        block.extend_from_slice(&new_entries);
        block.resize(allocated as usize * ENTRY_BYTES, 0);
        file.write_all_at(&block, end).map_err(error)?;
        file.write_all_at(&end.to_le_bytes(), 8).map_err(error)?;
        file.write_all_at(&allocated.to_le_bytes(), 16)
            .map_err(error)?;
    }
    Ok(())
}

/// Writes the header, the name list and an empty index into an empty file; returns its
/// length.
fn create(file: &File) -> Result<u64, SimError> {
    let namelist_location = HEADER_BYTES;
    let index_location = namelist_location + 64 * NAMELIST_ENTRIES;
    let mut h = Vec::with_capacity(HEADER_BYTES as usize);
    for word in [
        MAGIC,
        index_location,
        INITIAL_INDEX_ENTRIES,
        namelist_location,
        NAMELIST_ENTRIES,
    ] {
        h.extend_from_slice(&word.to_le_bytes());
    }
    h.extend_from_slice(&version(1, 4).to_le_bytes());
    h.extend_from_slice(&version(2, 0).to_le_bytes());
    for text in [concat!("suspflow ", env!("CARGO_PKG_VERSION")), "hoomd"] {
        let mut field = [0u8; 64];
        field[..text.len()].copy_from_slice(text.as_bytes());
        h.extend_from_slice(&field);
    }
    h.resize(HEADER_BYTES as usize, 0);
    let mut names: Vec<u8> = NAMES
        .iter()
        .flat_map(|n| [n.as_bytes(), &[0]].concat())
        .collect();
    assert!(
        names.len() < 64 * NAMELIST_ENTRIES as usize,
        "the names fit their room"
    );
    names.resize(64 * NAMELIST_ENTRIES as usize, 0);
    let index = vec![0u8; INITIAL_INDEX_ENTRIES as usize * ENTRY_BYTES];
    let all = [h, names, index].concat();
    file.write_all_at(&all, 0).map_err(error)?;
    Ok(all.len() as u64)
}

fn f32_bytes(values: impl IntoIterator<Item = f64>) -> Vec<u8> {
    values
        .into_iter()
        .flat_map(|v| (v as f32).to_le_bytes())
        .collect()
}

/// The chunks of one frame of `sim`, sorted by id; the constant ones when `first`.
fn frame_chunks(sim: &Simulation, first: bool) -> Result<Vec<Chunk>, SimError> {
    let p = &sim.particles;
    let n = p.len();
    // Particles in order of identity, the same in every frame.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| p.id[i]);
    let cell = SnapshotCell::of(&sim.pbox);
    let [lx, ly, lz] = cell.len;
    let xy = cell.tilt_xy / ly;
    let centre = [0.5 * (lx + cell.tilt_xy), 0.5 * ly, 0.5 * lz];
    let per_particle = |m: u32, kind: Kind, id: u16, bytes: Vec<u8>| Chunk {
        id,
        n: n as u64,
        m,
        kind,
        bytes,
    };
    // A column of `n` values.
    let column = |id: u16, kind: Kind, n: u64, bytes: Vec<u8>| Chunk {
        id,
        n,
        m: 1,
        kind,
        bytes,
    };
    let species = p
        .species
        .iter()
        .copied()
        .max()
        .map_or(0, |s| s as usize + 1);
    let symbols = (0..species)
        .map(|s| element_symbol(s as u16))
        .collect::<Result<Vec<_>, _>>()?;
    let width = symbols.iter().map(|s| s.len()).max().unwrap_or(0) + 1;
    let types: Vec<u8> = symbols
        .iter()
        .flat_map(|s| {
            let mut row = s.as_bytes().to_vec();
            row.resize(width, 0);
            row
        })
        .collect();
    let vectors = |v: &[crate::state::Vec3], shift: [f64; 3]| {
        f32_bytes(
            order
                .iter()
                .flat_map(|&i| (0..3).map(move |k| v[i][k] - shift[k])),
        )
    };
    let chunks = vec![
        column(0, Kind::U64, 1, sim.step.to_le_bytes().to_vec()),
        column(1, Kind::F32, 6, f32_bytes([lx, ly, lz, xy, 0.0, 0.0])),
        column(2, Kind::U32, 1, (n as u32).to_le_bytes().to_vec()),
        Chunk {
            id: 3,
            n: species as u64,
            m: width as u32,
            kind: Kind::I8,
            bytes: types,
        },
        per_particle(
            1,
            Kind::U32,
            4,
            order
                .iter()
                .flat_map(|&i| u32::from(p.species[i]).to_le_bytes())
                .collect(),
        ),
        per_particle(1, Kind::F32, 5, f32_bytes(order.iter().map(|&i| p.mass[i]))),
        per_particle(
            1,
            Kind::F32,
            6,
            f32_bytes(order.iter().map(|&i| 2.0 * p.radius[i])),
        ),
        per_particle(3, Kind::F32, 7, vectors(&p.pos, centre)),
        per_particle(3, Kind::F32, 8, vectors(&p.vel, [0.0; 3])),
        per_particle(3, Kind::F32, 9, vectors(&p.omega, [0.0; 3])),
        column(10, Kind::F64, 1, sim.time.to_le_bytes().to_vec()),
    ];
    Ok(chunks
        .into_iter()
        .filter(|c| first || !FIRST_FRAME_ONLY.contains(&c.id))
        .collect())
}
