//! A group of planned fingers moved by one variable (a gripper's jaws), and what that variable
//! commands: the members' normal loads (force control; the thesis's load ramps, section
//! 4.2.2), or their approaches (position control: a servo's jaws opened to let go, or closed
//! to take over).
//!
//! The planner's program is written in one unit: an approach group's variable is its
//! members' approach measured from a reference and multiplied by a fixed stiffness-like scale
//! `c` (N/m), chosen when the plan starts so that the group's travel is of the order of the
//! loads planned beside it ([`Commanded::Approach`]). The scale only conditions the program:
//! every bound, rate and schedule value is converted back to metres exactly.

/// What a group's variable commands.
#[derive(Debug, Clone, PartialEq)]
pub enum Commanded {
    /// Each member's normal load, N: its share times the variable.
    Load,
    /// Each member's approach, m: `reference_m + share * variable / newtons_per_metre`.
    Approach {
        /// The scale `c` of the variable, N/m (see the module).
        newtons_per_metre: f64,
        /// Per member, its approach where the variable is 0, m (a releasing group's end, a
        /// receiving group's start).
        reference_m: Vec<f64>,
        /// The approaches every member keeps within, `(smallest, largest)`, m.
        range_m: (f64, f64),
    },
}

/// The largest rate of each kind of command, as the options give them (`None`: no limit).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RateLimits {
    /// Largest load rate of a force-controlled finger, N/s.
    pub load_n_per_s: Option<f64>,
    /// Largest approach speed of a position-controlled finger, m/s.
    pub speed_m_per_s: Option<f64>,
}

/// Fingers moved together by one variable: each member by its share of it.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedGroup {
    /// `releasing` or `receiving`.
    pub name: String,
    /// `(finger, share)`.
    pub members: Vec<(String, f64)>,
    /// What the variable commands.
    pub commanded: Commanded,
}

impl PlannedGroup {
    /// The largest share.
    pub fn largest_share(&self) -> f64 {
        self.members.iter().fold(0.0, |a, m| a.max(m.1))
    }

    /// The smallest share.
    pub fn smallest_share(&self) -> f64 {
        self.members.iter().fold(f64::INFINITY, |a, m| a.min(m.1))
    }

    /// True when the group commands approaches.
    pub fn is_approach(&self) -> bool {
        matches!(self.commanded, Commanded::Approach { .. })
    }

    /// Member `m`'s command at the variable's value `x`: a load (N) or an approach (m).
    pub fn member_value(&self, m: usize, x: f64) -> f64 {
        let share = self.members[m].1;
        match &self.commanded {
            Commanded::Load => share * x,
            Commanded::Approach {
                newtons_per_metre,
                reference_m,
                ..
            } => reference_m[m] + share * x / newtons_per_metre,
        }
    }

    /// The rate limit of the variable, its units per second, so that no member's command
    /// changes faster than its own limit; `None` without a limit of the group's kind.
    pub fn variable_rate(&self, limits: &RateLimits) -> Option<f64> {
        let share = self.largest_share();
        match &self.commanded {
            Commanded::Load => limits.load_n_per_s.map(|r| r / share),
            Commanded::Approach {
                newtons_per_metre, ..
            } => limits.speed_m_per_s.map(|v| v * newtons_per_metre / share),
        }
    }

    /// The variable's bounds `(largest, smallest)` that keep every member's command within
    /// `min_load_n` to `max_load_n` (a load group, N) or within the group's range of
    /// approaches.
    pub fn bounds(&self, min_load_n: f64, max_load_n: f64) -> (f64, f64) {
        match &self.commanded {
            Commanded::Load => (
                max_load_n / self.largest_share(),
                min_load_n / self.smallest_share(),
            ),
            Commanded::Approach {
                newtons_per_metre: c,
                reference_m,
                range_m,
            } => {
                let each = self.members.iter().zip(reference_m);
                each.fold((f64::INFINITY, f64::NEG_INFINITY), |(hi, lo), (m, r)| {
                    (
                        hi.min((range_m.1 - r) * c / m.1),
                        lo.max((range_m.0 - r) * c / m.1),
                    )
                })
            }
        }
    }

    /// The unit of the members' commands, for reports: `N` or `m`.
    pub fn unit(&self) -> &'static str {
        if self.is_approach() {
            "m"
        } else {
            "N"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jaws() -> PlannedGroup {
        PlannedGroup {
            name: "releasing".into(),
            members: vec![("a".into(), 1.0), ("b".into(), 0.5)],
            commanded: Commanded::Approach {
                newtons_per_metre: 1000.0,
                reference_m: vec![-0.001, 0.0],
                range_m: (-0.001, 0.004),
            },
        }
    }

    /// The variable maps to each member's approach through its reference and share, and the
    /// bounds and the rate are the tightest member's, in the variable's units.
    #[test]
    fn an_approach_group_converts_exactly_to_metres() {
        let g = jaws();
        assert_eq!(g.member_value(0, 5.0), -0.001 + 0.005);
        assert_eq!(g.member_value(1, 5.0), 0.0025);
        let (hi, lo) = g.bounds(0.0, f64::INFINITY);
        // a: (0.004 + 0.001) * 1000 / 1 = 5; b: 0.004 * 1000 / 0.5 = 8; the smaller binds.
        assert!((hi - 5.0).abs() < 1e-12, "{hi}");
        // a: 0; b: -0.001 * 1000 / 0.5 = -2; the larger binds.
        assert!(lo.abs() < 1e-12, "{lo}");
        let limits = RateLimits {
            load_n_per_s: Some(1.0),
            speed_m_per_s: Some(0.002),
        };
        assert!((g.variable_rate(&limits).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(g.unit(), "m");
    }
}
