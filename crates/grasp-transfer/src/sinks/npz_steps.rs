//! `.npz` sink: every step's element fields as NumPy arrays (`grasp transfer --npz`), through
//! the archive of `grasp solve --npz` ([`grasp_io::NpzArchive`]): the arrays of step `k` are
//! named `step_<k>/<finger>/<field>` (`k` in five digits, `step_00012`), for the fingers of
//! that step's solution, with the readings of their tactile sensors beside them
//! (`step_<k>/<finger>/taxels/force_n`, ..., as `grasp solve --npz` names them); `times_s`
//! holds each step's time, s, and `state_names` the names of the `state` codes. The arrays
//! are written as the steps come, never held.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use grasp_io::NpzArchive;

use super::sink::{io_err, RunInfo, Sink};
use crate::error::TransferError;
use crate::stepper::StepRecord;

/// Writes every step's element fields into an `.npz` archive.
pub struct NpzSink {
    archive: Option<NpzArchive<BufWriter<File>>>,
    times_s: Vec<f64>,
    path: PathBuf,
}

impl NpzSink {
    /// Writes to an open file; `path` names it in error messages.
    pub fn from_file(file: File, path: &Path) -> Self {
        NpzSink {
            archive: Some(NpzArchive::new(BufWriter::with_capacity(1 << 20, file))),
            times_s: Vec::new(),
            path: path.to_path_buf(),
        }
    }

    fn archive(&mut self) -> Result<&mut NpzArchive<BufWriter<File>>, TransferError> {
        let path = &self.path;
        self.archive
            .as_mut()
            .ok_or_else(|| io_err("npz", path, "already finished"))
    }
}

impl Sink for NpzSink {
    fn begin(&mut self, _run: &RunInfo) -> Result<(), TransferError> {
        Ok(())
    }

    fn step(&mut self, _run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let prefix = format!("step_{:05}/", r.index);
        let archive = self.archive()?;
        let written = archive
            .add_solution(&prefix, &r.solution)
            .and_then(|()| archive.add_sensors(&prefix, &r.sensors));
        written.map_err(|e| io_err("npz", &self.path, e))?;
        self.times_s.push(r.time_s);
        Ok(())
    }

    fn finish(&mut self) -> Result<(), TransferError> {
        let times = std::mem::take(&mut self.times_s);
        let path = self.path.clone();
        let mut archive = self
            .archive
            .take()
            .ok_or_else(|| io_err("npz", &path, "already finished"))?;
        let written = archive
            .array("times_s", &[times.len() as u64], times)
            .and_then(|()| archive.finish())
            .and_then(|mut w| w.flush());
        written.map_err(|e| io_err("npz", &path, e))
    }

    fn abort(&mut self) {
        self.archive = None;
    }
}
