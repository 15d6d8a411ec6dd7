//! The tactile sensors in the Rerun recording: per step, in the 3-D view, each active sensor
//! finger's readings where the sensor sits (`grasp transfer --rrd` of a scene with a
//! `fingers[i].sensor`).
//!
//! - `world/tactile/<name>/taxels`: one arrow a taxel, from its centre on the plane at its
//!   depth in the pad (`depth_m` behind the contact point, along `-n`), the force crossing the
//!   taxel (`normal n + t1 t1 + t2 t2`, as it acts on the object), scaled as the finger's force
//!   arrows (`arrow_m_per_n`), coloured as the normal force arrows;
//! - `world/tactile/<name>/markers`: one arrow a marker, from its point on the pad's surface,
//!   the surface's displacement relative to the finger's core magnified `k` times, `k` chosen
//!   per step so that the longest arrow is a quarter of the patch's shorter side (the label
//!   says `k`); the normal part points into the finger when the surface is pushed in.
//!
//! A released finger (or a failed step) clears both.

use grasp_model::{FingerModel, SensorReadings};
use nalgebra::Vector3;
use rerun::{Arrows3D, AsComponents, Color};

use super::colour_key::NORMAL_FORCE_RGB;
use super::sink::RunInfo;
use crate::stepper::StepRecord;

/// Colour of the marker arrows (grey blue: displacements, not forces).
const MARKER_RGB: [u8; 3] = [90, 130, 200];

/// Longest marker arrow, as a fraction of the patch's shorter side.
const MARKER_ARROW_FRACTION: f64 = 0.25;

/// An entity path and what is logged there.
pub type Drawing = (String, Box<dyn AsComponents>);

/// The drawings of step `r`: every scene finger with a sensor, its readings when the step
/// has them, else cleared; `arrow_m_per_n` the force arrows' scale, m/N.
pub fn tactile_drawings(run: &RunInfo, r: &StepRecord, arrow_m_per_n: f64) -> Vec<Drawing> {
    let mut out: Vec<Drawing> = Vec::new();
    for fm in run.model.fingers() {
        let has = run
            .scene
            .fingers
            .iter()
            .any(|f| f.name == fm.name() && f.sensor.is_some());
        if !has {
            continue;
        }
        let name = fm.name();
        let readings = r.sensors.iter().find(|s| s.finger == name);
        out.push((
            format!("world/tactile/{name}/taxels"),
            Box::new(taxel_arrows(fm, readings, arrow_m_per_n)),
        ));
        out.push((
            format!("world/tactile/{name}/markers"),
            Box::new(marker_arrows(fm, readings)),
        ));
    }
    out
}

/// The point `(a, b)` m along `t1`, `t2` from the contact point of `fm`, `below_m` behind the
/// surface (along `-n`).
fn on_pad(fm: &FingerModel, ab: [f64; 2], below_m: f64) -> Vector3<f64> {
    let f = fm.frame();
    f.origin_m + f.t1 * ab[0] + f.t2 * ab[1] - f.normal * below_m
}

/// `[normal, t1, t2]` components in the world frame.
fn in_world(fm: &FingerModel, c: [f64; 3]) -> Vector3<f64> {
    let f = fm.frame();
    f.normal * c[0] + f.t1 * c[1] + f.t2 * c[2]
}

fn f32s(v: &Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The taxels' force arrows (none: cleared).
fn taxel_arrows(fm: &FingerModel, r: Option<&SensorReadings>, m_per_n: f64) -> Arrows3D {
    let Some(t) = r.and_then(|r| r.taxels.as_ref()) else {
        return Arrows3D::clear_fields();
    };
    let origins = t.centre_m.iter().map(|c| f32s(&on_pad(fm, *c, t.depth_m)));
    let vectors = t
        .force_n
        .iter()
        .map(|f| f32s(&(in_world(fm, *f) * m_per_n)));
    let [r_, g, b] = NORMAL_FORCE_RGB;
    Arrows3D::from_vectors(vectors.collect::<Vec<_>>())
        .with_origins(origins.collect::<Vec<_>>())
        .with_colors([Color::from_rgb(r_, g, b)])
}

/// The markers' displacement arrows, magnified (none: cleared).
fn marker_arrows(fm: &FingerModel, r: Option<&SensorReadings>) -> Arrows3D {
    let Some(m) = r.and_then(|r| r.markers.as_ref()) else {
        return Arrows3D::clear_fields();
    };
    // The surface displacement `[normal (into the finger), t1, t2]` as a world vector.
    let world = |u: &[f64; 3]| in_world(fm, [-u[0], u[1], u[2]]);
    let longest = m
        .displacement_m
        .iter()
        .map(|u| world(u).norm())
        .fold(0.0, f64::max);
    let g = &fm.patch().grid;
    let side = (g.nx as f64 * g.hx).min(g.ny as f64 * g.hy);
    let k = if longest > 0.0 {
        MARKER_ARROW_FRACTION * side / longest
    } else {
        1.0
    };
    let origins = m.position_m.iter().map(|p| f32s(&on_pad(fm, *p, 0.0)));
    let vectors = m.displacement_m.iter().map(|u| f32s(&(world(u) * k)));
    let [r_, g_, b] = MARKER_RGB;
    Arrows3D::from_vectors(vectors.collect::<Vec<_>>())
        .with_origins(origins.collect::<Vec<_>>())
        .with_colors([Color::from_rgb(r_, g_, b)])
        .with_labels([format!("markers x{k:.3e}")])
}
