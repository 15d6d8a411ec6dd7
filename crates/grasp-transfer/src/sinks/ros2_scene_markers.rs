//! The scene as `visualization_msgs/msg/MarkerArray` for the ROS 2 profile, so rviz2 shows a
//! hand-off replayed with `ros2 bag play`: the same drawing as the JSON profile's
//! `foxglove.SceneUpdate` ([`super::foxglove_scene`]).
//!
//! - `/grasp/scene`, once, at the first step ([`scene_markers`]): the object (namespace
//!   `object`, in the `object` frame and locked to it: its shape's triangles as a
//!   `TRIANGLE_LIST`, or the box around the contacts as a `CUBE`), the contact points
//!   (`contacts`, one `SPHERE_LIST`) and each fingertip (`fingertips`, id = the finger's index
//!   in the scene: a `SPHERE`, `CYLINDER` or `CUBE`);
//! - `/grasp/force_arrows`, every step ([`force_markers`]): each finger's normal and friction
//!   force as `ARROW`s from the tail to the centre of pressure, pushing on the object
//!   (namespace `forces`, ids `2 i` normal and `2 i + 1` friction, blue and orange,
//!   `arrow_m_per_n` m per N); an arrow too short to draw (a released finger) is a `DELETE` of
//!   its id, so no stale arrow stays.
//!
//! Every marker but the object is in the `world` frame; every marker lives until replaced
//! (lifetime zero).

use nalgebra::{UnitQuaternion, Vector3 as V3};

use super::colour_key::{unit_rgb, FRICTION_FORCE_RGB, NORMAL_FORCE_RGB};
use super::drawing_scale::contact_bounds;
use super::fingertip_drawing::{tip_drawings, z_to, TipDrawing};
use super::ros2_messages::{
    Bytes, ColorRgba, CompressedImage, Header, Marker, MarkerArray, MeshFile, Pose, Time,
    OBJECT_FRAME,
};
use super::sink::RunInfo;
use crate::stepper::StepRecord;

const ARROW: i32 = 0;
const CUBE: i32 = 1;
const SPHERE: i32 = 2;
const CYLINDER: i32 = 3;
const SPHERE_LIST: i32 = 7;
const TRIANGLE_LIST: i32 = 11;
const ADD: i32 = 0;
const DELETE: i32 = 2;

fn rgba(c: [f64; 3], a: f64) -> ColorRgba {
    ColorRgba {
        r: c[0] as f32,
        g: c[1] as f32,
        b: c[2] as f32,
        a: a as f32,
    }
}

fn pose(at: V3<f64>, q: UnitQuaternion<f64>) -> Pose {
    Pose {
        position: at.into(),
        orientation: q.into(),
    }
}

/// A marker of `kind` in namespace `ns` with `id`, at `stamp` in the world frame; the rest
/// empty (identity pose, unit scale, grey).
fn marker(stamp: Time, ns: &str, id: i32, kind: i32) -> Marker {
    Marker {
        header: Header {
            stamp,
            frame_id: "world".into(),
        },
        ns: ns.into(),
        id,
        r#type: kind,
        action: ADD,
        pose: pose(V3::zeros(), UnitQuaternion::identity()),
        scale: V3::repeat(1.0).into(),
        color: rgba([0.55, 0.55, 0.6], 0.5),
        lifetime: Time::ZERO,
        frame_locked: false,
        points: Vec::new(),
        colors: Vec::new(),
        texture_resource: String::new(),
        texture: CompressedImage {
            header: Header {
                stamp: Time::ZERO,
                frame_id: String::new(),
            },
            format: String::new(),
            data: Bytes::default(),
        },
        uv_coordinates: Vec::new(),
        text: String::new(),
        mesh_resource: String::new(),
        mesh_file: MeshFile::default(),
        mesh_use_embedded_materials: false,
    }
}

/// The object in its own frame (`object`: the centre of mass, world axes at the reference
/// pose), locked to it so it moves as `/tf` moves the object: its surface's triangles, or the
/// box around the contacts (`size_m`: the scene's size).
fn object_marker(run: &RunInfo, stamp: Time, size_m: f64) -> Marker {
    let g = run.model;
    let com = g.center_of_mass_m();
    let mut m = match g.object_surface() {
        Some(s) => {
            let mut m = marker(stamp, "object", 0, TRIANGLE_LIST);
            m.points = s
                .triangles
                .iter()
                .flatten()
                .map(|&k| (V3::from(s.vertices_m[k as usize]) - com).into())
                .collect();
            m.color = rgba([0.78, 0.78, 0.82], 0.45);
            m
        }
        None => {
            let (lo, hi) = contact_bounds(g);
            let mut m = marker(stamp, "object", 0, CUBE);
            m.pose = pose((lo + hi) * 0.5 - com, UnitQuaternion::identity());
            m.scale = (hi - lo).map(|x| x.max(0.04 * size_m)).into();
            m.color = rgba([0.78, 0.78, 0.82], 0.3);
            m
        }
    };
    m.header.frame_id = OBJECT_FRAME.into();
    m.frame_locked = true;
    m
}

/// One fingertip's marker, id `id`.
fn tip_marker(stamp: Time, id: i32, tip: &TipDrawing) -> Marker {
    match tip {
        TipDrawing::Sphere { centre, radius_m } => {
            let mut m = marker(stamp, "fingertips", id, SPHERE);
            m.pose = pose(*centre, UnitQuaternion::identity());
            m.scale = V3::repeat(2.0 * radius_m).into();
            m
        }
        TipDrawing::Cylinder {
            centre,
            axis,
            radius_m,
            length_m,
        } => {
            let mut m = marker(stamp, "fingertips", id, CYLINDER);
            m.pose = pose(*centre, z_to(axis));
            m.scale = V3::new(2.0 * radius_m, 2.0 * radius_m, *length_m).into();
            m
        }
        TipDrawing::Pad {
            centre,
            rotation,
            half_sizes_m,
        } => {
            let mut m = marker(stamp, "fingertips", id, CUBE);
            m.pose = pose(*centre, *rotation);
            m.scale = (half_sizes_m * 2.0).into();
            m
        }
    }
}

/// The markers sent once: the object, the contact points and the fingertips.
pub fn scene_markers(run: &RunInfo, stamp: Time, size_m: f64) -> MarkerArray {
    let mut markers = vec![object_marker(run, stamp, size_m)];
    let mut dots = marker(stamp, "contacts", 0, SPHERE_LIST);
    dots.scale = V3::repeat(0.03 * size_m).into();
    dots.color = rgba([0.35, 0.35, 0.4], 1.0);
    dots.points = run
        .model
        .fingers()
        .iter()
        .map(|f| f.frame().origin_m.into())
        .collect();
    markers.push(dots);
    for (name, tip) in tip_drawings(run, size_m) {
        let id = run.scene.fingers.iter().position(|f| f.name == name);
        markers.push(tip_marker(stamp, id.unwrap_or(0) as i32, &tip));
    }
    MarkerArray { markers }
}

/// How the force arrows are drawn.
#[derive(Debug, Clone, Copy)]
pub struct ArrowScale {
    /// Length per force, m per N.
    pub m_per_n: f64,
    /// The scene's size, m (the arrows' width, and the shortest drawn, follow it).
    pub size_m: f64,
}

/// An arrow of `force` (N) ending at `head` (m), id `id`; a `DELETE` of the id when too short
/// to draw.
fn force_arrow(stamp: Time, id: i32, head: V3<f64>, force: V3<f64>, draw: ArrowScale) -> Marker {
    let ArrowScale { m_per_n, size_m } = draw;
    let len = force.norm() * m_per_n;
    let mut m = marker(stamp, "forces", id, ARROW);
    // Not drawn: too short, or not a number.
    if len.is_nan() || len <= 1e-6 * size_m {
        m.action = DELETE;
        return m;
    }
    let w = 0.012 * size_m;
    m.points = vec![(head - force * m_per_n).into(), head.into()];
    m.scale = V3::new(w, 2.0 * w, 0.2 * len).into();
    m
}

/// The step's force arrows.
pub fn force_markers(run: &RunInfo, r: &StepRecord, stamp: Time, draw: ArrowScale) -> MarkerArray {
    let mut markers = Vec::new();
    for (i, spec) in run.scene.fingers.iter().enumerate() {
        let model = run.model.fingers().iter().find(|m| m.name() == spec.name);
        let solved = r.solution.finger(&spec.name);
        let (head, normal, friction) = match (model, solved) {
            (Some(m), Some(f)) => (
                V3::from(f.center_of_pressure_m),
                m.frame().normal * f.normal_force_n,
                V3::from(f.tangential_force_n),
            ),
            _ => (V3::zeros(), V3::zeros(), V3::zeros()),
        };
        let id = 2 * i as i32;
        let mut n = force_arrow(stamp, id, head, normal, draw);
        n.color = rgba(unit_rgb(NORMAL_FORCE_RGB), 1.0);
        let mut t = force_arrow(stamp, id + 1, head, friction, draw);
        t.color = rgba(unit_rgb(FRICTION_FORCE_RGB), 1.0);
        markers.extend([n, t]);
    }
    MarkerArray { markers }
}
