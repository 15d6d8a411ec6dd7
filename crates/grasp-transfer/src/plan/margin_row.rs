//! One linearised constraint of the planner: a margin at one step, with its derivatives in
//! the planner's variables (the keyframe loads and the duration). Two kinds: a finger's slip
//! margin `1 - |Q| / (mu P)` (dimensionless, kept at least `--min-slip-margin`), and the step's
//! smallest disturbance margin divided by `--min-margin` (kept at least 1).

/// What a row constrains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// A finger's slip margin `1 - |Q| / (mu P)`.
    Slip,
    /// The step's smallest disturbance margin over the axis directions
    /// ([`crate::step_margin`]), divided by the threshold `--min-margin` (N): 1 at the
    /// threshold.
    Disturbance,
}

/// One margin at one step, with its gradient.
#[derive(Debug, Clone, PartialEq)]
pub struct MarginRow {
    /// What it constrains.
    pub kind: RowKind,
    /// Step index.
    pub step: usize,
    /// Schedule time, s.
    pub time_s: f64,
    /// The finger: the one whose slip margin it is, or the one that fails first along the
    /// disturbance (empty when none is named).
    pub finger: String,
    /// The margin (see [`RowKind`]; dimensionless either way).
    pub margin: f64,
    /// `dm / dx` over the path's keyframe loads, `x[g * K + k]` for group `g` and keyframe
    /// `k`, per N.
    pub gradient: Vec<f64>,
    /// `dm / dT` (duration, per s): nonzero only where time matters (viscoelastic pads),
    /// filled by a difference of two runs.
    pub per_duration: f64,
}
