//! The one colour key of every output: the element states and the force arrows, the same in
//! the Rerun recording (3-D view and patch views), the Foxglove scene and the `grasp plot`
//! pictures (docs/guide/outputs.md, "Colour key").

use grasp_model::ElementState;

/// Normal force arrows: blue, RGB.
pub const NORMAL_FORCE_RGB: [u8; 3] = [31, 100, 200];

/// Friction force arrows: orange, RGB.
pub const FRICTION_FORCE_RGB: [u8; 3] = [240, 140, 20];

/// The colour of an element state, RGB: stick green, slip orange, separated grey, in contact on
/// a frictionless finger violet, off the surface near-black.
pub fn state_rgb(s: ElementState) -> [u8; 3] {
    match s {
        ElementState::Stick => [60, 180, 75],
        ElementState::Slip => [245, 130, 48],
        ElementState::Separated => [128, 128, 128],
        ElementState::OffSurface => [40, 40, 48],
        ElementState::Frictionless => [145, 90, 200],
    }
}

/// The state colours in words, as the views and the guide state them.
pub const STATE_KEY: &str = "green = stick, orange = slip, grey = separated, violet = in \
                             contact without friction (a frictionless finger), near-black = \
                             off the surface";

/// The force colours in words.
pub const FORCE_KEY: &str = "blue = normal force, orange = friction force";

/// A colour as Foxglove's `{r, g, b}` fractions in [0, 1].
pub fn unit_rgb(rgb: [u8; 3]) -> [f64; 3] {
    rgb.map(|c| f64::from(c) / 255.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every state has its own colour, and none is a force arrow's.
    #[test]
    fn each_state_has_its_own_colour() {
        use ElementState::*;
        let all = [Stick, Slip, Separated, OffSurface, Frictionless].map(state_rgb);
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert_ne!(a, b);
            }
            assert_ne!(*a, NORMAL_FORCE_RGB);
            assert_ne!(*a, FRICTION_FORCE_RGB);
        }
    }
}
