//! The file formats of the particle frames a run writes every few snapshots: extended XYZ
//! ([`extended_xyz`]), a LAMMPS text dump ([`lammps_dump`]) or binary GSD ([`gsd`]).
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::{extended_xyz, gsd, lammps_dump};
use std::io::{Seek as _, SeekFrom, Write as _};

/// A snapshot file format.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SnapshotFormat {
    /// Extended XYZ, `frames.xyz`.
    #[default]
    Xyz,
    /// LAMMPS text dump, `frames.lammpstrj`.
    Lammps,
    /// GSD (HOOMD-blue's binary format, float32), `frames.gsd`.
    Gsd,
}

impl SnapshotFormat {
    /// The name of the frames file in a result directory.
    pub fn file_name(self) -> &'static str {
        match self {
            SnapshotFormat::Xyz => "frames.xyz",
            SnapshotFormat::Lammps => "frames.lammpstrj",
            SnapshotFormat::Gsd => "frames.gsd",
        }
    }

    /// One frame of `sim` as text, in a text format (GSD frames only exist in their file).
    pub fn frame(self, sim: &Simulation) -> Result<String, SimError> {
        match self {
            SnapshotFormat::Xyz => extended_xyz::frame(sim),
            SnapshotFormat::Lammps => lammps_dump::frame(sim),
            SnapshotFormat::Gsd => Err(SimError::Output {
                path: self.file_name().into(),
                message: "GSD frames are binary; append them to their file".into(),
            }),
        }
    }

    /// Appends one frame of `sim` to `file` (opened for reading and writing).
    pub fn append_frame(self, file: &mut std::fs::File, sim: &Simulation) -> Result<(), SimError> {
        if self == SnapshotFormat::Gsd {
            return gsd::append_frame(file, sim);
        }
        let text = self.frame(sim)?;
        file.seek(SeekFrom::End(0))
            .and_then(|_| file.write_all(text.as_bytes()))
            .map_err(|e| SimError::Output {
                path: self.file_name().into(),
                message: e.to_string(),
            })
    }
}

impl std::str::FromStr for SnapshotFormat {
    type Err = SimError;

    /// `xyz`, `lammps` or `gsd`.
    fn from_str(s: &str) -> Result<Self, SimError> {
        match s {
            "xyz" => Ok(SnapshotFormat::Xyz),
            "lammps" => Ok(SnapshotFormat::Lammps),
            "gsd" => Ok(SnapshotFormat::Gsd),
            other => Err(SimError::Output {
                path: "frames".into(),
                message: format!("unknown snapshot format `{other}` (xyz, lammps or gsd)"),
            }),
        }
    }
}
