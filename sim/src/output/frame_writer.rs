//! The frames file of a run: a particle frame in a [`SnapshotFormat`] every `every` samples,
//! appended to the file of the run a resumed run continues. A resumed run first cuts the
//! file back to the frames of the samples before its own first one (in a text format by
//! the line count of a frame, in GSD by its frame index): frames that a run killed after
//! its last checkpoint wrote are written again by the resumed run, and must not be there
//! twice (time running backwards). A failed write is kept and reported at the end, so that
//! the run itself goes on.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::output::gsd;
use crate::output::snapshot_format::SnapshotFormat;
use std::io::{BufRead, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// An open frames file.
pub struct FrameWriter {
    format: SnapshotFormat,
    every: u64,
    path: PathBuf,
    file: std::fs::File,
    /// A resumed run's file, not yet cut back to the frames before its first sample.
    to_trim: bool,
    error: Option<SimError>,
}

impl FrameWriter {
    /// Opens `dir/<format's file name>`: truncated, or continued when `append` (a resumed run).
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
        if append && format == SnapshotFormat::Gsd {
            gsd::check_continuable(&file)?;
        }
        Ok(Self {
            format,
            every: every.max(1),
            path,
            file,
            to_trim: append,
            error: None,
        })
    }

    /// After sample number `samples` of the run: writes a frame of `sim` when `samples` is a
    /// multiple of `every` and no write has failed yet.
    pub fn after_sample(&mut self, samples: u64, sim: &Simulation) {
        if self.error.is_some() {
            return;
        }
        if std::mem::take(&mut self.to_trim) {
            // The frames of samples 1 ..= samples - 1: by the GSD index, or in a text
            // format each as many lines as this one's.
            let kept = samples.saturating_sub(1) / self.every;
            let trimmed = match self.format {
                SnapshotFormat::Gsd => gsd::keep_frames(&self.file, kept),
                text => text
                    .frame(sim)
                    .and_then(|frame| self.keep_lines(kept * frame.matches('\n').count() as u64)),
            };
            if let Err(e) = trimmed {
                self.error = Some(e);
                return;
            }
        }
        if samples.is_multiple_of(self.every) {
            self.error = self.format.append_frame(&mut self.file, sim).err();
        }
    }

    /// Cuts the file after its first `lines` lines (or keeps it whole if shorter, a partial
    /// last line dropped) and moves to its end.
    fn keep_lines(&mut self, lines: u64) -> Result<(), SimError> {
        let io = |e: std::io::Error| SimError::Output {
            path: self.path.display().to_string(),
            message: format!("cutting back the frames of a resumed run: {e}"),
        };
        self.file.rewind().map_err(io)?;
        let mut reader = std::io::BufReader::new(&self.file);
        let (mut end, mut line) = (0u64, Vec::new());
        for _ in 0..lines {
            line.clear();
            let read = reader.read_until(b'\n', &mut line).map_err(io)?;
            if read == 0 || line.last() != Some(&b'\n') {
                break;
            }
            end += read as u64;
        }
        drop(reader);
        self.file.set_len(end).map_err(io)?;
        self.file.seek(SeekFrom::End(0)).map_err(io)?;
        Ok(())
    }

    /// The first failed write, if any.
    pub fn finish(self) -> Result<(), SimError> {
        self.error.map_or(Ok(()), Err)
    }
}
