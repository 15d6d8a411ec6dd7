//! CSV sink: force histories, one row per step.
//!
//! Columns: `time_s, step, status`, then per finger `<name>_normal_force_n`,
//! `<name>_friction_n`, `<name>_slip_fraction`, then `iterations, wall_time_s`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use super::{sink_err, RunInfo, Sink};
use crate::error::TransferError;
use crate::sinks::mcap_log::FingersMessage;
use crate::stepper::StepRecord;

/// Writes a CSV force history.
pub struct CsvSink {
    out: Option<BufWriter<File>>,
    path: std::path::PathBuf,
}

impl CsvSink {
    /// Creates the file (the caller has checked it may be written).
    pub fn create(path: &Path) -> Result<Self, TransferError> {
        let tmp = super::partial_path(path);
        let f =
            File::create(&tmp).map_err(|e| sink_err("csv", format!("{}: {e}", tmp.display())))?;
        Ok(CsvSink {
            out: Some(BufWriter::new(f)),
            path: path.to_path_buf(),
        })
    }

    fn out(&mut self) -> Result<&mut BufWriter<File>, TransferError> {
        self.out
            .as_mut()
            .ok_or_else(|| sink_err("csv", "already finished"))
    }
}

impl Sink for CsvSink {
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        let mut h = String::from("time_s,step,status");
        for f in &run.scene.fingers {
            h.push_str(&format!(
                ",{0}_normal_force_n,{0}_friction_n,{0}_slip_fraction",
                f.name
            ));
        }
        h.push_str(",iterations,wall_time_s\n");
        self.out()?
            .write_all(h.as_bytes())
            .map_err(|e| sink_err("csv", e))
    }

    fn step(&mut self, _run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let m = FingersMessage::from_record(r);
        let mut line = format!("{},{},{}", r.time_s, r.index, m.status);
        for f in &m.fingers {
            line.push_str(&format!(
                ",{},{},{}",
                f.normal_force_n, f.tangential_magnitude_n, f.slip_fraction
            ));
        }
        line.push_str(&format!(",{},{}\n", m.iterations, r.wall_time_s));
        self.out()?
            .write_all(line.as_bytes())
            .map_err(|e| sink_err("csv", e))
    }

    fn finish(&mut self) -> Result<(), TransferError> {
        if let Some(mut o) = self.out.take() {
            o.flush().map_err(|e| sink_err("csv", e))?;
            drop(o);
            super::move_into_place("csv", &super::partial_path(&self.path), &self.path)?;
        }
        Ok(())
    }

    fn abort(&mut self) {
        if let Some(mut o) = self.out.take() {
            let _ = o.flush();
        }
    }
}
