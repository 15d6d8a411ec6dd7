//! The files a transfer run writes, opened from the paths asked for: an MCAP log, a Rerun
//! recording, a CSV history and an `.npz` archive of the element fields, each a [`Sink`] writing the temporary file of its target
//! under the run's output policy ([`grasp_io::OutputSet`]: claimed targets, exclusive
//! temporary files moved into place on success). Every front end opens its files here.

use std::path::Path;

use grasp_io::{OutputError, OutputSet, PendingOutput};

use super::csv_history::CsvSink;
use super::mcap_log::McapSink;
use super::npz_steps::NpzSink;
use super::rerun_log::RerunSink;
use super::ros2_log::Ros2McapSink;
use super::sink::Sink;
use crate::error::TransferError;

/// What the MCAP log holds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum McapProfile {
    /// JSON messages with JSON Schemas, for Foxglove (`super::mcap_log`).
    #[default]
    Json,
    /// CDR-encoded ROS 2 messages with `ros2msg` schemas, as `ros2 bag record` writes them
    /// (`super::ros2_log`), stamped `start_ns` nanoseconds after the Unix epoch plus the
    /// schedule's time.
    Ros2 {
        /// The stamp of schedule time 0, ns after the Unix epoch.
        start_ns: u64,
    },
}

impl McapProfile {
    /// The ROS 2 profile whose schedule time 0 is stamped `start_s` seconds after the Unix
    /// epoch; `Err` (what to give instead) outside `[0, 2^31 - 1)`, the seconds a ROS 2 stamp
    /// holds.
    pub fn ros2_from(start_s: f64) -> Result<Self, String> {
        let largest = i32::MAX as f64;
        if !(0.0..largest).contains(&start_s) {
            return Err(format!(
                "give the seconds after the Unix epoch, in [0, {largest}) (a ROS 2 stamp's \
                 seconds are a 32-bit integer)"
            ));
        }
        // Whole seconds and the fraction apart: `start_s * 1e9` would round a recent epoch time's
        // fraction to 256 ns.
        let whole = start_s.floor();
        let fraction_ns = ((start_s - whole) * 1e9).round() as u64;
        Ok(McapProfile::Ros2 {
            start_ns: whole as u64 * 1_000_000_000 + fraction_ns,
        })
    }
}

/// The targets asked for (none: no file of that kind).
#[derive(Debug, Clone, Copy, Default)]
pub struct OutputPaths<'a> {
    /// The MCAP log.
    pub mcap: Option<&'a Path>,
    /// What it holds.
    pub mcap_profile: McapProfile,
    /// The Rerun recording (`.rrd`).
    pub rrd: Option<&'a Path>,
    /// The CSV force history.
    pub csv: Option<&'a Path>,
    /// Every step's element fields as NumPy arrays (`.npz`).
    pub npz: Option<&'a Path>,
}

/// Why the files could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// A target refused, or its temporary file not created.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A sink could not start on its file.
    #[error(transparent)]
    Sink(#[from] TransferError),
}

/// The sinks of the files asked for, each writing its temporary file; the temporary files are
/// removed when dropped unless taken ([`OutputFiles::take_pending`]) and committed.
pub struct OutputFiles {
    mcap: Option<McapSink>,
    ros2: Option<Ros2McapSink>,
    rrd: Option<RerunSink>,
    csv: Option<CsvSink>,
    npz: Option<NpzSink>,
    pending: Vec<PendingOutput>,
}

impl OutputFiles {
    /// Opens a temporary file for each target of `paths` (claimed in `outputs`), in the order
    /// MCAP, recording, CSV, `.npz`, and a sink writing it.
    pub fn open(outputs: &OutputSet, paths: OutputPaths<'_>) -> Result<OutputFiles, OpenError> {
        let mut files = OutputFiles {
            mcap: None,
            ros2: None,
            rrd: None,
            csv: None,
            npz: None,
            pending: Vec::new(),
        };
        if let Some(t) = paths.mcap {
            let p = outputs.create(t)?;
            match paths.mcap_profile {
                McapProfile::Json => files.mcap = Some(McapSink::from_file(p.file_handle()?, t)?),
                McapProfile::Ros2 { start_ns } => {
                    files.ros2 = Some(Ros2McapSink::from_file(p.file_handle()?, t, start_ns)?)
                }
            }
            files.pending.push(p);
        }
        if let Some(t) = paths.rrd {
            let p = outputs.create(t)?;
            files.rrd = Some(RerunSink::create_as(&p.write_path(), t)?);
            files.pending.push(p);
        }
        if let Some(t) = paths.csv {
            let p = outputs.create(t)?;
            files.csv = Some(CsvSink::from_file(p.file_handle()?, t));
            files.pending.push(p);
        }
        if let Some(t) = paths.npz {
            let p = outputs.create(t)?;
            files.npz = Some(NpzSink::from_file(p.file_handle()?, t));
            files.pending.push(p);
        }
        Ok(files)
    }

    /// The sinks of a run, in the order they are written: MCAP, the recording, `live` (a
    /// stream to a viewer, when there is one), CSV, `.npz`.
    pub fn sinks<'a>(&'a mut self, live: Option<&'a mut RerunSink>) -> Vec<&'a mut dyn Sink> {
        let mut v: Vec<&mut dyn Sink> = Vec::new();
        if let Some(s) = self.mcap.as_mut() {
            v.push(s);
        }
        if let Some(s) = self.ros2.as_mut() {
            v.push(s);
        }
        if let Some(s) = self.rrd.as_mut() {
            v.push(s);
        }
        if let Some(s) = live {
            v.push(s);
        }
        if let Some(s) = self.csv.as_mut() {
            v.push(s);
        }
        if let Some(s) = self.npz.as_mut() {
            v.push(s);
        }
        v
    }

    /// Names the recording, when there is one (the viewer lists it by this name).
    pub fn name_recording(&mut self, name: &str) {
        if let Some(s) = self.rrd.as_mut() {
            s.set_recording_name(name);
        }
    }

    /// Writes the warnings (the CSV's column, the MCAP's metadata) with the option names of the
    /// front end that runs: `respell` rewrites a library text (`grasp_model::option_names`).
    pub fn respell_options(&mut self, respell: fn(&str) -> String) {
        if let Some(s) = self.mcap.as_mut() {
            s.respell_options(respell);
        }
        if let Some(s) = self.ros2.as_mut() {
            s.respell_options(respell);
        }
        if let Some(s) = self.csv.as_mut() {
            s.respell_options(respell);
        }
    }

    /// Adds another output of the run (a picture), committed and removed with the files.
    pub fn add_pending(&mut self, output: PendingOutput) {
        self.pending.push(output);
    }

    /// The temporary files, to commit once the run is complete (the sinks finished).
    pub fn take_pending(&mut self) -> Vec<PendingOutput> {
        std::mem::take(&mut self.pending)
    }
}
