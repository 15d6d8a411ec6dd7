//! Rerun sink: a saved `.rrd` recording to replay a hand-off in the Rerun viewer.
//!
//! Entities (world frame, metres):
//! - `world/object` (static): a wireframe box around the contacts and the centre of mass;
//! - `world/fingers/<name>` (static): each finger as an arrow pointing at its contact, and
//!   `world/fingers/<name>/tip` its tip's shape ([`super::fingertip_drawing`]);
//! - `world/forces/<name>/normal`, `.../friction`: force arrows on the object at the centre
//!   of pressure, scaled by `arrow_m_per_n`;
//! - `world/patches/<name>/pressure`: elements coloured by pressure (dark blue to yellow,
//!   relative to the step's largest pressure);
//! - `world/patches/<name>/state`: elements coloured by state (the colour key of
//!   [`super::colour_key`]);
//!
//!   both one point an element for patches of up to
//!   [`COMPACT_ABOVE_ELEMENTS`](super::element_maps::COMPACT_ABOVE_ELEMENTS) elements, and
//!   images on the patch's plane (`GridMap`s, with a static `Transform3D` at
//!   `world/patches/<name>`) for larger ones ([`super::rerun_grid_maps`]);
//! - `plots/normal_force/<name>`, `plots/friction/<name>`: time series in newtons (fingers
//!   whose curves coincide, a symmetric pair, say so in their legend names);
//! - `plots/margin/smallest`: the step's smallest disturbance margin, N (with `--margins`);
//! - `world/fingers/<name>/core`, `plots/core/<name>`: a mounted finger's core moved on its
//!   spring, an arrow at true scale and its length in mm; `world/hands/<name>` and the same
//!   plot for hands and servos ([`super::shared_spring_drawing`]);
//! - `plots/viscous_displacement/<name>`: on a viscoelastic contact, the largest normal
//!   displacement its history added at the step, m (the creep or relaxation under way);
//! - `world/tactile/<name>/taxels`, `.../markers`: a sensor finger's readings
//!   ([`super::tactile_drawing`]); `tactile/<name>/gel`, `.../gel_height`: its gel image
//!   ([`super::gel_drawing`]);
//! - `world/margin/...` (static, `grasp margin --rrd`): the wrench surface
//!   ([`RerunSink::log_wrench_surface`]).
//!
//! The recording opens on a fixed layout (3-D view beside the force plots, see
//! `rerun_layout`).
//!
//! Timelines: `schedule_time` (s) and `step`. Rows are gathered per entity and sent as
//! pre-built chunks every [`FLUSH_EVERY_STEPS`] steps (so memory does not grow with the number
//! of steps) and at the end.
//!
//! The same inputs give the same file, byte for byte, up to its footer: chunk and row ids
//! count up from a fixed origin (Rerun's default ids mix wall time and randomness), log time is
//! off, the recording id is fixed and no start time is sent, and the stream's announcement
//! (`SetStoreInfo`) carries a fixed id instead of the SDK's random one ([`FixedIdFile`]). The
//! footer Rerun 0.36 appends (an index of the chunks, one manifest per store, which `rerun rrd
//! verify` requires) is built from hash maps inside Rerun: it lists the recording's and the
//! layout's manifests, and each manifest's schema fields, in an order that changes from run to
//! run, so its bytes (and by a few bytes its length) differ while its content does not. A live
//! stream (`connect`, `spawn`) is not a file and has no footer.

use std::collections::BTreeMap;
use std::path::Path;

use grasp_model::{FingerModel, FingerSolution};
use rerun::external::re_tuid::Tuid;
use rerun::log::{Chunk, ChunkBatcherConfig, ChunkId, LogMsg, RowId};
use rerun::sink::{FileSink, LogSink, SinkFlushError};
use rerun::{
    Arrows3D, AsComponents, Boxes3D, Color, Cylinders3D, Ellipsoids3D, FillMode, Mesh3D, Points3D,
    RecordingStream, Scalars, SerializedComponentBatch, SeriesLines, TimeCell, TimePoint,
};

use super::colour_key::{state_rgb, FRICTION_FORCE_RGB, NORMAL_FORCE_RGB};
use super::drawing_scale::{contact_bounds, drawing_scale};
use super::element_maps::is_compact;
use super::fingertip_drawing::{tip_drawings, z_to, TipDrawing};
use super::gel_drawing::gel_drawings;
use super::identical_curves::IdenticalCurves;
use super::patch_views::{has_flat_views, pressure_tensor, state_image, state_key};
use super::rerun_grid_maps::{cleared_map, patch_pose, pressure_map, state_map};
use super::rerun_layout::{layout_messages, LayoutContent, APPLICATION_ID};
use super::shared_spring_drawing::{has_shared_springs, shared_spring_drawings};
use super::sink::{io_err, RunInfo, Sink};
use super::tactile_drawing::tactile_drawings;
use super::viewer_address::reachable;
use crate::error::TransferError;
use crate::stepper::StepRecord;

/// Writes a Rerun recording.
pub struct RerunSink {
    rec: Option<RecordingStream>,
    path: std::path::PathBuf,
    arrow_m_per_n: f32,
    /// Counter of the deterministic chunk and row ids.
    ids: u64,
    /// Time point of the current step (empty: static).
    time: TimePoint,
    /// Rows accumulated per entity since the last flush: one chunk per entity, sent in path
    /// order.
    pending: BTreeMap<(String, bool), PendingChunk>,
    /// Steps logged since the last flush.
    steps_since_flush: usize,
    /// Steps between two sends: [`FLUSH_EVERY_STEPS`] to a file, 1 live.
    flush_every: usize,
    /// A live stream (viewer or server): the closing flush waits at most [`LIVE_FLUSH_TIMEOUT`].
    live: bool,
    /// The default layout has been sent (at `begin`).
    layout_sent: bool,
    /// The recording's name in the viewer (the scene's), when given.
    recording_name: Option<String>,
    /// Steps will be logged (a hand-off): the layout has the patches' flat views. False for a
    /// static recording ([`RerunSink::without_steps`]).
    steps: bool,
    /// The fingers whose force curves coincide so far (set at `begin`).
    same: Option<IdenticalCurves>,
}

/// Longest wait for a live viewer or server to take the last rows when a run ends.
pub const LIVE_FLUSH_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(10);

/// Steps whose rows are gathered before they are sent as chunks.
pub const FLUSH_EVERY_STEPS: usize = 128;

/// Rows of one entity waiting to be sent as one chunk.
struct PendingChunk {
    id: ChunkId,
    rows: Vec<(RowId, TimePoint, Vec<SerializedComponentBatch>)>,
}

/// Origin of the deterministic ids (2024-01-01T00:00:00Z in ns); only their order matters.
const ID_ORIGIN_NS: u64 = 1_704_067_200_000_000_000;

fn v3(v: &nalgebra::Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// A force in N for a label: four significant digits in fixed notation (`3.342`, `1234`,
/// `0.01250`), without the sign of a value that rounds to zero.
fn newtons(v: f64) -> String {
    let decimals = match v.abs() {
        a if a >= 1000.0 => 0,
        a if a > 0.0 => (3 - a.log10().floor() as i64).clamp(0, 9) as usize,
        _ => 3,
    };
    let s = format!("{v:.decimals$}");
    match s
        .trim_start_matches('-')
        .trim_matches(|c| c == '0' || c == '.')
    {
        "" => s.trim_start_matches('-').to_owned(),
        _ => s,
    }
}

/// A direction's margin for a label: `1.234 N`, `unbounded (held to 3851 N)` or
/// `undetermined (held to 415.0 N)`: an unbounded or undetermined margin is no number.
fn margin_text(d: &grasp_model::DirectionMargin) -> String {
    match d.margin_n {
        Some(m) => format!("{} N", newtons(m)),
        None if d.is_unbounded() => format!("unbounded (held to {} N)", newtons(d.held_to_n)),
        None => format!("undetermined (held to {} N)", newtons(d.held_to_n)),
    }
}

/// A colour of the key as Rerun's.
fn rgb_colour([r, g, b]: [u8; 3]) -> Color {
    Color::from_rgb(r, g, b)
}

/// A perceptually ordered colour ramp (dark blue, teal, yellow) for `u in [0, 1]`.
fn ramp(u: f64) -> Color {
    let u = u.clamp(0.0, 1.0);
    let stops = [
        (40.0, 30.0, 100.0),
        (30.0, 150.0, 140.0),
        (250.0, 230.0, 40.0),
    ];
    let (a, b, s) = if u < 0.5 {
        (stops[0], stops[1], u * 2.0)
    } else {
        (stops[1], stops[2], u * 2.0 - 1.0)
    };
    let mix = |x: f64, y: f64| (x + (y - x) * s).round() as u8;
    Color::from_rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl RerunSink {
    /// Creates (or truncates) the recording file at `path` and writes to it.
    pub fn create(path: &Path) -> Result<Self, TransferError> {
        Self::create_as(path, path)
    }

    /// Creates (or truncates) the recording file at `path`; `name` names it in error messages
    /// (the file the user asked for, when `path` is its temporary file).
    pub fn create_as(path: &Path, name: &Path) -> Result<Self, TransferError> {
        let file = FileSink::new(path).map_err(|e| io_err("rerun", name, e))?;
        let sinks: Vec<Box<dyn LogSink>> = vec![Box::new(FixedIdFile(file))];
        let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
            .recording_id("grasp-transfer")
            .set_sinks(sinks)
            .map_err(|e| io_err("rerun", name, e))?;
        Ok(Self::on_stream(rec, name, FLUSH_EVERY_STEPS, false))
    }

    /// Streams every step, as it is computed, to the Rerun viewer or server at `url` (a gRPC
    /// proxy address such as `rerun+http://127.0.0.1:9876/proxy`).
    pub fn connect(url: &str) -> Result<Self, TransferError> {
        let name = Path::new(url);
        // Without a listener the stream would wait for one at the end of the run: ask first.
        reachable(url).map_err(|e| io_err("rerun", name, e))?;
        let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
            .recording_id("grasp-transfer")
            .connect_grpc_opts(url)
            .map_err(|e| {
                io_err(
                    "rerun",
                    name,
                    format!("{e} (give a proxy address such as rerun+http://127.0.0.1:9876/proxy)"),
                )
            })?;
        Ok(Self::on_stream(rec, name, 1, true))
    }

    /// Starts a Rerun viewer (the `rerun` program on the PATH) and streams every step to it.
    pub fn spawn() -> Result<Self, TransferError> {
        let name = Path::new("rerun viewer");
        let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
            .recording_id("grasp-transfer")
            .spawn()
            .map_err(|e| {
                io_err(
                    "rerun",
                    name,
                    format!("{e} (install the viewer: pip install rerun-sdk==0.36.3)"),
                )
            })?;
        Ok(Self::on_stream(rec, name, 1, true))
    }

    /// A sink on `rec`, sending its rows every `flush_every` steps.
    fn on_stream(rec: RecordingStream, name: &Path, flush_every: usize, live: bool) -> Self {
        rec.set_log_time_enabled(false);
        RerunSink {
            rec: Some(rec),
            path: name.to_path_buf(),
            arrow_m_per_n: 1.0,
            ids: 0,
            time: TimePoint::default(),
            pending: BTreeMap::new(),
            steps_since_flush: 0,
            flush_every,
            live,
            layout_sent: false,
            recording_name: None,
            steps: true,
            same: None,
        }
    }

    /// Sends the gathered rows as one chunk per entity, in path order.
    fn send_pending(&mut self) -> Result<(), TransferError> {
        let Some(rec) = &self.rec else {
            return Err(io_err("rerun", &self.path, "already finished"));
        };
        for ((path, _), p) in std::mem::take(&mut self.pending) {
            let mut b = Chunk::builder_with_id(p.id, path.as_str());
            for (row, time, batches) in p.rows {
                b = b.with_serialized_batches(row, time, batches);
            }
            rec.send_chunk(b.build().map_err(|e| io_err("rerun", &self.path, e))?);
        }
        self.steps_since_flush = 0;
        Ok(())
    }

    /// Symmetric fingers' curves lie on each other: their plot legends say so, as the SVG's
    /// note does ("f1 normal force [N] (f1 = f2: identical curves)"), static, replacing the
    /// names logged at `begin`.
    fn note_identical_curves(&mut self) -> Result<(), TransferError> {
        let Some(same) = self.same.take() else {
            return Ok(());
        };
        self.time = TimePoint::default();
        for group in same.groups() {
            let note = format!("{}: identical curves", group.join(" = "));
            for name in &group {
                for (plot, what) in [("normal_force", "normal"), ("friction", "friction")] {
                    self.send(
                        format!("plots/{plot}/{name}"),
                        &SeriesLines::new()
                            .with_names([format!("{name} {what} force [N] ({note})")]),
                    )?;
                }
            }
        }
        Ok(())
    }

    /// A recording of no steps (`grasp margin`'s wrench surface): no patch and no plot has
    /// anything to show, so the layout is the 3-D view alone, without patch views, key or
    /// force plots (call before `begin`).
    pub fn without_steps(&mut self) {
        self.steps = false;
    }

    /// Names the recording (the viewer lists it by this name; the scene's file, say).
    pub fn set_recording_name(&mut self, name: &str) {
        self.recording_name = Some(name.to_string());
    }

    /// Sends the default layout ([`layout_messages`]) once, with a view for each part of
    /// `content`.
    fn send_layout(&mut self, content: LayoutContent) -> Result<(), TransferError> {
        let Some(rec) = &self.rec else {
            return Err(io_err("rerun", &self.path, "already finished"));
        };
        if !self.layout_sent {
            let (msgs, activation) =
                layout_messages(content).map_err(|e| io_err("rerun", &self.path, e))?;
            rec.send_blueprint(msgs, activation);
            self.layout_sent = true;
        }
        Ok(())
    }

    fn next_id(&mut self) -> Tuid {
        self.ids += 1;
        Tuid::from_nanos_and_inc(ID_ORIGIN_NS, self.ids)
    }

    /// Adds one row at the current time point (static before the first step) to the entity's
    /// chunk.
    fn send(
        &mut self,
        path: impl Into<String>,
        arch: &dyn AsComponents,
    ) -> Result<(), TransferError> {
        // Static and temporal rows of an entity go to separate chunks.
        let key = (path.into(), self.time.is_static());
        if !self.pending.contains_key(&key) {
            let id = ChunkId::from_tuid(self.next_id());
            let rows = Vec::new();
            self.pending.insert(key.clone(), PendingChunk { id, rows });
        }
        let row_id = RowId::from_tuid(self.next_id());
        let time = self.time.clone();
        // Inserted just above if it was missing.
        if let Some(p) = self.pending.get_mut(&key) {
            p.rows.push((row_id, time, arch.as_serialized_batches()));
        }
        Ok(())
    }
}

/// A recording file whose announcement (`SetStoreInfo`) carries a fixed id: the SDK draws a
/// random, time-based one, the only id of the file it chooses itself (see the module
/// documentation). Everything else passes through to the file sink unchanged.
struct FixedIdFile(FileSink);

impl LogSink for FixedIdFile {
    fn send(&self, msg: LogMsg) {
        let msg = match msg {
            LogMsg::SetStoreInfo(mut announce)
                if announce.info.store_id.kind() == rerun::StoreKind::Recording =>
            {
                // Before every chunk and row id of the recording (those count up from 1).
                announce.row_id = Tuid::from_nanos_and_inc(ID_ORIGIN_NS, 0);
                LogMsg::SetStoreInfo(announce)
            }
            other => other,
        };
        LogSink::send(&self.0, msg);
    }

    fn flush_blocking(&self, timeout: std::time::Duration) -> Result<(), SinkFlushError> {
        LogSink::flush_blocking(&self.0, timeout)
    }

    fn default_batcher_config(&self) -> ChunkBatcherConfig {
        self.0.default_batcher_config()
    }

    fn defers_finalization_to_shutdown(&self) -> bool {
        self.0.defers_finalization_to_shutdown()
    }
}

impl RerunSink {
    /// Logs a margin report as static entities around the object (call after `begin`):
    /// `world/margin/force` (the wrench surface's force part: from the centre of mass, each
    /// direction's force part times its margin, at the force-arrow scale) and
    /// `world/margin/torque` (the couple part, at the same scale per N m / L), the smallest
    /// margin in red, unbounded ones (drawn at the cap) pale; `world/margin/smallest` labels
    /// it.
    pub fn log_wrench_surface(
        &mut self,
        run: &RunInfo,
        report: &grasp_model::MarginReport,
    ) -> Result<(), TransferError> {
        let com = run.model.center_of_mass_m();
        let k = self.arrow_m_per_n as f64;
        let colour = |i: usize, bounded: bool| match (i == report.smallest, bounded) {
            (true, _) => Color::from_rgb(214, 39, 40),
            (false, true) => Color::from_rgb(31, 119, 180),
            (false, false) => Color::from_rgb(174, 199, 232),
        };
        for (part, pick) in [("force", 0usize), ("torque", 1)] {
            let mut vectors = Vec::new();
            let mut colours = Vec::new();
            for (i, d) in report.directions.iter().enumerate() {
                let v = if pick == 0 {
                    d.direction.force
                } else {
                    d.direction.torque
                };
                let v = nalgebra::Vector3::from(v) * (d.held_to_n * k);
                if v.norm() > 0.0 {
                    vectors.push(v3(&v));
                    colours.push(colour(i, d.bounded));
                }
            }
            let origins = vec![v3(&com); vectors.len()];
            self.send(
                format!("world/margin/{part}"),
                &Arrows3D::from_vectors(vectors)
                    .with_origins(origins)
                    .with_colors(colours),
            )?;
        }
        if let Some(d) = report.directions.get(report.smallest) {
            let v = nalgebra::Vector3::from(d.direction.force)
                + nalgebra::Vector3::from(d.direction.torque);
            let tip = com + v * (d.held_to_n * k);
            let who = d.failing_finger.as_deref().unwrap_or("-");
            self.send(
                "world/margin/smallest",
                &Points3D::new([v3(&tip)])
                    .with_colors([colour(report.smallest, d.bounded)])
                    .with_labels([format!("smallest margin {} (first: {who})", margin_text(d))]),
            )?;
        }
        Ok(())
    }
}

impl RerunSink {
    /// Logs finger `fm`'s step: its force arrows (`scale` m/N), its patch (pressures relative
    /// to `p_max`) and its plot points.
    fn log_finger(
        &mut self,
        fm: &FingerModel,
        f: &FingerSolution,
        scale: f64,
        p_max: f64,
    ) -> Result<(), TransferError> {
        let name = &fm.name();
        self.log_forces(fm, f, scale)?;
        self.log_patch(fm, f, p_max)?;
        if has_flat_views(fm) {
            let name = fm.name();
            let pressure = pressure_tensor(fm, f, p_max);
            self.send(format!("patches/{name}/pressure"), &pressure)?;
            self.send(format!("patches/{name}/state"), &state_image(fm, f))?;
        }
        self.send(
            format!("plots/normal_force/{name}"),
            &Scalars::new([f.normal_force_n]),
        )?;
        self.send(
            format!("plots/friction/{name}"),
            &Scalars::new([f.tangential_magnitude_n]),
        )?;
        if let Some(core) = &f.mount_displacement {
            // The core's move at true scale in the 3-D view, its length in mm plotted.
            let arrow = Arrows3D::from_vectors([core.translation_m.map(|x| x as f32)])
                .with_origins([v3(&fm.frame().origin_m)]);
            self.send(format!("world/fingers/{name}/core"), &arrow)?;
            let moved_mm = core.moved_m() * 1e3;
            self.send(format!("plots/core/{name}"), &Scalars::new([moved_mm]))?;
        }
        // A viscoelastic contact: the largest normal displacement its history added, m.
        let history = f
            .elements
            .iter()
            .filter_map(|e| e.viscous_displacement_m.map(|h| h[0]))
            .fold(None, |m: Option<f64>, h| Some(m.map_or(h, |m| m.max(h))));
        match history {
            Some(h) => self.send(
                format!("plots/viscous_displacement/{name}"),
                &Scalars::new([h]),
            ),
            None => Ok(()),
        }
    }

    /// The normal and friction force arrows of finger `fm`, at the centre of pressure, `scale`
    /// m/N.
    fn log_forces(
        &mut self,
        fm: &FingerModel,
        f: &FingerSolution,
        scale: f64,
    ) -> Result<(), TransferError> {
        let name = &fm.name();
        let cop = nalgebra::Vector3::from(f.center_of_pressure_m);
        let pn = fm.frame().normal * (f.normal_force_n * scale);
        self.send(
            format!("world/forces/{name}/normal"),
            &Arrows3D::from_vectors([v3(&pn)])
                .with_origins([v3(&(cop - pn))])
                .with_colors([rgb_colour(NORMAL_FORCE_RGB)]),
        )?;
        let q = nalgebra::Vector3::from(f.tangential_force_n) * scale;
        self.send(
            format!("world/forces/{name}/friction"),
            &Arrows3D::from_vectors([v3(&q)])
                .with_origins([v3(&cop)])
                .with_colors([rgb_colour(FRICTION_FORCE_RGB)]),
        )
    }

    /// Finger `fm`'s elements coloured by pressure (relative to `p_max`) and, set off behind
    /// the patch, by state: points, or images for a large patch.
    fn log_patch(
        &mut self,
        fm: &FingerModel,
        f: &FingerSolution,
        p_max: f64,
    ) -> Result<(), TransferError> {
        let name = &fm.name();
        if is_compact(f.elements.len()) {
            self.send(
                format!("world/patches/{name}/pressure"),
                &pressure_map(fm, f, p_max),
            )?;
            return self.send(format!("world/patches/{name}/state"), &state_map(fm, f));
        }
        let h = 0.5 * fm.patch().grid.hx.min(fm.patch().grid.hy);
        let pos: Vec<[f32; 3]> = f
            .elements
            .iter()
            .map(|e| e.position_m.map(|x| x as f32))
            .collect();
        self.send(
            format!("world/patches/{name}/pressure"),
            &Points3D::new(pos.clone())
                .with_colors(f.elements.iter().map(|e| ramp(e.pressure_pa / p_max)))
                .with_radii(std::iter::repeat_n(0.9 * h as f32, pos.len())),
        )?;
        let off = fm.frame().normal * (-2.0 * h);
        let pos_state: Vec<[f32; 3]> = f
            .elements
            .iter()
            .map(|e| v3(&(nalgebra::Vector3::from(e.position_m) + off)))
            .collect();
        self.send(
            format!("world/patches/{name}/state"),
            &Points3D::new(pos_state)
                .with_colors(f.elements.iter().map(|e| rgb_colour(state_rgb(e.state))))
                .with_radii(std::iter::repeat_n(0.6 * h as f32, f.elements.len())),
        )
    }

    /// Clears the arrows and patch of a finger without a solution (released, or a failed
    /// step) and plots zero.
    fn clear_finger(&mut self, fm: &FingerModel) -> Result<(), TransferError> {
        let name = &fm.name();
        let none: [[f32; 3]; 0] = [];
        for part in ["normal", "friction"] {
            self.send(
                format!("world/forces/{name}/{part}"),
                &Arrows3D::from_vectors(none),
            )?;
        }
        for part in ["pressure", "state"] {
            let path = format!("world/patches/{name}/{part}");
            match is_compact(fm.patch().len()) {
                true => self.send(path, &cleared_map())?,
                false => self.send(path, &Points3D::new(none))?,
            }
        }
        if has_flat_views(fm) {
            for part in ["pressure", "state"] {
                self.send(format!("patches/{name}/{part}"), &rerun::Clear::flat())?;
            }
        }
        if fm.mount().is_some() {
            // Released: no push, the core at its commanded pose.
            self.send(
                format!("world/fingers/{name}/core"),
                &Arrows3D::clear_fields(),
            )?;
            self.send(format!("plots/core/{name}"), &Scalars::new([0.0]))?;
        }
        self.send(format!("plots/normal_force/{name}"), &Scalars::new([0.0]))?;
        self.send(format!("plots/friction/{name}"), &Scalars::new([0.0]))
    }
}

impl Sink for RerunSink {
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        let g = run.model;
        let flat: Vec<String> = g
            .fingers()
            .iter()
            .filter(|f| self.steps && has_flat_views(f))
            .map(|f| f.name().to_string())
            .collect();
        self.send_layout(LayoutContent {
            steps: self.steps,
            margins: run.margins,
            mounts: g.fingers().iter().any(|f| f.mount().is_some()) || has_shared_springs(run),
            flat: &flat,
            gels: &run.gel_fingers(),
        })?;
        let names: Vec<String> = g.fingers().iter().map(|f| f.name().to_string()).collect();
        self.same = Some(IdenticalCurves::new(&names));
        if let Some(name) = self.recording_name.clone() {
            let info = rerun::RecordingInfo::update_fields().with_name(name);
            self.send("__properties", &info)?;
        }
        if !flat.is_empty() {
            self.send("patches/key", &state_key())?;
        }
        let (lo, hi) = contact_bounds(g);
        let (size, m_per_n) = drawing_scale(g);
        self.arrow_m_per_n = m_per_n as f32;
        match g.object_surface() {
            // The object as its shape (posed), half transparent so the patches show.
            Some(surface) => self.send("world/object", &object_mesh(surface))?,
            // Without a shape: the box around the contacts and the centre of mass.
            None => {
                let centre = (lo + hi) * 0.5;
                let half = ((hi - lo) * 0.5).map(|x| x.max(0.02 * size));
                self.send(
                    "world/object",
                    &Boxes3D::from_centers_and_half_sizes([v3(&centre)], [v3(&half)]),
                )?;
            }
        }
        self.send(
            "world/object/center_of_mass",
            &Points3D::new([v3(&g.center_of_mass_m())])
                .with_radii([0.01 * size as f32])
                .with_labels(["centre of mass"]),
        )?;
        for (name, tip) in tip_drawings(run, size) {
            self.send(
                format!("world/fingers/{name}/tip"),
                tip_archetype(&tip).as_ref(),
            )?;
        }
        for f in g.fingers().iter().filter(|f| is_compact(f.patch().len())) {
            self.send(format!("world/patches/{}", f.name()), &patch_pose(f))?;
        }
        for f in g.fingers() {
            let len = 0.25 * size;
            let base = f.frame().origin_m - f.frame().normal * len;
            self.send(
                format!("world/fingers/{}", f.name()),
                &Arrows3D::from_vectors([v3(&(f.frame().normal * (0.9 * len)))])
                    .with_origins([v3(&base)])
                    .with_colors([Color::from_rgb(150, 150, 160)])
                    .with_labels([f.name()]),
            )?;
            if !self.steps {
                continue;
            }
            self.send(
                format!("plots/normal_force/{}", f.name()),
                &SeriesLines::new().with_names([format!("{} normal force [N]", f.name())]),
            )?;
            self.send(
                format!("plots/friction/{}", f.name()),
                &SeriesLines::new().with_names([format!("{} friction force [N]", f.name())]),
            )?;
        }
        Ok(())
    }

    fn step(&mut self, run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let scale = self.arrow_m_per_n as f64;
        self.time = [
            (
                super::rerun_layout::TIMELINE,
                TimeCell::from_duration_nanos((r.time_s * 1e9).round() as i64),
            ),
            ("step", TimeCell::from_sequence(r.index as i64)),
        ]
        .into_iter()
        .collect();
        let p_max = r
            .solution
            .fingers
            .iter()
            .map(|f| f.peak_pressure_pa)
            .fold(0.0_f64, f64::max)
            .max(f64::MIN_POSITIVE);
        for fm in run.model.fingers() {
            match r.solution.finger(fm.name()) {
                Some(f) => self.log_finger(fm, f, scale, p_max)?,
                // Released (or failed step): clear its arrows and patch, plot zero.
                None => self.clear_finger(fm)?,
            }
        }
        let tactile = tactile_drawings(run, r, scale).into_iter();
        let springs = shared_spring_drawings(run, r).into_iter();
        for (path, drawing) in tactile.chain(gel_drawings(run, r)).chain(springs) {
            self.send(path, drawing.as_ref())?;
        }
        // An unbounded or undetermined margin is no number: the plot shows a gap there.
        if let Some(n) = r.margin.as_ref().and_then(|m| m.smallest_n) {
            self.send("plots/margin/smallest", &Scalars::new([n]))?;
        }
        if let Some(same) = self
            .same
            .as_mut()
            .filter(|_| r.solution.status.has_forces())
        {
            same.push_solution(&r.solution);
        }
        self.steps_since_flush += 1;
        if self.steps_since_flush >= self.flush_every {
            self.send_pending()?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), TransferError> {
        if self.rec.is_some() {
            self.note_identical_curves()?;
            self.send_pending()?;
        }
        if let Some(rec) = self.rec.take() {
            let flushed = match self.live {
                true => rec.flush_with_timeout(LIVE_FLUSH_TIMEOUT),
                false => rec.flush_blocking(),
            };
            flushed.map_err(|e| io_err("rerun", &self.path, e))?;
        }
        Ok(())
    }

    fn abort(&mut self) {
        self.pending.clear();
        if let Some(rec) = self.rec.take() {
            let _ = rec.flush_with_timeout(LIVE_FLUSH_TIMEOUT);
        }
    }
}

/// A fingertip as a solid, half transparent grey shape.
fn tip_archetype(tip: &TipDrawing) -> Box<dyn AsComponents> {
    let grey = Color::from_unmultiplied_rgba(140, 140, 150, 128);
    let quat = |q: &nalgebra::UnitQuaternion<f64>| {
        rerun::Quaternion::from_xyzw([q.i as f32, q.j as f32, q.k as f32, q.w as f32])
    };
    match tip {
        TipDrawing::Sphere { centre, radius_m } => Box::new(
            Ellipsoids3D::from_centers_and_radii([v3(centre)], [*radius_m as f32])
                .with_colors([grey])
                .with_fill_mode(FillMode::Solid),
        ),
        TipDrawing::Cylinder {
            centre,
            axis,
            radius_m,
            length_m,
        } => Box::new(
            Cylinders3D::from_lengths_and_radii([*length_m as f32], [*radius_m as f32])
                .with_centers([v3(centre)])
                .with_quaternions([quat(&z_to(axis))])
                .with_colors([grey])
                .with_fill_mode(FillMode::Solid),
        ),
        TipDrawing::Pad {
            centre,
            rotation,
            half_sizes_m,
        } => Box::new(
            Boxes3D::from_centers_and_half_sizes([v3(centre)], [v3(half_sizes_m)])
                .with_quaternions([quat(rotation)])
                .with_colors([grey])
                .with_fill_mode(FillMode::Solid),
        ),
    }
}

/// The object's surface as a Rerun mesh (light grey, half transparent).
fn object_mesh(surface: &grasp_model::TriangleMesh) -> Mesh3D {
    let f = |v: &[f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32];
    Mesh3D::new(surface.vertices_m.iter().map(f))
        .with_triangle_indices(surface.triangles.iter().copied())
        .with_albedo_factor(rerun::datatypes::Rgba32::from_unmultiplied_rgba(
            200, 200, 210, 110,
        ))
}

#[cfg(test)]
mod tests {
    use super::newtons;

    #[test]
    fn a_label_force_reads_in_fixed_notation_with_four_digits() {
        assert_eq!(newtons(3.342_24), "3.342");
        assert_eq!(newtons(0.012_5), "0.01250");
        assert_eq!(newtons(123.44), "123.4");
        assert_eq!(newtons(4448.2), "4448");
        assert_eq!(newtons(0.0), "0.000");
        assert_eq!(newtons(-1e-15), "0.000000000");
    }
}
