//! The MCAP log's ROS 2 profile (`--mcap-profile ros2`): the hand-off as `ros2 bag record`
//! would have recorded it, CDR-encoded standard messages with `ros2msg` schemas
//! ([`super::ros2_definitions`], [`super::ros2_messages`]), one MCAP file with the `ros2`
//! profile, which `ros2 bag info`, `ros2 bag play` (with `-s mcap` before Iron), PlotJuggler,
//! Foxglove and the Python readers of rosbag2 (`rosbags`, `mcap-ros2-support`) open as it is.
//!
//! Topics (`<finger>` each scene finger's name):
//! - `/tf_static` (`tf2_msgs/msg/TFMessage`, once, transient-local: [`LATCHED`]): `world` to each
//!   `<finger>/contact` (origin the contact point; x, y, z along `t1`, `t2` and the inward
//!   normal);
//! - `/tf` (`tf2_msgs/msg/TFMessage`, every solved step): `world` to `object` (the object's
//!   centre of mass and orientation after the step's rigid displacement);
//! - `/grasp/<finger>/wrench` (`geometry_msgs/msg/WrenchStamped`, every solved step, frame
//!   `<finger>/contact`): the force the finger puts on the object (x, y: friction along `t1`,
//!   `t2`; z: the normal force) and its moment about the contact point (zero while released);
//! - `/grasp/<finger>/pressure` (`sensor_msgs/msg/Image`, `32FC1`, Pa) and
//!   `/grasp/<finger>/contact_state` (`mono8`: 0 stick, 1 slip, 2 separated, 3 off the
//!   surface, 4 in contact without friction), each step the finger is in the grasp, frame
//!   `<finger>/contact`: pixel (column `i`, row `j`) is element `(i, j)`, columns along `t1`
//!   and rows along `t2`, as a camera whose optical z is the normal lays out its image;
//! - for a finger with a sensor, the same layout: `/grasp/<finger>/taxels` (`32FC3`: each
//!   taxel's `[normal, t1, t2]` force, N), `/grasp/<finger>/markers` (`32FC3`: each marker's
//!   `[normal, t1, t2]` displacement, m), `/grasp/<finger>/gel` (`rgb8`) and
//!   `/grasp/<finger>/gel_height` (`32FC1`, m);
//! - `/grasp/step` (`grasp_msgs/msg/StepReport`, every step): the solve's outcome and work,
//!   the margin and every finger's state (`ros2/grasp_msgs`);
//! - `/grasp/scene` (`visualization_msgs/msg/MarkerArray`, once, transient-local): the object,
//!   contacts and fingertips; `/grasp/force_arrows` (the same type, every step): the force
//!   arrows ([`super::ros2_scene_markers`]).
//!
//! A step without forces (no equilibrium, no convergence: `--keep-going`) has its
//! `/grasp/step` report, which says why, and deletes the force arrows; it writes no wrench, no
//! image and no `/tf` (tf2 keeps the last pose).
//!
//! Stamps (headers, and each record's log and publish time) are the schedule's time plus the
//! start time asked for (0 by default: the Unix epoch), so a simulated hand-off can be laid
//! beside a real recording. The run's warnings are metadata records as in the JSON profile.
//! Nothing nondeterministic is written.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use nalgebra::{UnitQuaternion, Vector3 as V3};
use serde::Serialize;

use super::drawing_scale::drawing_scale;
use super::fingertip_drawing::frame_rotation;
use super::mcap_log::{
    close_writer, open_writer, FingerMessage, FingersMessage, HandMessage, ServoMessage,
};
use super::ros2_definitions::schema_text;
use super::ros2_messages::{
    cdr_message, contact_frame_id, FingerState, HandState, Header, Pose, ServoState, StepReport,
    TfMessage, Time, TransformStamped, WrenchStamped, OBJECT_FRAME,
};
use super::ros2_patch_images::finger_images;
use super::ros2_scene_markers::{force_markers, scene_markers, ArrowScale};
use super::sink::{io_err, RunInfo, Sink};
use crate::error::TransferError;
use crate::slip_margin::{carrying, slip_margin, step_slip_margins};
use crate::stepper::StepRecord;
use grasp_model::{FingerSolution, SolveAt, WarningTally};

/// The topics written once and offered transient-local (depth 1), so that a subscriber that
/// joins a `ros2 bag play` later (rviz2 started after it) still receives them.
const LATCHED: [&str; 2] = ["/tf_static", "/grasp/scene"];

/// The offered QoS of a recorded topic as rosbag2 stores it (`offered_qos_profiles`):
/// reliable, keep-last `depth`, volatile or (the [`LATCHED`] topics) transient-local, every
/// duration unset (rmw's "infinite").
fn qos_yaml(depth: u32, transient_local: bool) -> String {
    let infinite = "\n    sec: 9223372036\n    nsec: 854775807";
    format!(
        "- history: 1\n  depth: {depth}\n  reliability: 1\n  durability: {}\n  deadline:{infinite}\n  \
         lifespan:{infinite}\n  liveliness: 1\n  liveliness_lease_duration:{infinite}\n  \
         avoid_ros_namespace_conventions: false\n",
        if transient_local { 1 } else { 2 }
    )
}

/// Why `name` cannot be a token of a ROS 2 topic or frame name (letters, digits and
/// underscores, not starting with a digit), if it cannot.
pub fn ros_name_problem(name: &str) -> Option<String> {
    let ok = name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && name.chars().next().is_some_and(|c| !c.is_ascii_digit());
    (!ok).then(|| {
        format!(
            "finger name {name:?} cannot be part of a ROS 2 topic name (letters, digits and \
             underscores only, not starting with a digit): rename the finger in the scene to \
             write the ros2 MCAP profile"
        )
    })
}

/// The channels of one finger.
#[derive(Debug, Clone, Default)]
struct FingerChannels {
    wrench: u16,
    /// Topic name's last part and channel, per image kind the finger has.
    images: BTreeMap<&'static str, u16>,
}

/// Writes an MCAP file of the ROS 2 profile.
pub struct Ros2McapSink {
    path: PathBuf,
    writer: Option<mcap::Writer<BufWriter<File>>>,
    start_ns: u64,
    schemas: BTreeMap<&'static str, u16>,
    step_channel: u16,
    tf_channel: u16,
    tf_static_channel: u16,
    scene_channel: u16,
    arrows_channel: u16,
    fingers: Vec<(String, FingerChannels)>,
    /// Scene size, m, and the force arrows' scale, m per N.
    drawing: ArrowScale,
    static_sent: bool,
    sequence: u32,
    warnings: WarningTally,
    respell: fn(&str) -> String,
}

impl Ros2McapSink {
    /// Writes to an open file (`path` names it in errors); stamps start `start_ns` after the
    /// Unix epoch.
    pub fn from_file(file: File, path: &Path, start_ns: u64) -> Result<Self, TransferError> {
        let writer = open_writer(file, path, "ros2")?;
        Ok(Ros2McapSink {
            path: path.to_path_buf(),
            writer: Some(writer),
            start_ns,
            schemas: BTreeMap::new(),
            step_channel: 0,
            tf_channel: 0,
            tf_static_channel: 0,
            scene_channel: 0,
            arrows_channel: 0,
            fingers: Vec::new(),
            drawing: ArrowScale {
                m_per_n: 1.0,
                size_m: 1.0,
            },
            static_sent: false,
            sequence: 0,
            warnings: WarningTally::new(),
            respell: str::to_string,
        })
    }

    /// Writes the warnings with the option names of the front end that runs.
    pub fn respell_options(&mut self, respell: fn(&str) -> String) {
        self.respell = respell;
    }

    fn err(&self, e: impl std::fmt::Display) -> TransferError {
        io_err("mcap", &self.path, e)
    }

    fn writer(&mut self) -> Result<&mut mcap::Writer<BufWriter<File>>, TransferError> {
        let path = self.path.clone();
        self.writer
            .as_mut()
            .ok_or_else(|| io_err("mcap", &path, "already finished"))
    }

    /// A channel on `topic` of message type `ty` (its schema added once).
    fn channel(&mut self, ty: &'static str, topic: &str, depth: u32) -> Result<u16, TransferError> {
        let schema = match self.schemas.get(ty) {
            Some(&id) => id,
            None => {
                let text = schema_text(ty).ok_or_else(|| self.err(format!("no schema {ty}")))?;
                let id = self.writer()?.add_schema(ty, "ros2msg", text.as_bytes());
                let id = id.map_err(|e| self.err(e))?;
                self.schemas.insert(ty, id);
                id
            }
        };
        let qos = qos_yaml(depth, LATCHED.contains(&topic));
        let metadata = BTreeMap::from([("offered_qos_profiles".to_string(), qos)]);
        let id = self.writer()?.add_channel(schema, topic, "cdr", &metadata);
        id.map_err(|e| self.err(e))
    }

    /// The stamp of schedule time `time_s`, s, in nanoseconds after the epoch.
    fn stamp_ns(&self, time_s: f64) -> u64 {
        self.start_ns
            .saturating_add((time_s.max(0.0) * 1e9).round() as u64)
    }

    fn write<T: Serialize>(&mut self, channel: u16, ns: u64, m: &T) -> Result<(), TransferError> {
        let data = cdr_message(m).map_err(|e| self.err(e))?;
        self.sequence = self.sequence.wrapping_add(1);
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time: ns,
            publish_time: ns,
        };
        let r = self.writer()?.write_to_known_channel(&header, &data);
        r.map_err(|e| self.err(e))
    }

    /// Every finger's wrench and images at a solved step `r`, stamped `stamp` (`ns`).
    fn write_fingers(
        &mut self,
        run: &RunInfo,
        r: &StepRecord,
        ns: u64,
        stamp: Time,
    ) -> Result<(), TransferError> {
        for i in 0..self.fingers.len() {
            let (name, channels) = &self.fingers[i];
            let wrench = (channels.wrench, finger_wrench(run, r, name, stamp));
            let images: Vec<_> = finger_images(run, r, name, stamp)
                .into_iter()
                .filter_map(|(kind, image)| channels.images.get(kind).map(|&c| (c, image)))
                .collect();
            self.write(wrench.0, ns, &wrench.1)?;
            for (channel, image) in images {
                self.write(channel, ns, &image)?;
            }
        }
        Ok(())
    }

    /// Each finger's channels: its wrench and its images (those its patch and sensor give).
    fn finger_channels(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        for spec in &run.scene.fingers {
            let name = spec.name.clone();
            let wrench = self.channel(
                "geometry_msgs/msg/WrenchStamped",
                &format!("/grasp/{name}/wrench"),
                10,
            )?;
            let mut images = BTreeMap::new();
            for kind in super::ros2_patch_images::image_kinds(spec) {
                let topic = format!("/grasp/{name}/{kind}");
                images.insert(kind, self.channel("sensor_msgs/msg/Image", &topic, 10)?);
            }
            self.fingers.push((name, FingerChannels { wrench, images }));
        }
        Ok(())
    }
}

/// `world` to each finger's contact frame, stamped `stamp`.
fn contact_transforms(run: &RunInfo, stamp: Time) -> TfMessage {
    let transforms = run
        .model
        .fingers()
        .iter()
        .map(|f| {
            let fr = f.frame();
            TransformStamped {
                header: Header {
                    stamp,
                    frame_id: "world".into(),
                },
                child_frame_id: contact_frame_id(f.name()),
                transform: Pose {
                    position: fr.origin_m.into(),
                    orientation: frame_rotation(fr).into(),
                },
            }
        })
        .collect();
    TfMessage { transforms }
}

/// `world` to `object`: the centre of mass moved and turned by the step's rigid displacement
/// (none: the reference pose).
fn object_transform(run: &RunInfo, r: &StepRecord, stamp: Time) -> TfMessage {
    let com = run.model.center_of_mass_m();
    let (t, w) = r
        .solution
        .rigid_displacement
        .map_or((V3::zeros(), V3::zeros()), |d| {
            (V3::from(d.translation_m), V3::from(d.rotation_rad))
        });
    TfMessage {
        transforms: vec![TransformStamped {
            header: Header {
                stamp,
                frame_id: "world".into(),
            },
            child_frame_id: OBJECT_FRAME.into(),
            transform: Pose {
                position: (com + t).into(),
                orientation: UnitQuaternion::from_scaled_axis(w).into(),
            },
        }],
    }
}

/// Finger `name`'s wrench on the object in its contact frame at `stamp`: force `(Q t1, Q t2,
/// P)` and moment about the contact point `(P c2, -P c1, M_n)`, `c` the centre of pressure in
/// the frame (the element forces act in the patch's plane); zero when not in the grasp.
fn finger_wrench(run: &RunInfo, r: &StepRecord, name: &str, stamp: Time) -> WrenchStamped {
    let model = run.model.fingers().iter().find(|m| m.name() == name);
    let (force, torque) = match (model, r.solution.finger(name)) {
        (Some(m), Some(f)) => {
            let fr = m.frame();
            let q = V3::from(f.tangential_force_n);
            let c = V3::from(f.center_of_pressure_m) - fr.origin_m;
            let p = f.normal_force_n;
            (
                V3::new(q.dot(&fr.t1), q.dot(&fr.t2), p),
                V3::new(p * c.dot(&fr.t2), -p * c.dot(&fr.t1), f.torsional_moment_nm),
            )
        }
        _ => (V3::zeros(), V3::zeros()),
    };
    WrenchStamped {
        header: Header {
            stamp,
            frame_id: contact_frame_id(name),
        },
        force: force.into(),
        torque: torque.into(),
    }
}

/// Finger `f`'s `grasp_msgs/msg/FingerState` (`s`: its solution, when in the grasp) in a
/// solution of load scale `load_scale_n` (N) that has forces when `solved`.
fn finger_state(
    f: &FingerMessage,
    s: Option<&FingerSolution>,
    solved: bool,
    load_scale_n: f64,
) -> FingerState {
    let contact = s.map_or(0, |s| s.stick_count + s.slip_count + s.frictionless_count);
    let stick = s.map_or(0, |s| s.stick_count);
    let frictional = s.filter(|s| solved && s.friction_coefficient > 0.0);
    FingerState {
        name: f.name.clone(),
        control: f.control.clone(),
        commanded_load_n: f.commanded_load_n,
        commanded_approach_m: f.commanded_approach_m,
        normal_force_n: f.normal_force_n,
        friction_force_n: f.tangential_magnitude_n,
        torsional_moment_nm: f.torsional_moment_nm,
        friction_utilization: f.friction_utilization,
        slip_margin: frictional.map_or(f64::NAN, slip_margin),
        slip_margin_counted: frictional.is_some_and(|s| carrying(s, load_scale_n)),
        core_displacement_m: f.core_displacement_m.unwrap_or([f64::NAN; 3]),
        stick_fraction: if contact > 0 {
            stick as f64 / contact as f64
        } else {
            0.0
        },
        slip_fraction: f.slip_fraction,
    }
}

fn hand_state(h: HandMessage) -> HandState {
    HandState {
        name: h.name,
        force_n: h.force_n,
        moment_nm: h.moment_nm,
        translation_m: h.translation_m,
        rotation_rad: h.rotation_rad,
    }
}

fn servo_state(v: ServoMessage) -> ServoState {
    ServoState {
        name: v.name,
        force_n: v.force_n,
        travel_m: v.travel_m,
    }
}

/// The `grasp_msgs/msg/StepReport` of step `r` at `stamp`.
fn step_report(r: &StepRecord, stamp: Time) -> StepReport {
    let m = FingersMessage::from_record(r);
    let sol = &r.solution;
    let solved = sol.status.has_forces();
    let fingers = m
        .fingers
        .iter()
        .map(|f| finger_state(f, sol.finger(&f.name), solved, sol.load_scale_n))
        .collect();
    let smallest = step_slip_margins(sol).counted;
    StepReport {
        header: Header {
            stamp,
            frame_id: "world".into(),
        },
        step: r.index as u32,
        status: m.status,
        reason: m.reason.unwrap_or_default(),
        solver: m.solver,
        warm_start: m.warm_start,
        iterations: m.iterations,
        factorizations: m.factorizations,
        inner_iterations: m.inner_iterations,
        smallest_slip_margin: smallest.map_or(f64::NAN, |s| s.margin),
        slip_margin_finger: smallest.map_or(String::new(), |s| s.finger.to_string()),
        equilibrium_residual: m.equilibrium_residual.unwrap_or(f64::NAN),
        smallest_margin_n: m.smallest_margin_n.unwrap_or(f64::NAN),
        margin_held_to_n: m.margin_held_to_n.unwrap_or(f64::NAN),
        margin_failing_finger: m.margin_failing_finger.unwrap_or_default(),
        fingers,
        hands: m.hands.into_iter().map(hand_state).collect(),
        servos: m.servos.into_iter().map(servo_state).collect(),
    }
}

/// Why a stamp cannot be written: schedule time `time_s` (s) is `ns` after the epoch, past
/// what a ROS 2 stamp holds.
fn past_2038(time_s: f64, ns: u64) -> String {
    format!(
        "schedule time {time_s} s would be stamped {} s after the Unix epoch, past 2038-01-19 \
         03:14:07 UTC, the last a ROS 2 stamp holds (its seconds are a 32-bit integer): give an \
         earlier start time (--ros2-start-time, ros2_start_time=)",
        ns / 1_000_000_000
    )
}

impl Sink for Ros2McapSink {
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        if let Some(problem) = run
            .scene
            .fingers
            .iter()
            .find_map(|f| ros_name_problem(&f.name))
        {
            return Err(self.err(problem));
        }
        let (size_m, m_per_n) = drawing_scale(run.model);
        self.drawing = ArrowScale { m_per_n, size_m };
        self.tf_static_channel = self.channel("tf2_msgs/msg/TFMessage", "/tf_static", 1)?;
        self.tf_channel = self.channel("tf2_msgs/msg/TFMessage", "/tf", 10)?;
        self.step_channel = self.channel("grasp_msgs/msg/StepReport", "/grasp/step", 10)?;
        self.scene_channel =
            self.channel("visualization_msgs/msg/MarkerArray", "/grasp/scene", 1)?;
        self.arrows_channel = self.channel(
            "visualization_msgs/msg/MarkerArray",
            "/grasp/force_arrows",
            10,
        )?;
        self.finger_channels(run)
    }

    fn step(&mut self, run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let at = SolveAt {
            index: r.index,
            time_s: Some(r.time_s),
        };
        self.warnings.add(at, &r.solution.warnings);
        let ns = self.stamp_ns(r.time_s);
        let stamp = Time::from_ns(ns).ok_or_else(|| self.err(past_2038(r.time_s, ns)))?;
        if !self.static_sent {
            self.write(self.tf_static_channel, ns, &contact_transforms(run, stamp))?;
            let scene = scene_markers(run, stamp, self.drawing.size_m);
            self.write(self.scene_channel, ns, &scene)?;
            self.static_sent = true;
        }
        self.write(self.step_channel, ns, &step_report(r, stamp))?;
        if r.solution.status.has_forces() {
            self.write(self.tf_channel, ns, &object_transform(run, r, stamp))?;
            self.write_fingers(run, r, ns, stamp)?;
        }
        let arrows = force_markers(run, r, stamp, self.drawing);
        self.write(self.arrows_channel, ns, &arrows)
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
    use super::*;

    #[test]
    fn finger_names_that_cannot_be_topic_names_are_refused_by_name() {
        assert!(ros_name_problem("f1").is_none());
        assert!(ros_name_problem("left_jaw").is_none());
        for bad in ["left jaw", "1st", "a-b", ""] {
            let why = ros_name_problem(bad).expect(bad);
            assert!(why.contains(&format!("{bad:?}")), "{why}");
        }
    }
}
