//! Invariances of the energy model (model.md, "Checks with known answers").

mod support;
use support::*;

use grasp_model::Solution;

fn max_rel_diff(a: &Solution, b: &Solution, factor: f64) -> f64 {
    let mut worst = 0.0_f64;
    let scale = a.load_scale_n;
    for (fa, fb) in a.fingers.iter().zip(&b.fingers) {
        worst =
            worst.max((fa.normal_force_n * factor - fb.normal_force_n).abs() / (scale * factor));
        for c in 0..3 {
            let d = fa.tangential_force_n[c] * factor - fb.tangential_force_n[c];
            worst = worst.max(d.abs() / (scale * factor));
        }
    }
    worst
}

/// Flat tips: `C` scales by 1/k and `c = 0`, so the minimiser is unchanged. Tolerance 1e-7 of
/// the load: two independent interior-point solves at tolerance 1e-10 on the scaled program.
#[test]
fn all_moduli_times_1e3_leave_forces_unchanged_for_flat_tips() {
    for name in ["plate_four_fingers.json", "cube_a.json", "cube_b.json"] {
        let v = example_json(name);
        let mut w = v.clone();
        scale_moduli(&mut w, 1e3);
        let d = max_rel_diff(&solved(&v), &solved(&w), 1.0);
        assert!(d < 1e-7, "{name}: forces changed by {d} of the load");
    }
}

/// Flat tips, constant mu: the program is homogeneous in the load, so weight x10 scales every
/// force by 10.
#[test]
fn weight_times_10_scales_forces_by_10() {
    for name in ["plate_four_fingers.json", "cube_a.json", "cube_b.json"] {
        let v = example_json(name);
        let mut w = v.clone();
        let weight = w["object"]["weight"].as_f64().unwrap();
        w["object"]["weight"] = (10.0 * weight).into();
        let d = max_rel_diff(&solved(&v), &solved(&w), 10.0);
        assert!(d < 1e-7, "{name}: forces off by {d} of the load");
    }
}

/// Disc: mirror x -> -x maps f1 to f2; normal forces equal, friction mirrored.
#[test]
fn mirror_symmetric_disc_gives_mirror_symmetric_forces() {
    let s = solved(&example_json("disc_three_fingers.json"));
    let (a, b) = (s.finger("f1").unwrap(), s.finger("f2").unwrap());
    let tol = 1e-7 * s.load_scale_n;
    assert!((a.normal_force_n - b.normal_force_n).abs() < tol);
    let (qa, qb) = (a.tangential_force_n, b.tangential_force_n);
    assert!(
        (qa[0] + qb[0]).abs() < tol && (qa[2] - qb[2]).abs() < tol,
        "{qa:?} vs {qb:?}"
    );
}

/// Cube B: mirror x <-> y maps f1 to f2 and f3 to itself.
#[test]
fn mirror_symmetric_cube_b_gives_mirror_symmetric_forces() {
    let s = solved(&example_json("cube_b.json"));
    let (a, b, c) = (
        s.finger("f1").unwrap(),
        s.finger("f2").unwrap(),
        s.finger("f3").unwrap(),
    );
    let tol = 1e-7 * s.load_scale_n;
    assert!((a.normal_force_n - b.normal_force_n).abs() < tol);
    let (qa, qb, qc) = (
        a.tangential_force_n,
        b.tangential_force_n,
        c.tangential_force_n,
    );
    assert!(
        (qa[0] - qb[1]).abs() < tol && (qa[1] - qb[0]).abs() < tol && (qa[2] - qb[2]).abs() < tol
    );
    assert!(
        (qc[0] - qc[1]).abs() < tol,
        "f3's friction is on the mirror plane: {qc:?}"
    );
}

/// Rigid motion of the whole scene (points rotated and shifted, directions rotated, each
/// patch's tangent carried along): finger forces are unchanged, tangential forces rotate.
#[test]
fn rotating_and_translating_the_scene_rotates_the_forces() {
    use nalgebra::{Rotation3, Unit, Vector3};
    use serde_json::{json, Value};
    let vec = |a: &Value| {
        Vector3::new(
            a[0].as_f64().unwrap(),
            a[1].as_f64().unwrap(),
            a[2].as_f64().unwrap(),
        )
    };
    let arr = |q: Vector3<f64>| json!([q.x, q.y, q.z]);
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(1.0, 2.0, 0.5)), 0.7);
    let shift = Vector3::new(0.3, -1.2, 0.8);
    // The original with explicit tangents, so both scenes use corresponding patch frames.
    let mut v = example_json("cube_a.json");
    for f in v["fingers"].as_array_mut().unwrap() {
        let n = vec(&f["normal"]);
        let hint = if n.x.abs() < 0.5 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        f["tangent"] = arr(hint);
    }
    let mut w = v.clone();
    w["object"]["center_of_mass"] = arr(rot * vec(&v["object"]["center_of_mass"]) + shift);
    w["object"]["gravity"] = arr(rot * vec(&v["object"]["gravity"]));
    for (i, f) in w["fingers"].as_array_mut().unwrap().iter_mut().enumerate() {
        let o = &v["fingers"][i];
        f["contact_point"] = arr(rot * vec(&o["contact_point"]) + shift);
        f["normal"] = arr(rot * vec(&o["normal"]));
        f["tangent"] = arr(rot * vec(&o["tangent"]));
    }
    let (a, b) = (solved(&v), solved(&w));
    let tol = 1e-7 * a.load_scale_n;
    for (fa, fb) in a.fingers.iter().zip(&b.fingers) {
        assert!((fa.normal_force_n - fb.normal_force_n).abs() < tol);
        let qa = rot * Vector3::from(fa.tangential_force_n);
        let qb = Vector3::from(fb.tangential_force_n);
        assert!((qa - qb).norm() < tol, "{}: {qa:?} vs {qb:?}", fa.name);
    }
}
