//! The frames file of a run: a particle frame in a [`SnapshotFormat`] every `every` samples,
//! appended to the file of the run a resumed run continues. A failed write is kept and
//! reported at the end, so that the run itself goes on.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::snapshot_format::SnapshotFormat;
use std::path::Path;

/// An open frames file.
pub struct FrameWriter {
    format: SnapshotFormat,
    every: u64,
    file: std::fs::File,
    error: Option<SimError>,
}

impl FrameWriter {
    /// Opens `dir/<format's file name>`: truncated, or appended to when `append` (a resumed run).
    /// Opened for reading and writing without `O_APPEND`: a GSD frame also updates the
    /// file's index and header in place.
    pub fn open(
        dir: &Path,
        format: SnapshotFormat,
        every: u64,
        append: bool,
    ) -> Result<Self, SimError> {
        let path = dir.join(format.file_name());
        let file = std::fs::OpenOptions::new()
            .create(true)
            .read(true)
            .write(true)
            .truncate(!append)
            .open(&path)
            .map_err(|e| SimError::Output {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
        Ok(Self {
            format,
            every: every.max(1),
            file,
            error: None,
        })
    }

    /// After sample number `samples` of the run: writes a frame of `sim` when `samples` is a
    /// multiple of `every` and no write has failed yet.
    pub fn after_sample(&mut self, samples: u64, sim: &Simulation) {
        if samples.is_multiple_of(self.every) && self.error.is_none() {
            self.error = self.format.append_frame(&mut self.file, sim).err();
        }
    }

    /// The first failed write, if any.
    pub fn finish(self) -> Result<(), SimError> {
        self.error.map_or(Ok(()), Err)
    }
}
