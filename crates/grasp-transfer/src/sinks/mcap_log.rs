//! MCAP sink: JSON-encoded messages with JSON Schemas, so Foxglove can plot them.
//!
//! Channels:
//! - `/grasp/fingers` (`grasp.FingerResultants`): per step, every finger's command and
//!   resultants;
//! - `/grasp/patches` (`grasp.PatchFields`): per step, every active patch's element fields,
//!   one JSON object an element (patches of up to
//!   [`COMPACT_ABOVE_ELEMENTS`](super::element_maps::COMPACT_ABOVE_ELEMENTS) elements);
//! - `/grasp/patch_maps` (`grasp.PatchMaps`, only when the scene has a larger patch): per step,
//!   every active larger patch's element fields as compact base64 arrays
//!   ([`super::patch_maps_message`]);
//! - `/grasp/tactile` (`grasp.TactileReadings`, only when the scene has a finger with a
//!   `sensor`): per step, every active sensor's readings ([`super::tactile_message`]);
//! - `/grasp/tactile/<finger>/gel`, `.../gel_height` (`foxglove.RawImage`, per finger whose
//!   sensor has a gel image): its shaded image and height map ([`super::gel_image_message`]);
//! - `/grasp/scene` (`foxglove.SceneUpdate`): the object and contact points once, then per
//!   step the finger forces as arrows, for Foxglove's 3-D panel ([`super::foxglove_scene`]).
//!
//! The run's warnings, each once with the steps that gave it, are metadata records named
//! [`WARNING_METADATA`] (none when the run gave no warning).
//!
//! Log and publish time are the schedule time in nanoseconds. Nothing nondeterministic (wall
//! times) is written, so the same inputs give the same file. Chunks are compressed with zstd
//! (the `mcap` crate's default).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde_json::json;

use super::drawing_scale::drawing_scale;
use super::element_maps::is_compact;
use super::foxglove_scene::{forces_update, object_update, scene_update_schema, SCENE_TOPIC};
use super::gel_image_message::{gel_messages, gel_topics, raw_image_schema, RAW_IMAGE_SCHEMA};
use super::patch_maps_message::{
    has_compact_patch, patch_maps_message, patch_maps_schema, PATCH_MAPS_SCHEMA, PATCH_MAPS_TOPIC,
};
use super::sink::{io_err, io_err_chain, RunInfo, Sink};
use super::tactile_message::{
    has_sensor, tactile_message, tactile_schema, TACTILE_SCHEMA, TACTILE_TOPIC,
};
use crate::error::TransferError;
use crate::schedule::Command;
use crate::stepper::StepRecord;
use grasp_model::{SolveAt, TalliedWarning, WarningTally};

/// Topic of per-finger resultants.
pub const FINGERS_TOPIC: &str = "/grasp/fingers";
/// Topic of per-element patch fields.
pub const PATCHES_TOPIC: &str = "/grasp/patches";

/// One finger in a `/grasp/fingers` message.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(test, derive(schemars::JsonSchema))]
pub struct FingerMessage {
    /// Finger name.
    pub name: String,
    /// `held`, `load`, `approach` or `released`.
    pub control: String,
    /// Commanded load, N (0 unless `load`).
    pub commanded_load_n: f64,
    /// Commanded approach, m (0 unless `approach`).
    #[serde(default)]
    pub commanded_approach_m: f64,
    /// Normal force, N.
    pub normal_force_n: f64,
    /// Friction force, world frame, N.
    pub tangential_force_n: [f64; 3],
    /// `|Q|`, N.
    pub tangential_magnitude_n: f64,
    /// Torsional moment about the normal, N m.
    pub torsional_moment_nm: f64,
    /// `|Q|/(mu P)`.
    pub friction_utilization: f64,
    /// Fraction of the contact elements that slip.
    pub slip_fraction: f64,
    /// A finger on a mount (`fingers[i].mount`): its rigid core's displacement from the
    /// commanded pose, world frame, m (absent for a rigid core and while released).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub core_displacement_m: Option<[f64; 3]>,
}

/// A `/grasp/fingers` message.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(test, derive(schemars::JsonSchema))]
pub struct FingersMessage {
    /// Schedule time, s.
    pub time_s: f64,
    /// Step index.
    pub step: usize,
    /// Solve status.
    pub status: String,
    /// Why, if not solved.
    pub reason: Option<String>,
    /// Which solver answered the step (`native` or `clarabel`).
    pub solver: String,
    /// Why the native solver's answer was not used, when it was not.
    pub fallback: Option<String>,
    /// True when the step started from the previous step's solution (same grasp structure).
    pub warm_start: bool,
    /// Iterations of the step: Newton steps of the native solver plus interior-point
    /// iterations of Clarabel, over all its convex solves.
    pub iterations: u32,
    /// Reduced matrices factorised by the native solver in the step.
    pub factorizations: u32,
    /// The form of the patch compliances: `dense`, `fft` or `mixed` (docs/guide/solving.md, "Fine patches").
    pub compliance: String,
    /// Conjugate-gradient iterations of the FFT path in the step (0 on the dense path).
    pub inner_iterations: u32,
    /// Relative equilibrium residual (absent without forces).
    pub equilibrium_residual: Option<f64>,
    /// Scheduled external force at the centre of mass, N.
    pub external_force_n: [f64; 3],
    /// Scheduled external couple, N m.
    pub external_torque_nm: [f64; 3],
    /// Smallest disturbance margin of the step, N (absent unless margins were asked for and
    /// the step solved, and absent when unbounded or undetermined: `margin_held_to_n` and
    /// `margin_undetermined` say which).
    pub smallest_margin_n: Option<f64>,
    /// The largest push known to hold along the smallest margin's direction, N: the margin,
    /// the search's cap when unbounded, a lower bound when undetermined.
    pub margin_held_to_n: Option<f64>,
    /// Why the smallest margin is not known above `margin_held_to_n`, when it is not.
    pub margin_undetermined: Option<String>,
    /// The finger that fails first along the smallest margin's direction.
    pub margin_failing_finger: Option<String>,
    /// A second coulomb equilibrium at a margin's failing end, in words, when the step's
    /// search found one ([`crate::StepMargin::other_equilibrium`]).
    pub margin_other_equilibrium: Option<String>,
    /// Every scene finger, scene order.
    pub fingers: Vec<FingerMessage>,
    /// Each hand the step's grasp holds (`hands`; absent without): its load and its base's
    /// motion.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hands: Vec<HandMessage>,
    /// Each servo the step's grasp holds (`servos`; absent without): its load and its jaws'
    /// travel.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub servos: Vec<ServoMessage>,
}

/// A hand in a `/grasp/fingers` message (`grasp_model::HandSolution`).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(test, derive(schemars::JsonSchema))]
pub struct HandMessage {
    /// Its name in the scene.
    pub name: String,
    /// The force its fingers put on the object, N (world frame).
    pub force_n: [f64; 3],
    /// Their moment about the hand's origin, N m (world frame).
    pub moment_nm: [f64; 3],
    /// The base's translation from its commanded pose, m (world frame).
    pub translation_m: [f64; 3],
    /// The base's small rotation about its origin, rad (world frame).
    pub rotation_rad: [f64; 3],
}

/// A servo in a `/grasp/fingers` message (`grasp_model::ServoSolution`).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(test, derive(schemars::JsonSchema))]
pub struct ServoMessage {
    /// Its name in the scene.
    pub name: String,
    /// The sum of its jaws' normal forces, N.
    pub force_n: f64,
    /// The jaws' travel from their command, m (negative: pushed back).
    pub travel_m: f64,
}

impl FingersMessage {
    /// Builds the message of a step (all scene fingers, released ones with zero forces).
    pub fn from_record(r: &StepRecord) -> Self {
        let status = serde_json::to_value(r.solution.status)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
            .unwrap_or_default();
        FingersMessage {
            time_s: r.time_s,
            step: r.index,
            status,
            reason: r.solution.reason.clone(),
            solver: serde_json::to_value(r.solution.solver.solver)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default(),
            fallback: r.solution.solver.fallback.clone(),
            warm_start: r.reused_program,
            iterations: r.solution.solver.iterations,
            factorizations: r.solution.solver.factorizations,
            compliance: serde_json::to_value(r.solution.solver.compliance)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default(),
            inner_iterations: r.solution.solver.inner_iterations,
            equilibrium_residual: r.solution.residuals.map(|x| x.equilibrium_relative),
            external_force_n: r.external_force_n,
            external_torque_nm: r.external_torque_nm,
            smallest_margin_n: r.margin.as_ref().and_then(|m| m.smallest_n),
            margin_held_to_n: r.margin.as_ref().map(|m| m.held_to_n),
            margin_undetermined: r.margin.as_ref().and_then(|m| m.undetermined.clone()),
            margin_failing_finger: r.margin.as_ref().and_then(|m| m.failing_finger.clone()),
            margin_other_equilibrium: r
                .margin
                .as_ref()
                .and_then(|m| m.other_equilibrium.as_ref().map(|o| o.found.clone())),
            fingers: r
                .commands
                .iter()
                .map(|c| {
                    let (control, load, approach) = match c.command {
                        Command::Held => ("held", 0.0, 0.0),
                        Command::Load(p) => ("load", p, 0.0),
                        Command::Released => ("released", 0.0, 0.0),
                        Command::Approach(d) => ("approach", 0.0, d),
                    };
                    let f = r.solution.finger(&c.name);
                    let contact =
                        f.map_or(0, |f| f.stick_count + f.slip_count + f.frictionless_count);
                    FingerMessage {
                        name: c.name.clone(),
                        control: control.into(),
                        commanded_load_n: load,
                        commanded_approach_m: approach,
                        normal_force_n: f.map_or(0.0, |f| f.normal_force_n),
                        tangential_force_n: f.map_or([0.0; 3], |f| f.tangential_force_n),
                        tangential_magnitude_n: f.map_or(0.0, |f| f.tangential_magnitude_n),
                        torsional_moment_nm: f.map_or(0.0, |f| f.torsional_moment_nm),
                        friction_utilization: f.map_or(0.0, |f| f.friction_utilization),
                        slip_fraction: f.map_or(0.0, |f| {
                            if contact > 0 {
                                f.slip_count as f64 / contact as f64
                            } else {
                                0.0
                            }
                        }),
                        core_displacement_m: f
                            .and_then(|f| f.mount_displacement)
                            .map(|d| d.translation_m),
                    }
                })
                .collect(),
            hands: hand_messages(&r.solution),
            servos: servo_messages(&r.solution),
        }
    }
}

/// The hands of a step's solution, as `/grasp/fingers` carries them.
fn hand_messages(s: &grasp_model::Solution) -> Vec<HandMessage> {
    s.hands
        .iter()
        .map(|h| HandMessage {
            name: h.name.clone(),
            force_n: h.force_n,
            moment_nm: h.moment_nm,
            translation_m: h.translation_m,
            rotation_rad: h.rotation_rad,
        })
        .collect()
}

/// The servos of a step's solution, as `/grasp/fingers` carries them.
fn servo_messages(s: &grasp_model::Solution) -> Vec<ServoMessage> {
    s.servos
        .iter()
        .map(|v| ServoMessage {
            name: v.name.clone(),
            force_n: v.force_n,
            travel_m: v.travel_m,
        })
        .collect()
}

/// The JSON Schema of a `/grasp/fingers` message, [`FingersMessage`], written out (not
/// generated: the schema text is part of every MCAP file, and it lists the values of the
/// string fields, which the struct's types do not know); a test checks it field by field
/// against the struct.
fn fingers_schema() -> serde_json::Value {
    let num = json!({"type": "number"});
    // Absent rather than null when a finger has no mount; a reader may still write null.
    let core = json!({"type": ["array", "null"], "items": num, "minItems": 3, "maxItems": 3});
    let vec3 = json!({"type": "array", "items": num, "minItems": 3, "maxItems": 3});
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "grasp.FingerResultants",
        "type": "object",
        "properties": {
            "time_s": num, "step": {"type": "integer"}, "status": {"type": "string"},
            "reason": {"type": ["string", "null"]},
            "solver": {"type": "string", "enum": ["native", "clarabel"]},
            "fallback": {"type": ["string", "null"]}, "warm_start": {"type": "boolean"},
            "iterations": {"type": "integer"}, "factorizations": {"type": "integer"},
            "compliance": {"type": "string", "enum": ["dense", "fft", "mixed"]},
            "inner_iterations": {"type": "integer"},
            "equilibrium_residual": {"type": ["number", "null"]},
            "external_force_n": {"type": "array", "items": num, "minItems": 3, "maxItems": 3},
            "external_torque_nm": {"type": "array", "items": num, "minItems": 3, "maxItems": 3},
            "smallest_margin_n": {"type": ["number", "null"]},
            "margin_held_to_n": {"type": ["number", "null"]},
            "margin_undetermined": {"type": ["string", "null"]},
            "margin_failing_finger": {"type": ["string", "null"]},
            "margin_other_equilibrium": {"type": ["string", "null"]},
            "fingers": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"}, "control": {"type": "string", "enum": ["held", "load", "released", "approach"]},
                "commanded_load_n": num, "commanded_approach_m": num, "normal_force_n": num,
                "tangential_force_n": {"type": "array", "items": num, "minItems": 3, "maxItems": 3},
                "tangential_magnitude_n": num, "torsional_moment_nm": num,
                "friction_utilization": num, "slip_fraction": num, "core_displacement_m": core
            }}},
            "hands": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"}, "force_n": vec3, "moment_nm": vec3,
                "translation_m": vec3, "rotation_rad": vec3
            }}},
            "servos": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"}, "force_n": num, "travel_m": num
            }}}
        }
    })
}

fn patches_schema() -> serde_json::Value {
    let num = json!({"type": "number"});
    let v2 = json!({"type": "array", "items": num, "minItems": 2, "maxItems": 2});
    let v3 = json!({"type": "array", "items": num, "minItems": 3, "maxItems": 3});
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "grasp.PatchFields",
        "type": "object",
        "properties": {
            "time_s": num, "step": {"type": "integer"},
            "patches": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"},
                "elements": {"type": "array", "items": {"type": "object", "properties": {
                    "index": {"type": "array", "items": {"type": "integer"}},
                    "position_m": v3, "normal_force_n": num, "tangential_force_n": v2,
                    "pressure_pa": num, "gap_m": num, "slip_m": v2, "step_slip_m": v2,
                    "viscous_displacement_m": {"type": "array", "items": num, "minItems": 3, "maxItems": 3},
                    "state": {"type": "string", "enum": ["stick", "slip", "separated", "off_surface", "frictionless"]}
                }}}
            }}}
        }
    })
}

/// One element of a `/grasp/patches` message (a viscoelastic contact's elements also carry
/// the displacement their history added this step).
fn element_json(e: &grasp_model::ElementSolution) -> serde_json::Value {
    let mut v = json!({
        "index": e.index, "position_m": e.position_m, "normal_force_n": e.normal_force_n,
        "tangential_force_n": e.tangential_force_n, "pressure_pa": e.pressure_pa,
        "gap_m": e.gap_m, "slip_m": e.slip_m, "step_slip_m": e.step_slip_m,
        "state": e.state
    });
    if let Some(h) = e.viscous_displacement_m {
        v["viscous_displacement_m"] = json!(h);
    }
    v
}

/// The `/grasp/patches` message of a step: every solved finger whose patch is not recorded as
/// compact maps.
pub fn patches_message(r: &StepRecord) -> serde_json::Value {
    json!({
        "time_s": r.time_s,
        "step": r.index,
        "patches": r.solution.fingers.iter().filter(|f| !is_compact(f.elements.len())).map(|f| json!({
            "name": f.name,
            "elements": f.elements.iter().map(element_json).collect::<Vec<_>>()
        })).collect::<Vec<_>>()
    })
}

/// Writes an MCAP file.
pub struct McapSink {
    path: PathBuf,
    writer: Option<mcap::Writer<BufWriter<File>>>,
    fingers_channel: u16,
    patches_channel: u16,
    scene_channel: u16,
    /// The `/grasp/patch_maps` channel, when the scene has a patch recorded as compact maps.
    maps_channel: Option<u16>,
    /// The `/grasp/tactile` channel, when the scene has a finger with a sensor.
    tactile_channel: Option<u16>,
    /// Per finger with a gel image, its name and its `[colour, height]` channels.
    gel_channels: Vec<(String, [u16; 2])>,
    /// Size of the scene (diagonal of the contacts and centre of mass), m, and the force
    /// arrows' scale, m per N.
    drawing: (f64, f64),
    object_sent: bool,
    sequence: u32,
    /// The steps' warnings, written as metadata records when the log is finished.
    warnings: WarningTally,
    /// How the warnings name the options a user can change.
    respell: fn(&str) -> String,
}

/// The name of the MCAP metadata records holding a run's warnings: one record per warning
/// (each once, [`grasp_model::WarningTally`]), written when the log is finished, none when the
/// run gave no warning. Its keys: `message` (the text, a figure that changed between steps
/// written as its range), `count` (how many steps gave it), `steps` (which: runs of step
/// indices, `3-17, 25`), `first_time_s` and `last_time_s` (their schedule times, s).
pub const WARNING_METADATA: &str = "grasp.warning";

/// The metadata record of one warning (see [`WARNING_METADATA`]).
pub(super) fn warning_metadata(
    w: &TalliedWarning,
    respell: fn(&str) -> String,
) -> mcap::records::Metadata {
    let mut metadata = BTreeMap::from([
        ("message".to_string(), respell(&w.message)),
        ("count".to_string(), w.count.to_string()),
        ("steps".to_string(), w.runs_text(|k| k.to_string())),
    ]);
    for (key, t) in [
        ("first_time_s", w.first_time_s),
        ("last_time_s", w.last_time_s),
    ] {
        if let Some(t) = t {
            metadata.insert(key.to_string(), t.to_string());
        }
    }
    mcap::records::Metadata {
        name: WARNING_METADATA.to_string(),
        metadata,
    }
}

/// An MCAP writer on `file` with `profile` (`""`: the JSON profile, `"ros2"`), named for this
/// library; `path` names the file in errors.
pub(super) fn open_writer(
    file: File,
    path: &Path,
    profile: &str,
) -> Result<mcap::Writer<BufWriter<File>>, TransferError> {
    mcap::WriteOptions::new()
        .profile(profile)
        .library(concat!("grasp-transfer ", env!("CARGO_PKG_VERSION")))
        .create(BufWriter::new(file))
        .map_err(|e| io_err_chain("mcap", path, &e))
}

/// Closes an MCAP log: the run's `warnings` as metadata records (spelt by `respell`,
/// [`WARNING_METADATA`]), the summary, and the file synced to disk (`path` names it in errors).
pub(super) fn close_writer(
    mut w: mcap::Writer<BufWriter<File>>,
    warnings: &WarningTally,
    respell: fn(&str) -> String,
    path: &Path,
) -> Result<(), TransferError> {
    let err = |e: &dyn std::error::Error| io_err_chain("mcap", path, e);
    for warning in warnings.warnings() {
        w.write_metadata(&warning_metadata(&warning, respell))
            .map_err(|e| err(&e))?;
    }
    w.finish().map_err(|e| err(&e))?;
    let file = w.into_inner().into_inner().map_err(|e| err(e.error()))?;
    file.sync_all().map_err(|e| err(&e))
}

impl McapSink {
    /// Creates (or truncates) the file at `path` and writes to it.
    pub fn create(path: &Path) -> Result<Self, TransferError> {
        let file = File::create(path).map_err(|e| io_err("mcap", path, e))?;
        Self::from_file(file, path)
    }

    /// Writes to an open file; `path` names it in error messages.
    pub fn from_file(file: File, path: &Path) -> Result<Self, TransferError> {
        let writer = open_writer(file, path, "")?;
        Ok(McapSink {
            path: path.to_path_buf(),
            writer: Some(writer),
            fingers_channel: 0,
            patches_channel: 0,
            scene_channel: 0,
            maps_channel: None,
            tactile_channel: None,
            gel_channels: Vec::new(),
            drawing: (1.0, 1.0),
            object_sent: false,
            sequence: 0,
            warnings: WarningTally::new(),
            respell: str::to_string,
        })
    }

    /// Writes the warnings with the option names of the front end that runs (`respell`
    /// rewrites a library text, `grasp_model::option_names::respell`), as it prints them.
    pub fn respell_options(&mut self, respell: fn(&str) -> String) {
        self.respell = respell;
    }

    fn err(&self, e: impl std::error::Error) -> TransferError {
        io_err_chain("mcap", &self.path, &e)
    }

    fn writer(&mut self) -> Result<&mut mcap::Writer<BufWriter<File>>, TransferError> {
        let path = self.path.clone();
        self.writer
            .as_mut()
            .ok_or_else(|| io_err("mcap", &path, "already finished"))
    }

    fn write(&mut self, channel: u16, time_s: f64, data: &[u8]) -> Result<(), TransferError> {
        let ns = (time_s * 1e9).round() as u64;
        self.sequence = self.sequence.wrapping_add(1);
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time: ns,
            publish_time: ns,
        };
        let r = self.writer()?.write_to_known_channel(&header, data);
        r.map_err(|e| self.err(e))
    }
}

/// Adds the JSON Schema `schema` named `name` and a JSON channel on `topic` with it; the
/// channel's id.
fn json_channel(
    w: &mut mcap::Writer<BufWriter<File>>,
    name: &str,
    schema: &serde_json::Value,
    topic: &str,
) -> Result<u16, mcap::McapError> {
    let id = w.add_schema(name, "jsonschema", schema.to_string().as_bytes())?;
    w.add_channel(id, topic, "json", &BTreeMap::new())
}

/// Per finger of `run` whose sensor has a gel image, its `[colour, height]` channels on
/// Foxglove's image schema (added once).
fn gel_channels(
    w: &mut mcap::Writer<BufWriter<File>>,
    run: &RunInfo,
) -> Result<Vec<(String, [u16; 2])>, mcap::McapError> {
    let mut out = Vec::new();
    let mut schema = None;
    for name in run.gel_fingers() {
        let id = match schema {
            Some(id) => id,
            None => {
                let text = raw_image_schema().to_string();
                *schema.insert(w.add_schema(RAW_IMAGE_SCHEMA, "jsonschema", text.as_bytes())?)
            }
        };
        let [colour, height] = gel_topics(&name);
        let none = BTreeMap::new();
        let channels = [
            w.add_channel(id, &colour, "json", &none)?,
            w.add_channel(id, &height, "json", &none)?,
        ];
        out.push((name, channels));
    }
    Ok(out)
}

impl Sink for McapSink {
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        self.drawing = drawing_scale(run.model);
        let path = self.path.clone();
        let e = |e: mcap::McapError| io_err_chain("mcap", &path, &e);
        let w = self.writer()?;
        let fc = json_channel(
            w,
            "grasp.FingerResultants",
            &fingers_schema(),
            FINGERS_TOPIC,
        );
        let fc = fc.map_err(e)?;
        let pc = json_channel(w, "grasp.PatchFields", &patches_schema(), PATCHES_TOPIC);
        let pc = pc.map_err(e)?;
        let scene = scene_update_schema();
        let sc = json_channel(w, "foxglove.SceneUpdate", &scene, SCENE_TOPIC).map_err(e)?;
        self.fingers_channel = fc;
        self.patches_channel = pc;
        self.scene_channel = sc;
        if has_compact_patch(run) {
            let w = self.writer()?;
            let mc = json_channel(w, PATCH_MAPS_SCHEMA, &patch_maps_schema(), PATCH_MAPS_TOPIC);
            self.maps_channel = Some(mc.map_err(e)?);
        }
        if has_sensor(run) {
            let w = self.writer()?;
            let tc = json_channel(w, TACTILE_SCHEMA, &tactile_schema(), TACTILE_TOPIC);
            self.tactile_channel = Some(tc.map_err(e)?);
        }
        self.gel_channels = gel_channels(self.writer()?, run).map_err(e)?;
        Ok(())
    }

    fn step(&mut self, run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let at = SolveAt {
            index: r.index,
            time_s: Some(r.time_s),
        };
        self.warnings.add(at, &r.solution.warnings);
        let f = serde_json::to_vec(&FingersMessage::from_record(r)).map_err(|e| self.err(e))?;
        self.write(self.fingers_channel, r.time_s, &f)?;
        let p = serde_json::to_vec(&patches_message(r)).map_err(|e| self.err(e))?;
        self.write(self.patches_channel, r.time_s, &p)?;
        if let Some(channel) = self.maps_channel {
            let m = serde_json::to_vec(&patch_maps_message(run, r)).map_err(|e| self.err(e))?;
            self.write(channel, r.time_s, &m)?;
        }
        if let Some(channel) = self.tactile_channel {
            let m = serde_json::to_vec(&tactile_message(r)).map_err(|e| self.err(e))?;
            self.write(channel, r.time_s, &m)?;
        }
        for (name, channels) in self.gel_channels.clone() {
            let s = r.sensors.iter().find(|s| s.finger == name);
            let Some(g) = s.and_then(|s| s.gel.as_ref()) else {
                continue;
            };
            for (channel, m) in channels.into_iter().zip(gel_messages(&name, g, r.time_s)) {
                self.write(channel, r.time_s, m.to_string().as_bytes())?;
            }
        }
        let (size_m, m_per_n) = self.drawing;
        if !self.object_sent {
            let o = object_update(run, r.time_s, size_m).to_string();
            self.write(self.scene_channel, r.time_s, o.as_bytes())?;
            self.object_sent = true;
        }
        let a = forces_update(run, r, m_per_n, size_m).to_string();
        self.write(self.scene_channel, r.time_s, a.as_bytes())
    }

    fn finish(&mut self) -> Result<(), TransferError> {
        match self.writer.take() {
            Some(w) => close_writer(w, &self.warnings, self.respell, &self.path),
            None => Ok(()),
        }
    }

    fn abort(&mut self) {
        self.writer.take();
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use serde_json::Value;

    use super::*;

    /// The JSON types a schema allows (`type`, a name or a list of names), after `$ref`.
    fn types(schema: &Value) -> BTreeSet<String> {
        match &schema["type"] {
            Value::String(t) => BTreeSet::from([t.clone()]),
            Value::Array(ts) => ts
                .iter()
                .filter_map(|t| t.as_str().map(String::from))
                .collect(),
            _ => BTreeSet::new(),
        }
    }

    /// `schema` with a `$ref` into the generated schema's `$defs` followed.
    fn resolved<'a>(schema: &'a Value, root: &'a Value) -> &'a Value {
        match schema["$ref"].as_str() {
            Some(r) => &root["$defs"][r.trim_start_matches("#/$defs/")],
            None => schema,
        }
    }

    /// Asserts that `written` and `generated` (resolved against `root`) allow the same JSON
    /// types at `at`, with the same properties (recursively) and the same array items and
    /// lengths.
    fn assert_same_fields(written: &Value, generated: &Value, root: &Value, at: &str) {
        let generated = resolved(generated, root);
        assert_eq!(types(written), types(generated), "{at}: JSON types");
        if let Some(props) = generated["properties"].as_object() {
            let expected: BTreeSet<&String> = props.keys().collect();
            let written_props = written["properties"].as_object().expect("properties");
            let got: BTreeSet<&String> = written_props.keys().collect();
            assert_eq!(got, expected, "{at}: properties");
            for (name, g) in props {
                assert_same_fields(&written_props[name], g, root, &format!("{at}.{name}"));
            }
        }
        if generated.get("items").is_some() {
            for bound in ["minItems", "maxItems"] {
                assert_eq!(written[bound], generated[bound], "{at}: {bound}");
            }
            assert_same_fields(
                &written["items"],
                &generated["items"],
                root,
                &format!("{at}[]"),
            );
        }
    }

    /// The schema written with `/grasp/fingers` describes every field [`FingersMessage`]
    /// serialises (and its fingers' [`FingerMessage`]), with the JSON type the field's Rust
    /// type serialises as, and no other: the two cannot drift apart.
    #[test]
    fn the_fingers_schema_matches_the_message_field_by_field() {
        let generated = serde_json::to_value(schemars::schema_for!(FingersMessage)).unwrap();
        let written = fingers_schema();
        assert_eq!(written["title"], "grasp.FingerResultants");
        assert_same_fields(&written, &generated, &generated, "FingersMessage");
    }
}
