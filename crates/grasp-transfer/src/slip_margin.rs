//! The slip-margin rule of every hand-off report: which fingers a step's smallest slip margin
//! `1 - |Q| / (mu P)` counts (a frictional finger whose contact force is at least 5 % of the
//! load scale), the one rule of `grasp transfer`'s summary and of `grasp plan`'s constraint,
//! and the fingers it leaves out (a finger letting go, or just touching, may slide).

use grasp_model::{FingerSolution, Solution, LOADED_FRACTION};

/// A finger counts in the smallest slip margin of a step while its contact force (normal and
/// friction together) is at least this fraction of the step's load scale: a finger letting go
/// may slide as it leaves, and one just touching may slide before it carries anything.
pub const CARRYING_FRACTION: f64 = 0.05;

/// The rule in words, as the reports state it beside the figure (the text summaries, the JSON
/// reports).
pub const SLIP_MARGIN_RULE: &str = "1 - |Q|/(mu P), smallest over the frictional fingers \
    whose contact force (normal and friction together) is at least 5 % of the load scale; a \
    lighter finger (letting go, or just touching) is not counted";

/// True when finger `f` of a solution counts at its step: frictional, pressed, and carrying at
/// least [`CARRYING_FRACTION`] of the load scale (N).
pub fn carrying(f: &FingerSolution, load_scale_n: f64) -> bool {
    f.friction_coefficient > 0.0
        && f.normal_force_n > 0.0
        && contact_force_n(f) >= CARRYING_FRACTION * load_scale_n
}

/// A finger's slip margin `1 - |Q| / (mu P)`: 0 at the friction limit, 1 with no friction force.
pub fn slip_margin(f: &FingerSolution) -> f64 {
    1.0 - f.friction_utilization
}

/// A finger's slip margin at a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerSlipMargin<'a> {
    /// `1 - |Q| / (mu P)`.
    pub margin: f64,
    /// The finger.
    pub finger: &'a str,
}

/// The smallest slip margins of one step: over the fingers the rule counts, and over the loaded
/// frictional fingers it leaves out.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepSlipMargins<'a> {
    /// The smallest over the counted fingers; `None` when none counts (or the step found no
    /// forces).
    pub counted: Option<FingerSlipMargin<'a>>,
    /// The smallest over the fingers left out: frictional, loaded (normal force above
    /// [`LOADED_FRACTION`] of the load scale) but below [`CARRYING_FRACTION`] of it.
    pub not_counted: Option<FingerSlipMargin<'a>>,
}

/// The smallest slip margins of a step's solution (see [`StepSlipMargins`]).
pub fn step_slip_margins(sol: &Solution) -> StepSlipMargins<'_> {
    let mut out = StepSlipMargins::default();
    if !sol.status.has_forces() {
        return out;
    }
    for f in &sol.fingers {
        let m = slip_margin(f);
        let slot = if carrying(f, sol.load_scale_n) {
            &mut out.counted
        } else if f.friction_coefficient > 0.0
            && f.normal_force_n > LOADED_FRACTION * sol.load_scale_n
        {
            &mut out.not_counted
        } else {
            continue;
        };
        if slot.is_none_or(|s| m < s.margin) {
            *slot = Some(FingerSlipMargin {
                margin: m,
                finger: f.name.as_str(),
            });
        }
    }
    out
}

/// The magnitude of a finger's contact force, normal and friction together, N.
fn contact_force_n(f: &FingerSolution) -> f64 {
    let q = f.tangential_force_n;
    (f.normal_force_n.powi(2) + q.iter().map(|c| c * c).sum::<f64>()).sqrt()
}
