//! The file formats of the particle frames a run writes every few snapshots: extended XYZ
//! ([`extended_xyz`]) or a LAMMPS text dump ([`lammps_dump`]).
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::{extended_xyz, lammps_dump};
use std::io::Write as _;

/// A snapshot file format.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SnapshotFormat {
    /// Extended XYZ, `frames.xyz`.
    #[default]
    Xyz,
    /// LAMMPS text dump, `frames.lammpstrj`.
    Lammps,
}

impl SnapshotFormat {
    /// The name of the frames file in a result directory.
    pub fn file_name(self) -> &'static str {
        match self {
            SnapshotFormat::Xyz => "frames.xyz",
            SnapshotFormat::Lammps => "frames.lammpstrj",
        }
    }

    /// One frame of `sim` in this format.
    pub fn frame(self, sim: &Simulation) -> Result<String, SimError> {
        match self {
            SnapshotFormat::Xyz => extended_xyz::frame(sim),
            SnapshotFormat::Lammps => lammps_dump::frame(sim),
        }
    }

    /// Appends one frame of `sim` to `file`.
    pub fn append_frame(self, file: &mut std::fs::File, sim: &Simulation) -> Result<(), SimError> {
        file.write_all(self.frame(sim)?.as_bytes())
            .map_err(|e| SimError::Output {
                path: self.file_name().into(),
                message: e.to_string(),
            })
    }
}

impl std::str::FromStr for SnapshotFormat {
    type Err = SimError;

    /// `xyz` or `lammps`.
    fn from_str(s: &str) -> Result<Self, SimError> {
        match s {
            "xyz" => Ok(SnapshotFormat::Xyz),
            "lammps" => Ok(SnapshotFormat::Lammps),
            other => Err(SimError::Output {
                path: "frames".into(),
                message: format!("unknown snapshot format `{other}` (xyz or lammps)"),
            }),
        }
    }
}
