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

use grasp_model::{FingerModel, MarkerReadings, SensorReadings, TaxelReadings};
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

/// An arrow: its origin and its vector, world frame, m.
type Arrow = (Vector3<f64>, Vector3<f64>);

/// Each taxel's arrow: from its centre at its depth in the pad, its force as it acts on the
/// object times `m_per_n`.
fn taxel_vectors(fm: &FingerModel, t: &TaxelReadings, m_per_n: f64) -> Vec<Arrow> {
    let origins = t.centre_m.iter().map(|c| on_pad(fm, *c, t.depth_m));
    let vectors = t.force_n.iter().map(|f| in_world(fm, *f) * m_per_n);
    origins.zip(vectors).collect()
}

/// Each marker's arrow, from its point on the surface, its displacement magnified `k` times so
/// that the longest is [`MARKER_ARROW_FRACTION`] of the patch's shorter side; and `k`.
fn marker_vectors(fm: &FingerModel, m: &MarkerReadings) -> (f64, Vec<Arrow>) {
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
    let origins = m.position_m.iter().map(|p| on_pad(fm, *p, 0.0));
    let vectors = m.displacement_m.iter().map(|u| world(u) * k);
    (k, origins.zip(vectors).collect())
}

/// `arrows` as Rerun's, in `rgb`.
fn drawn(arrows: &[Arrow], rgb: [u8; 3]) -> Arrows3D {
    let [r, g, b] = rgb;
    Arrows3D::from_vectors(arrows.iter().map(|a| f32s(&a.1)).collect::<Vec<_>>())
        .with_origins(arrows.iter().map(|a| f32s(&a.0)).collect::<Vec<_>>())
        .with_colors([Color::from_rgb(r, g, b)])
}

/// The taxels' force arrows (none: cleared).
fn taxel_arrows(fm: &FingerModel, r: Option<&SensorReadings>, m_per_n: f64) -> Arrows3D {
    match r.and_then(|r| r.taxels.as_ref()) {
        Some(t) => drawn(&taxel_vectors(fm, t, m_per_n), NORMAL_FORCE_RGB),
        None => Arrows3D::clear_fields(),
    }
}

/// The markers' displacement arrows, magnified (none: cleared).
fn marker_arrows(fm: &FingerModel, r: Option<&SensorReadings>) -> Arrows3D {
    let Some(m) = r.and_then(|r| r.markers.as_ref()) else {
        return Arrows3D::clear_fields();
    };
    let (k, arrows) = marker_vectors(fm, m);
    drawn(&arrows, MARKER_RGB).with_labels([format!("markers x{k:.3e}")])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first finger of the taxel plate hand-off (f1: contact at x = -0.1 m, normal +x).
    fn finger() -> FingerModel {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/plate_transfer_taxels.json"
        );
        let scene = grasp_model::Scene::from_json_str(&std::fs::read_to_string(path).unwrap());
        let model = grasp_model::GraspModel::from_scene(&scene.unwrap()).unwrap();
        model.fingers()[0].clone()
    }

    /// A taxel's arrow starts `depth_m` behind the surface, in the pad, and a normal reading
    /// points along `n`, into the object (as the force the finger puts on it), at the force
    /// arrows' scale; a shear reading along `t1`.
    #[test]
    fn a_taxels_arrow_starts_in_the_pad_and_points_as_its_force_acts_on_the_object() {
        let fm = finger();
        let f = fm.frame();
        let t = TaxelReadings {
            finger: "f1".into(),
            count: [2, 1],
            depth_m: 5e-4,
            size_m: 1e-3,
            centre_m: vec![[1e-3, 2e-3], [0.0, 0.0]],
            force_n: vec![[2.0, 0.0, 0.0], [0.0, 0.5, 0.0]],
        };
        let a = taxel_vectors(&fm, &t, 0.01);
        let origin = f.origin_m + f.t1 * 1e-3 + f.t2 * 2e-3 - f.normal * 5e-4;
        assert!((a[0].0 - origin).norm() < 1e-15);
        assert!(
            (a[0].0 - f.origin_m).dot(&f.normal) < 0.0,
            "behind the surface"
        );
        assert!((a[0].1 - f.normal * 0.02).norm() < 1e-15);
        assert!((a[1].1 - f.t1 * 0.005).norm() < 1e-15);
    }

    /// A marker pushed into the finger draws an arrow along `-n` from its surface point, the
    /// longest a quarter of the patch's shorter side (the 10 mm x 5 mm patch: 1.25 mm).
    #[test]
    fn a_markers_arrow_points_where_the_surface_moved_magnified_to_a_quarter_side() {
        let fm = finger();
        let f = fm.frame();
        let m = MarkerReadings {
            count: [2, 1],
            position_m: vec![[0.0, 0.0], [1e-3, 0.0]],
            displacement_m: vec![[2e-6, 0.0, 0.0], [0.0, 0.0, 1e-6]],
        };
        let (k, a) = marker_vectors(&fm, &m);
        assert!((k * 2e-6 - 1.25e-3).abs() < 1e-15, "{k}");
        assert!(
            (a[0].1.normalize() + f.normal).norm() < 1e-12,
            "into the finger"
        );
        assert!((a[0].0 - f.origin_m).norm() < 1e-15);
        assert!((a[1].1 - f.t2 * (k * 1e-6)).norm() < 1e-15);
    }
}
