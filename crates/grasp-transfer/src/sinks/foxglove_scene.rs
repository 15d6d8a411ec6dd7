//! `foxglove.SceneUpdate` messages (JSON encoding) for the MCAP's `/grasp/scene` topic, so
//! Foxglove's 3-D panel replays a hand-off: the object (its shape's triangles, or the box
//! around the contacts), a dot at each contact point, each fingertip as its shape
//! ([`super::fingertip_drawing`]: sphere, cylinder or pad), and per step each finger's normal
//! and friction forces as arrows pushing on the object (blue: normal, orange: friction;
//! length `arrow_m_per_n` m per N). Field names and required fields follow Foxglove's
//! published message definitions (foxglove-sdk `schemas/`).

use nalgebra::{UnitQuaternion, Vector3};
use serde_json::{json, Value};

use super::colour_key::{unit_rgb, FRICTION_FORCE_RGB, NORMAL_FORCE_RGB};
use super::drawing_scale::contact_bounds;
use super::fingertip_drawing::{tip_drawings, z_to, TipDrawing};
use super::sink::RunInfo;
use crate::stepper::StepRecord;

/// Topic of the scene updates.
pub const SCENE_TOPIC: &str = "/grasp/scene";

fn vec3(v: &Vector3<f64>) -> Value {
    json!({"x": v.x, "y": v.y, "z": v.z})
}

fn point(v: &[f64; 3]) -> Value {
    json!({"x": v[0], "y": v[1], "z": v[2]})
}

fn color(r: f64, g: f64, b: f64, a: f64) -> Value {
    json!({"r": r, "g": g, "b": b, "a": a})
}

fn identity_pose(at: &Vector3<f64>) -> Value {
    json!({"position": vec3(at), "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}})
}

fn pose(at: &Vector3<f64>, q: &UnitQuaternion<f64>) -> Value {
    json!({"position": vec3(at), "orientation": {"x": q.i, "y": q.j, "z": q.k, "w": q.w}})
}

/// The fingertips' primitives (`spheres`, `cylinders`, `cubes`), light grey.
fn fingertips(run: &RunInfo, size_m: f64) -> Value {
    let (mut spheres, mut cylinders, mut cubes) = (Vec::new(), Vec::new(), Vec::new());
    let grey = color(0.55, 0.55, 0.6, 0.5);
    for (_, tip) in tip_drawings(run, size_m) {
        match tip {
            TipDrawing::Sphere { centre, radius_m } => spheres.push(json!({
                "pose": identity_pose(&centre), "size": vec3(&Vector3::repeat(2.0 * radius_m)), "color": grey
            })),
            TipDrawing::Cylinder { centre, axis, radius_m, length_m } => cylinders.push(json!({
                "pose": pose(&centre, &z_to(&axis)),
                "size": vec3(&Vector3::new(2.0 * radius_m, 2.0 * radius_m, length_m)),
                "bottom_scale": 1.0, "top_scale": 1.0, "color": grey
            })),
            TipDrawing::Pad { centre, rotation, half_sizes_m } => cubes.push(json!({
                "pose": pose(&centre, &rotation), "size": vec3(&(half_sizes_m * 2.0)), "color": grey
            })),
        }
    }
    json!({"spheres": spheres, "cylinders": cylinders, "cubes": cubes})
}

/// Foxglove time from seconds (`sec`, `nsec`), clamped at 0.
pub fn foxglove_time(t_s: f64) -> Value {
    let ns = (t_s.max(0.0) * 1e9).round() as u64;
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

/// An entity with every primitive list present (empty unless given).
fn entity(id: &str, t_s: f64, primitives: Value) -> Value {
    let mut e = json!({
        "timestamp": foxglove_time(t_s), "frame_id": "world", "id": id,
        "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": false, "metadata": [],
        "arrows": [], "cubes": [], "spheres": [], "cylinders": [], "lines": [],
        "triangles": [], "texts": [], "models": []
    });
    if let (Some(e), Some(p)) = (e.as_object_mut(), primitives.as_object()) {
        for (k, v) in p {
            e.insert(k.clone(), v.clone());
        }
    }
    e
}

/// The object and the contact points (sent once, at the first step's time).
pub fn object_update(run: &RunInfo, t_s: f64, size_m: f64) -> Value {
    let g = run.model;
    let object = match g.object_surface() {
        Some(s) => json!({"triangles": [{
            "pose": identity_pose(&Vector3::zeros()),
            "points": s.vertices_m.iter().map(point).collect::<Vec<_>>(),
            "color": color(0.78, 0.78, 0.82, 0.45), "colors": [],
            "indices": s.triangles.iter().flatten().collect::<Vec<_>>()
        }]}),
        None => {
            let (lo, hi) = contact_bounds(g);
            let extent = (hi - lo).map(|x| x.max(0.04 * size_m));
            json!({"cubes": [{"pose": identity_pose(&((lo + hi) * 0.5)), "size": vec3(&extent), "color": color(0.78, 0.78, 0.82, 0.3)}]})
        }
    };
    let d = 0.03 * size_m;
    let tips: Vec<Value> = g
        .fingers()
        .iter()
        .map(|f| json!({"pose": identity_pose(&f.frame().origin_m), "size": vec3(&Vector3::repeat(d)), "color": color(0.35, 0.35, 0.4, 1.0)}))
        .collect();
    let entities = [
        entity("object", t_s, object),
        entity("contacts", t_s, json!({"spheres": tips})),
        entity("fingertips", t_s, fingertips(run, size_m)),
    ];
    json!({"deletions": [], "entities": entities})
}

/// An arrow of `force` (N) whose head is at `head` (m), pushing along the force.
fn arrow(
    head: &Vector3<f64>,
    force: &Vector3<f64>,
    m_per_n: f64,
    rgb: [f64; 3],
    size_m: f64,
) -> Option<Value> {
    let len = force.norm() * m_per_n;
    if len.is_nan() || len <= 1e-6 * size_m {
        return None;
    }
    let dir = force.normalize();
    let q = UnitQuaternion::rotation_between(&Vector3::x(), &dir).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI)
    });
    let tail = head - dir * len;
    let w = 0.012 * size_m;
    Some(json!({
        "pose": {"position": vec3(&tail), "orientation": {"x": q.i, "y": q.j, "z": q.k, "w": q.w}},
        "shaft_length": 0.8 * len, "shaft_diameter": w, "head_length": 0.2 * len, "head_diameter": 2.0 * w,
        "color": color(rgb[0], rgb[1], rgb[2], 1.0)
    }))
}

/// The step's finger forces: at each loaded finger's centre of pressure, its normal force and
/// its friction force.
pub fn forces_update(run: &RunInfo, r: &StepRecord, m_per_n: f64, size_m: f64) -> Value {
    let mut arrows = Vec::new();
    for f in &r.solution.fingers {
        let Some(model) = run.model.fingers().iter().find(|m| m.name() == f.name) else {
            continue;
        };
        let cop = Vector3::from(f.center_of_pressure_m);
        let normal = model.frame().normal * f.normal_force_n;
        arrows.extend(arrow(
            &cop,
            &normal,
            m_per_n,
            unit_rgb(NORMAL_FORCE_RGB),
            size_m,
        ));
        arrows.extend(arrow(
            &cop,
            &Vector3::from(f.tangential_force_n),
            m_per_n,
            unit_rgb(FRICTION_FORCE_RGB),
            size_m,
        ));
    }
    json!({"deletions": [], "entities": [entity("forces", r.time_s, json!({"arrows": arrows}))]})
}

/// The JSON Schema written with the channel: the subset of `foxglove.SceneUpdate` these
/// messages use (Foxglove recognises the schema by its name).
pub fn scene_update_schema() -> Value {
    let num = json!({"type": "number"});
    let xyz = json!({"type": "object", "properties": {"x": num, "y": num, "z": num}, "required": ["x", "y", "z"]});
    let rgba = json!({"type": "object", "properties": {"r": num, "g": num, "b": num, "a": num}, "required": ["r", "g", "b", "a"]});
    let quat = json!({"type": "object", "properties": {"x": num, "y": num, "z": num, "w": num}, "required": ["x", "y", "z", "w"]});
    let pose = json!({"type": "object", "properties": {"position": xyz, "orientation": quat}, "required": ["position", "orientation"]});
    let stamp = json!({"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}, "required": ["sec", "nsec"]});
    let list = |item: Value| json!({"type": "array", "items": item});
    json!({
        "title": "foxglove.SceneUpdate",
        "type": "object",
        "properties": {
            "deletions": list(json!({"type": "object"})),
            "entities": list(json!({
                "type": "object",
                "properties": {
                    "timestamp": stamp, "frame_id": {"type": "string"}, "id": {"type": "string"},
                    "lifetime": stamp, "frame_locked": {"type": "boolean"}, "metadata": list(json!({"type": "object"})),
                    "arrows": list(json!({"type": "object", "properties": {"pose": pose, "shaft_length": num, "shaft_diameter": num, "head_length": num, "head_diameter": num, "color": rgba}})),
                    "cubes": list(json!({"type": "object", "properties": {"pose": pose, "size": xyz, "color": rgba}})),
                    "spheres": list(json!({"type": "object", "properties": {"pose": pose, "size": xyz, "color": rgba}})),
                    "triangles": list(json!({"type": "object", "properties": {"pose": pose, "points": list(xyz.clone()), "color": rgba, "colors": list(rgba.clone()), "indices": list(json!({"type": "integer", "minimum": 0}))}})),
                    "cylinders": list(json!({"type": "object", "properties": {"pose": pose, "size": xyz, "bottom_scale": num, "top_scale": num, "color": rgba}})),
                    "lines": list(json!({"type": "object"})),
                    "texts": list(json!({"type": "object"})), "models": list(json!({"type": "object"}))
                }
            }))
        }
    })
}
