//! The first input of a margin trial's Tresca iteration (the coulomb model's sequential solve,
//! `crate::solve::sequential`): the element normal forces of the direction's last solved
//! trials, extrapolated in the magnitude.
//!
//! A trial is a quasi-static step from a start state whose slip memory sets the answer; the
//! state's last forces only start the fixed-point iteration `F <- T(F)`, whose iterates converge
//! linearly. The start state's forces are those at the magnitude it held (the step's
//! undisturbed state: none at all), while the direction's last trials were solved at
//! magnitudes near the one tried now: at the last step's margin when a step's search begins,
//! one bracket end away during a check, a walk or a bisection. While no element changes
//! between stick, slip and separation, the fixed point is affine in the magnitude (each Tresca
//! program's solution is affine in its data, the radii affine in the forces), so the line
//! through the last two trials' forces, evaluated at the new magnitude, is the fixed point
//! itself; otherwise a guess closer than either. Only where the iteration starts changes, not
//! the fixed point it converges to.

/// Largest extrapolation, in multiples of the distance between the two trials the line goes
/// through: beyond it the line's slope says little and the last forces alone are taken.
const LONGEST_REACH: f64 = 10.0;

/// The element normal forces (N, per finger) of the last two trials solved along a direction,
/// with their magnitudes (N), newest last.
#[derive(Debug, Clone, Default)]
pub(crate) struct TrialForces {
    points: Vec<(f64, Vec<Vec<f64>>)>,
}

impl TrialForces {
    /// Records the forces `forces_n` solved at magnitude `s_n`.
    pub(crate) fn push(&mut self, s_n: f64, forces_n: Vec<Vec<f64>>) {
        if self.points.len() == 2 {
            self.points.remove(0);
        }
        self.points.push((s_n, forces_n));
    }

    /// The forces to start a trial at magnitude `s_n` from: the line through the last two
    /// trials' forces at `s_n` (clipped at zero), the last trial's when the two are at the same
    /// magnitude, differ in layout, or `s_n` lies beyond [`LONGEST_REACH`] of them; `None`
    /// before any trial.
    pub(crate) fn at(&self, s_n: f64) -> Option<Vec<Vec<f64>>> {
        let (s1, f1) = self.points.last()?;
        let line = match self.points.as_slice() {
            [(s0, f0), _] if same_layout(f0, f1) => {
                let gap = s1 - s0;
                let reach = (s_n - s1) / gap;
                (gap != 0.0 && reach.abs() <= LONGEST_REACH).then_some((f0, reach))
            }
            _ => None,
        };
        let Some((f0, reach)) = line else {
            return Some(f1.clone());
        };
        let extrapolate = |(a, b): (&Vec<f64>, &Vec<f64>)| -> Vec<f64> {
            let pair = a.iter().zip(b);
            pair.map(|(x0, x1)| (x1 + reach * (x1 - x0)).max(0.0))
                .collect()
        };
        Some(f0.iter().zip(f1).map(extrapolate).collect())
    }
}

fn same_layout(a: &[Vec<f64>], b: &[Vec<f64>]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.len() == y.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forces_affine_in_the_magnitude_are_extrapolated_exactly() {
        let f = |s: f64| vec![vec![1.0 + 0.5 * s, 2.0 - 0.25 * s], vec![3.0 * s]];
        let mut t = TrialForces::default();
        assert!(t.at(1.0).is_none());
        t.push(1.0, f(1.0));
        assert_eq!(t.at(2.0), Some(f(1.0)), "one point: its forces");
        t.push(1.5, f(1.5));
        for s in [1.2, 1.5, 2.0, 4.0] {
            let g = t.at(s).unwrap();
            for (a, b) in g.iter().flatten().zip(f(s).iter().flatten()) {
                assert!((a - b).abs() < 1e-12, "at {s}: {g:?}");
            }
        }
    }

    #[test]
    fn far_reaches_equal_magnitudes_and_other_layouts_take_the_last_forces() {
        let mut t = TrialForces::default();
        t.push(1.0, vec![vec![1.0, 1.0]]);
        t.push(1.1, vec![vec![2.0, 0.5]]);
        assert_eq!(t.at(3.0), Some(vec![vec![2.0, 0.5]]), "19 gaps away");
        // Within reach the line is clipped at zero.
        assert_eq!(t.at(1.3).unwrap()[0][1], 0.0);
        t.push(1.1, vec![vec![3.0, 0.5]]);
        assert_eq!(t.at(1.2), Some(vec![vec![3.0, 0.5]]), "same magnitude");
        t.push(1.2, vec![vec![3.0], vec![1.0]]);
        assert_eq!(
            t.at(1.3),
            Some(vec![vec![3.0], vec![1.0]]),
            "another layout"
        );
    }
}
