//! Planning a hand-off's ramps: the keyframed loads (or, for jaws on a position servo, the
//! keyframed approaches) of the releasing and receiving fingers that keep every step's slip
//! margin (and, on request, its disturbance margin) above a threshold, within bounds and
//! rate limits (N/s, m/s), in the shortest duration (or with the largest smallest margin),
//! found by a trust-region sequence of quadratic programs on the sensitivities of every step.

pub mod binding_reason;
pub mod disturbance_rows;
pub mod keyframe_path;
pub mod margin_row;
pub mod option_names;
pub mod plan_error;
pub mod plan_options;
pub mod plan_report;
pub mod planned_group;
pub mod planner;
pub mod slip_rows;
pub mod start_diagnosis;
pub mod starting_commands;
pub mod starting_path;
pub mod trust_region_qp;

pub use keyframe_path::KeyframePath;
pub use plan_error::PlanError;
pub use plan_options::{Objective, PlanOptions};
pub use plan_report::{
    Binding, CheckedAt, MarginsAtStep, PlanReport, DISTURBANCE_TOLERANCE, FINE_STEPS,
    MARGIN_TOLERANCE,
};
pub use planner::plan;
pub use starting_path::Template;
