//! The closing summary of a hand-off: when the receiving fingers take half and all of the
//! load, the peak squeeze, the smallest slip margin, failed steps, and cost.

use serde::Serialize;

use crate::stepper::StepRecord;

/// A finger carries load when its normal force exceeds this fraction of the load scale.
pub const LOADED_FRACTION: f64 = 1e-6;

/// The summary of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransferSummary {
    /// Steps recorded.
    pub steps: usize,
    /// Failed steps: `(index, time s, reason)`.
    pub failed_steps: Vec<(usize, f64, String)>,
    /// Fingers loaded at the first successful step and unloaded at the last.
    pub releasing: Vec<String>,
    /// Fingers unloaded at the first successful step and loaded at the last.
    pub receiving: Vec<String>,
    /// First time the receiving fingers carry at least as much normal force as the releasing
    /// ones, s.
    pub half_transfer_time_s: Option<f64>,
    /// First time the releasing fingers carry no load, s.
    pub full_transfer_time_s: Option<f64>,
    /// Largest total normal force of all fingers, N, and when, s.
    pub peak_squeeze_n: f64,
    /// Time of the peak squeeze, s.
    pub peak_squeeze_time_s: f64,
    /// Smallest slip margin `1 - |Q|/(mu P)` of a loaded frictional finger: `(margin, time s,
    /// finger)`.
    pub smallest_slip_margin: Option<(f64, f64, String)>,
    /// Largest relative equilibrium residual over the steps.
    pub worst_equilibrium_residual: f64,
    /// Sum of step wall times, s.
    pub total_wall_time_s: f64,
    /// Sum of interior-point iterations.
    pub total_iterations: u64,
    /// Sequential solves (coulomb model, load-dependent mu): totals over the steps.
    pub sequential: Option<SequentialTotals>,
}

/// Totals of the sequential (fixed-point) solves of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SequentialTotals {
    /// Convex solves over all steps.
    pub convex_solves: u64,
    /// Most convex solves in one step.
    pub most_in_a_step: u32,
    /// Steps that started from the previous step's forces.
    pub warm_started_steps: usize,
    /// Warm starts that proved infeasible and restarted cold.
    pub cold_restarts: u32,
}

impl TransferSummary {
    /// Summarises the recorded steps.
    pub fn from_records(records: &[StepRecord], names: &[String]) -> TransferSummary {
        let ok: Vec<&StepRecord> = records
            .iter()
            .filter(|r| r.solution.status.has_forces())
            .collect();
        let loaded = |r: &StepRecord, n: &str| {
            r.normal_force_n(n) > LOADED_FRACTION * r.solution.load_scale_n
        };
        let (mut releasing, mut receiving) = (Vec::new(), Vec::new());
        if let (Some(first), Some(last)) = (ok.first(), ok.last()) {
            for n in names {
                match (loaded(first, n), loaded(last, n)) {
                    (true, false) => releasing.push(n.clone()),
                    (false, true) => receiving.push(n.clone()),
                    _ => {}
                }
            }
        }
        let sum =
            |r: &StepRecord, set: &[String]| set.iter().map(|n| r.normal_force_n(n)).sum::<f64>();
        let half = ok
            .iter()
            .find(|r| {
                !receiving.is_empty()
                    && !releasing.is_empty()
                    && sum(r, &receiving) > 0.0
                    && sum(r, &receiving) >= sum(r, &releasing)
            })
            .map(|r| r.time_s);
        let full = ok
            .iter()
            .find(|r| !releasing.is_empty() && releasing.iter().all(|n| !loaded(r, n)))
            .map(|r| r.time_s);
        let (mut peak, mut peak_t) = (0.0_f64, 0.0);
        let mut margin: Option<(f64, f64, String)> = None;
        let mut worst = 0.0_f64;
        for r in &ok {
            let total: f64 = r.solution.fingers.iter().map(|f| f.normal_force_n).sum();
            if total > peak {
                peak = total;
                peak_t = r.time_s;
            }
            for f in &r.solution.fingers {
                if f.normal_force_n > LOADED_FRACTION * r.solution.load_scale_n
                    && f.friction_utilization > 0.0
                {
                    let m = 1.0 - f.friction_utilization;
                    if margin.as_ref().is_none_or(|x| m < x.0) {
                        margin = Some((m, r.time_s, f.name.clone()));
                    }
                }
            }
            if let Some(res) = &r.solution.residuals {
                worst = worst.max(res.equilibrium_relative);
            }
        }
        TransferSummary {
            steps: records.len(),
            failed_steps: records
                .iter()
                .filter(|r| !r.solution.status.has_forces())
                .map(|r| {
                    (
                        r.index,
                        r.time_s,
                        r.solution.reason.clone().unwrap_or_default(),
                    )
                })
                .collect(),
            releasing,
            receiving,
            half_transfer_time_s: half,
            full_transfer_time_s: full,
            peak_squeeze_n: peak,
            peak_squeeze_time_s: peak_t,
            smallest_slip_margin: margin,
            worst_equilibrium_residual: worst,
            total_wall_time_s: records.iter().map(|r| r.wall_time_s).sum(),
            total_iterations: records
                .iter()
                .map(|r| r.solution.solver.iterations as u64)
                .sum(),
            sequential: sequential_totals(records),
        }
    }
}

fn sequential_totals(records: &[StepRecord]) -> Option<SequentialTotals> {
    let reports: Vec<_> = records
        .iter()
        .filter_map(|r| r.solution.sequential)
        .collect();
    if reports.is_empty() {
        return None;
    }
    Some(SequentialTotals {
        convex_solves: reports.iter().map(|s| s.iterations as u64).sum(),
        most_in_a_step: reports.iter().map(|s| s.iterations).max().unwrap_or(0),
        warm_started_steps: reports.iter().filter(|s| s.warm_started).count(),
        cold_restarts: reports.iter().map(|s| s.cold_restarts).sum(),
    })
}
