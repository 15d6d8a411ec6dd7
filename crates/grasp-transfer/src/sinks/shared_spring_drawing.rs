//! Hands and servos in the Rerun recording (`grasp transfer --rrd` of a scene with `hands` or
//! `servos`): each hand's base in the 3-D view and each one's motion plotted, step by step.
//!
//! - `world/hands/<name>`: an arrow from the hand's origin, its base's translation at true
//!   scale (as a mounted finger's core, `world/fingers/<name>/core`), cleared while none of its
//!   fingers holds the object;
//! - `plots/core/<name>`: how far the base moved (a hand) or its jaws fell short of their
//!   command (a servo), mm, in the view of the cores' moves (0 while released).

use grasp_model::SpringKind;
use rerun::{Arrows3D, Color, Scalars};

use super::sink::RunInfo;
use super::tactile_drawing::Drawing;
use crate::stepper::StepRecord;

/// Colour of a hand's base arrow (dark grey: a motion, not a force).
const HAND_RGB: [u8; 3] = [90, 90, 100];

/// True when the scene has a hand or a servo (the recording's layout then has the cores' plot).
pub fn has_shared_springs(run: &RunInfo) -> bool {
    !run.scene.hands.is_empty() || !run.scene.servos.is_empty()
}

/// The drawings of step `r`: every hand's base arrow, and every hand's and servo's plotted
/// motion.
pub fn shared_spring_drawings(run: &RunInfo, r: &StepRecord) -> Vec<Drawing> {
    let mut out: Vec<Drawing> = Vec::new();
    for spring in run.model.springs() {
        let name = spring.name();
        let SpringKind::Hand { origin_m, .. } = spring.kind() else {
            let travel = r.solution.servos.iter().find(|s| s.name == name);
            let mm = travel.map_or(0.0, |s| s.travel_m.abs() * 1e3);
            out.push((format!("plots/core/{name}"), Box::new(Scalars::new([mm]))));
            continue;
        };
        let hand = r.solution.hands.iter().find(|h| h.name == name);
        let arrow = match hand {
            Some(h) => Arrows3D::from_vectors([h.translation_m.map(|x| x as f32)])
                .with_origins([[origin_m.x as f32, origin_m.y as f32, origin_m.z as f32]])
                .with_colors([Color::from_rgb(HAND_RGB[0], HAND_RGB[1], HAND_RGB[2])])
                .with_labels([name]),
            None => Arrows3D::clear_fields(),
        };
        out.push((format!("world/hands/{name}"), Box::new(arrow)));
        let moved = hand.map_or(0.0, |h| {
            h.translation_m.iter().map(|x| x * x).sum::<f64>().sqrt() * 1e3
        });
        out.push((
            format!("plots/core/{name}"),
            Box::new(Scalars::new([moved])),
        ));
    }
    out
}
