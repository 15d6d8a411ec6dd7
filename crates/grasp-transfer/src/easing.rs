//! Easing curves between keyframes: `s(u)` for `u in [0, 1]`, with `s(0) = 0`, `s(1) = 1`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// How a load moves from one keyframe to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema, Default)]
#[serde(rename_all = "lowercase")]
pub enum Easing {
    /// Hold the earlier keyframe's value until the next keyframe's time.
    Step,
    /// Straight line.
    #[default]
    Linear,
    /// `3u^2 - 2u^3`: zero slope at both ends.
    Smoothstep,
    /// `(1 - cos(pi u)) / 2`: zero slope at both ends.
    Cosine,
}

impl Easing {
    /// `s(u)`, with `u` clamped to `[0, 1]`.
    pub fn apply(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        match self {
            Easing::Step => {
                if u >= 1.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Easing::Linear => u,
            Easing::Smoothstep => u * u * (3.0 - 2.0 * u),
            Easing::Cosine => 0.5 * (1.0 - (std::f64::consts::PI * u).cos()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn easings_are_monotone_from_zero_to_one() {
        for e in [
            Easing::Step,
            Easing::Linear,
            Easing::Smoothstep,
            Easing::Cosine,
        ] {
            assert_eq!(e.apply(0.0), 0.0);
            assert!((e.apply(1.0) - 1.0).abs() < 1e-15);
            let mut last = 0.0;
            for i in 0..=100 {
                let s = e.apply(i as f64 / 100.0);
                assert!(s >= last - 1e-15, "{e:?} not monotone");
                last = s;
            }
        }
        assert!((Easing::Smoothstep.apply(0.5) - 0.5).abs() < 1e-15);
        assert!((Easing::Cosine.apply(0.5) - 0.5).abs() < 1e-15);
    }
}
