//! CSV sink: force histories, one row per step.
//!
//! Columns: `time_s, step, status`, then per finger `<name>_normal_force_n`,
//! `<name>_friction_n`, `<name>_slip_fraction`, then `solver, warm_start, iterations,
//! factorizations, wall_time_s` (which solver answered, whether the step started from the
//! previous one, its Newton or interior-point iterations and factorisations), then
//! `smallest_margin_n` (the step's smallest disturbance margin, N; empty without `--margins`,
//! `inf` when unbounded, empty when undetermined), then `compliance, inner_iterations` (the
//! form of the patch compliances, `dense`, `fft` or `mixed`, and the FFT path's
//! conjugate-gradient iterations in the step), then `margin_held_to_n` (the largest push
//! known to hold along the smallest margin's direction, N: the margin, the search's cap when
//! unbounded, a lower bound when undetermined; empty without `--margins`), then per finger
//! with a mount (`fingers[i].mount`; none without) `<name>_approach_m` (the jaw's commanded
//! position from first touch, m), `<name>_core_along_n_m` (its core's displacement from that
//! pose along the normal, m: negative pushed back) and `<name>_core_moved_m` (the length of
//! the core's translation, m; all empty while the finger is released), then per hand (`hands`)
//! `<hand>_translation_{x,y,z}_m` and `<hand>_rotation_{x,y,z}_rad` (its base's displacement
//! from its commanded pose, world frame) and per servo (`servos`) `<servo>_force_n` (the sum of
//! its jaws' normal forces) and `<servo>_travel_m` (the jaws' travel from the command, m:
//! negative pushed back; all empty while none of its fingers is in the grasp), then per finger with a
//! sensor its readings' summary (`super::sensor_columns`; none without), then `warnings`:
//! the step's warnings (the scene's among them), separated by [`CSV_WARNING_SEPARATOR`], empty
//! when it has none.
//!
//! The warnings are a column, not a comment line (a CSV reader takes a comment for a row) nor
//! a second file (a file the user did not name): each step's row says what holds at that step,
//! so a warning that depends on the step (a patch at its edge at some loads) is on exactly the
//! rows it applies to, and a spreadsheet or `pandas.read_csv` reads it with the rest. The run's
//! warnings told once each, with their steps, are the summary's (and the MCAP's metadata).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::mcap_log::FingersMessage;
use super::sensor_columns::{sensor_cells, sensor_header};
use super::sink::{io_err, RunInfo, Sink};
use crate::error::TransferError;
use crate::stepper::StepRecord;

/// The `smallest_margin_n` cell of step `r`: the margin, `inf` when unbounded, empty when
/// undetermined or not computed.
fn margin_cell(r: &StepRecord) -> String {
    match &r.margin {
        Some(m) if m.smallest_n.is_some() || m.undetermined.is_none() => {
            m.margin_or_bound_n().to_string()
        }
        _ => String::new(),
    }
}

/// The columns of a mounted finger, after its name and `_`.
const MOUNT_COLUMNS: [&str; 3] = ["approach_m", "core_along_n_m", "core_moved_m"];

/// The cells of finger `name`'s mount at step `r` (each with its leading comma): its approach
/// and its core's displacement, empty while it is out of the step's grasp.
fn mount_cells(r: &StepRecord, name: &str) -> String {
    match r
        .solution
        .finger(name)
        .and_then(|f| Some((f.approach_m, f.mount_displacement?)))
    {
        Some((approach, d)) => format!(",{approach},{},{}", d.normal_m, d.moved_m()),
        None => ",,,".into(),
    }
}

/// The columns of a hand, after its name and `_`.
const HAND_COLUMNS: [&str; 6] = [
    "translation_x_m",
    "translation_y_m",
    "translation_z_m",
    "rotation_x_rad",
    "rotation_y_rad",
    "rotation_z_rad",
];

/// The columns of a servo, after its name and `_`.
const SERVO_COLUMNS: [&str; 2] = ["force_n", "travel_m"];

/// The header cells of the scene's hands and servos (each with its leading comma).
fn shared_spring_header(run: &RunInfo) -> String {
    let hands = run.scene.hands.iter().map(|h| (&h.name, &HAND_COLUMNS[..]));
    let servos = run
        .scene
        .servos
        .iter()
        .map(|s| (&s.name, &SERVO_COLUMNS[..]));
    let mut h = String::new();
    for (name, columns) in hands.chain(servos) {
        for col in columns {
            h.push(',');
            h.push_str(&csv_field(&format!("{name}_{col}")));
        }
    }
    h
}

/// The cells of the scene's hands and servos at step `r` (each with its leading comma), empty
/// for one the step's grasp does not hold.
fn shared_spring_cells(run: &RunInfo, r: &StepRecord) -> String {
    let mut line = String::new();
    for h in &run.scene.hands {
        match r.solution.hands.iter().find(|s| s.name == h.name) {
            Some(s) => {
                for v in s.translation_m.iter().chain(&s.rotation_rad) {
                    line.push_str(&format!(",{v}"));
                }
            }
            None => line.push_str(&",".repeat(HAND_COLUMNS.len())),
        }
    }
    for v in &run.scene.servos {
        match r.solution.servos.iter().find(|s| s.name == v.name) {
            Some(s) => line.push_str(&format!(",{},{}", s.force_n, s.travel_m)),
            None => line.push_str(&",".repeat(SERVO_COLUMNS.len())),
        }
    }
    line
}

/// Between two warnings of one step in the `warnings` column (no warning holds it).
pub const CSV_WARNING_SEPARATOR: &str = " | ";

/// Writes a CSV force history (RFC 4180: fields with a comma, quote or line break are quoted).
pub struct CsvSink {
    out: Option<BufWriter<File>>,
    path: PathBuf,
    /// How the `warnings` column names the options a user can change.
    respell: fn(&str) -> String,
}

impl CsvSink {
    /// Creates (or truncates) the file at `path` and writes to it.
    pub fn create(path: &Path) -> Result<Self, TransferError> {
        let f = File::create(path).map_err(|e| io_err("csv", path, e))?;
        Ok(Self::from_file(f, path))
    }

    /// Writes to an open file; `path` names it in error messages.
    pub fn from_file(file: File, path: &Path) -> Self {
        CsvSink {
            out: Some(BufWriter::new(file)),
            path: path.to_path_buf(),
            respell: str::to_string,
        }
    }

    /// Writes the warnings with the option names of the front end that runs (`respell`
    /// rewrites a library text, `grasp_model::option_names::respell`), as it prints them.
    pub fn respell_options(&mut self, respell: fn(&str) -> String) {
        self.respell = respell;
    }

    fn write(&mut self, text: &str) -> Result<(), TransferError> {
        let path = self.path.clone();
        let out = self
            .out
            .as_mut()
            .ok_or_else(|| io_err("csv", &path, "already finished"))?;
        out.write_all(text.as_bytes())
            .map_err(|e| io_err("csv", &path, e))
    }
}

impl Sink for CsvSink {
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        let mut h = String::from("time_s,step,status");
        for f in &run.scene.fingers {
            for col in ["normal_force_n", "friction_n", "slip_fraction"] {
                h.push(',');
                h.push_str(&csv_field(&format!("{}_{col}", f.name)));
            }
        }
        h.push_str(",solver,warm_start,iterations,factorizations,wall_time_s,smallest_margin_n");
        h.push_str(",compliance,inner_iterations,margin_held_to_n");
        for f in run.scene.fingers.iter().filter(|f| f.mount.is_some()) {
            for col in MOUNT_COLUMNS {
                h.push(',');
                h.push_str(&csv_field(&format!("{}_{col}", f.name)));
            }
        }
        h.push_str(&shared_spring_header(run));
        h.push_str(&sensor_header(run, |s| csv_field(s).into_owned()));
        h.push_str(",warnings\n");
        self.write(&h)
    }

    fn step(&mut self, run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let m = FingersMessage::from_record(r);
        let mut line = format!("{},{},{}", r.time_s, r.index, csv_field(&m.status));
        for f in &m.fingers {
            line.push_str(&format!(
                ",{},{},{}",
                f.normal_force_n, f.tangential_magnitude_n, f.slip_fraction
            ));
        }
        line.push_str(&format!(
            ",{},{},{},{},{},{},{},{},{}",
            csv_field(&m.solver),
            m.warm_start,
            m.iterations,
            m.factorizations,
            r.wall_time_s,
            margin_cell(r),
            csv_field(&m.compliance),
            m.inner_iterations,
            m.margin_held_to_n.map_or(String::new(), |v| v.to_string()),
        ));
        for f in run.scene.fingers.iter().filter(|f| f.mount.is_some()) {
            line.push_str(&mount_cells(r, &f.name));
        }
        line.push_str(&shared_spring_cells(run, r));
        line.push_str(&sensor_cells(run, r));
        let warnings: Vec<String> = r
            .solution
            .warnings
            .iter()
            .map(|w| (self.respell)(w))
            .collect();
        let warnings = warnings.join(CSV_WARNING_SEPARATOR);
        line.push_str(&format!(",{}\n", csv_field(&warnings)));
        self.write(&line)
    }

    fn finish(&mut self) -> Result<(), TransferError> {
        if let Some(o) = self.out.take() {
            let f = o
                .into_inner()
                .map_err(|e| io_err("csv", &self.path, e.error()))?;
            f.sync_all().map_err(|e| io_err("csv", &self.path, e))?;
        }
        Ok(())
    }

    fn abort(&mut self) {
        self.out.take();
    }
}

/// One CSV field as RFC 4180 writes it: quoted (inner quotes doubled) when it holds a comma, a
/// quote or a line break.
fn csv_field(s: &str) -> std::borrow::Cow<'_, str> {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\"")).into()
    } else {
        s.into()
    }
}
