//! What a schedule may ask of its scene's hands and servos, checked before the first step (the
//! schedule is read against the finger names alone): every scheduled hand is one of the
//! scene's `hands`, no servo's jaw gets a load phase (a servo sets its jaws' forces through its
//! stiffness: they open and close by `approach` phases), and in a planar scene a hand moves in
//! the plane (translations in it, rotations about its normal).

use grasp_model::Scene;

use crate::error::TransferError;
use crate::schedule::{Phase, Schedule};

/// Relative size of an out-of-plane component of a hand's pose above which it is refused.
const IN_PLANE_TOLERANCE: f64 = 1e-12;

/// The first thing `schedule` asks that `scene` cannot do, as an error naming the schedule's
/// field and the fix; `None` when there is none.
pub fn schedule_against_scene(scene: &Scene, schedule: &Schedule) -> Option<TransferError> {
    unknown_hand(scene, schedule)
        .or_else(|| loaded_jaw(scene, schedule))
        .or_else(|| out_of_plane(scene, schedule))
}

fn problem(path: String, message: String, fix: &str) -> Option<TransferError> {
    Some(TransferError::ScheduleAgainstScene {
        path,
        message,
        fix: fix.into(),
    })
}

/// A scheduled hand the scene lacks.
fn unknown_hand(scene: &Scene, schedule: &Schedule) -> Option<TransferError> {
    let known: Vec<&str> = scene.hands.iter().map(|h| h.name.as_str()).collect();
    let (name, _) = schedule
        .hand_poses
        .iter()
        .find(|(n, _)| !known.contains(&n.as_str()))?;
    let fix = match known.is_empty() {
        true => "the scene has no hands: add one under `hands`, or drop it here".to_string(),
        false => format!("use one of: {}", known.join(", ")),
    };
    problem(
        format!("hands.{name}"),
        format!("no hand named `{name}` in the scene"),
        &fix,
    )
}

/// A load phase (`ramp`, `csv`) on a servo's jaw.
fn loaded_jaw(scene: &Scene, schedule: &Schedule) -> Option<TransferError> {
    for servo in &scene.servos {
        for jaw in &servo.fingers {
            let i = scene.fingers.iter().position(|f| &f.name == jaw)?;
            let phases = schedule.phases.get(i)?.as_deref().unwrap_or_default();
            if phases.iter().any(|p| matches!(p, Phase::Ramp { .. })) {
                return problem(
                    format!("fingers.{jaw}"),
                    format!("loads a jaw of servo `{}`, which sets its jaws' forces", servo.name),
                    "move a servo's jaws by `approach` phases (open them past first touch to let go)",
                );
            }
        }
    }
    None
}

/// A hand moved out of a planar scene's plane.
fn out_of_plane(scene: &Scene, schedule: &Schedule) -> Option<TransferError> {
    let p = scene.planar.as_ref()?.normal;
    let norm = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let n = p.map(|c| c / norm);
    for (name, (keys, _)) in &schedule.hand_poses {
        for (k, (_, pose)) in keys.iter().enumerate() {
            let along = n[0] * pose[0] + n[1] * pose[1] + n[2] * pose[2];
            let r = [pose[3], pose[4], pose[5]];
            let about = n[0] * r[0] + n[1] * r[1] + n[2] * r[2];
            let tilt = (0..3)
                .map(|c| (r[c] - about * n[c]).powi(2))
                .sum::<f64>()
                .sqrt();
            let size = pose.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            if along.abs().max(tilt) > IN_PLANE_TOLERANCE * size {
                return problem(
                    format!("hands.{name}.keyframes[{k}]"),
                    "moves the hand out of the planar scene's plane".into(),
                    "give translations in the plane and rotations about its normal only",
                );
            }
        }
    }
    None
}
