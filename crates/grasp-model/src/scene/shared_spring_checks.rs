//! The checks of `hands` and `servos`: names unique (among fingers too), fingers named in the scene and each on at
//! most one hand and one servo, a hand's stiffness in one form and in range, a servo's jaws
//! position-controlled. Each problem names its JSON path and the fix.

use std::collections::HashSet;

use crate::scene::field_checks::FieldChecks;
use crate::scene::limits::{
    MOUNT_ROTATIONAL_STIFFNESS_RANGE_NM_PER_RAD, MOUNT_STIFFNESS_RANGE_N_PER_M,
};
use crate::scene::mount_checks::check_matrix;
use crate::scene::scene_format::{ControlSpec, Scene};
use crate::scene::shared_spring_spec::HandSpec;

/// The rows of a hand's matrix, as its problems name them.
const HAND_AXES: &str = "x, y, z, rot x, rot y, rot z";

/// Checks `scene.hands` and `scene.servos`.
pub fn check_shared_springs(scene: &Scene, v: &mut FieldChecks) {
    // A finger's name is taken too: the outputs name a hand's curves as a finger's.
    let mut names: HashSet<String> = scene.fingers.iter().map(|f| f.name.clone()).collect();
    let mut on_hand = HashSet::new();
    for (j, h) in scene.hands.iter().enumerate() {
        let p = format!("hands[{j}]");
        check_name(&p, &h.name, &mut names, v);
        check_fingers(scene, &p, &h.fingers, 1, &mut on_hand, v);
        v.point(&format!("{p}.origin_m"), &h.origin_m);
        check_hand_stiffness(&p, h, v);
    }
    let mut on_servo = HashSet::new();
    for (j, s) in scene.servos.iter().enumerate() {
        let p = format!("servos[{j}]");
        check_name(&p, &s.name, &mut names, v);
        check_fingers(scene, &p, &s.fingers, 2, &mut on_servo, v);
        v.range(
            &format!("{p}.stiffness_n_per_m"),
            s.stiffness_n_per_m,
            MOUNT_STIFFNESS_RANGE_N_PER_M,
            "N/m",
            "give the servo's stiffness in N/m",
        );
        check_jaw_controls(scene, &p, &s.fingers, v);
    }
}

/// A nonempty name not used by another hand or servo.
fn check_name(p: &str, name: &str, names: &mut HashSet<String>, v: &mut FieldChecks) {
    if name.trim().is_empty() {
        v.push(&format!("{p}.name"), "is empty".into(), "give a name");
    } else if !names.insert(name.to_string()) {
        v.push(
            &format!("{p}.name"),
            format!("\"{name}\" is used by a finger, or another hand or servo"),
            "give each hand and servo a name of its own",
        );
    }
}

/// At least `least` fingers, each named in the scene and not yet in `taken` (another spring of
/// the same kind, or twice in this one).
fn check_fingers(
    scene: &Scene,
    p: &str,
    fingers: &[String],
    least: usize,
    taken: &mut HashSet<String>,
    v: &mut FieldChecks,
) {
    if fingers.len() < least {
        v.push(
            &format!("{p}.fingers"),
            format!("lists {} finger(s)", fingers.len()),
            &format!("list at least {least} of the scene's fingers"),
        );
    }
    for (k, name) in fingers.iter().enumerate() {
        let path = format!("{p}.fingers[{k}]");
        if !scene.fingers.iter().any(|f| &f.name == name) {
            v.push(
                &path,
                format!("\"{name}\" is not a finger of the scene"),
                "name one of `fingers[..].name`",
            );
        } else if !taken.insert(name.clone()) {
            v.push(
                &path,
                format!("\"{name}\" is already on another one (or listed twice)"),
                "put each finger on at most one hand and at most one servo",
            );
        }
    }
}

/// One form of stiffness, in range.
fn check_hand_stiffness(p: &str, h: &HandSpec, v: &mut FieldChecks) {
    let by_direction = h.translational_n_per_m.is_some() || h.rotational_nm_per_rad.is_some();
    match (&h.matrix, by_direction) {
        (Some(_), true) => v.push(
            p,
            "gives both a matrix and stiffnesses by direction".into(),
            "give either `matrix` or `translational_n_per_m` / `rotational_nm_per_rad`",
        ),
        (None, false) => v.push(
            p,
            "gives no stiffness".into(),
            "give `translational_n_per_m`, `rotational_nm_per_rad` (N/m, N m/rad) or a 6x6 \
             `matrix`; leave the fingers off `hands` for a rigid base",
        ),
        (Some(k), false) => check_matrix(p, k, HAND_AXES, v),
        (None, true) => {
            if let Some(k) = h.translational_n_per_m {
                let path = format!("{p}.translational_n_per_m");
                let fix = "give the stiffness in N/m, or leave it out for a rigid base";
                v.range(&path, k, MOUNT_STIFFNESS_RANGE_N_PER_M, "N/m", fix);
            }
            if let Some(k) = h.rotational_nm_per_rad {
                let path = format!("{p}.rotational_nm_per_rad");
                let fix = "give the stiffness in N m/rad, or leave it out for a rigid base";
                let range = MOUNT_ROTATIONAL_STIFFNESS_RANGE_NM_PER_RAD;
                v.range(&path, k, range, "N m/rad", fix);
            }
        }
    }
}

/// A servo sets its jaws' forces through its stiffness: none of them may prescribe its load.
fn check_jaw_controls(scene: &Scene, p: &str, jaws: &[String], v: &mut FieldChecks) {
    for (k, name) in jaws.iter().enumerate() {
        let Some((i, f)) = scene
            .fingers
            .iter()
            .enumerate()
            .find(|(_, f)| &f.name == name)
        else {
            continue;
        };
        if matches!(f.control, ControlSpec::Load(_)) {
            v.push(
                &format!("{p}.fingers[{k}]"),
                format!("\"{name}\" has its normal load prescribed (fingers[{i}].control)"),
                "drive a servo's jaws by `approach_m` (the commanded travel) or `held`",
            );
        }
    }
}
