//! Warm versus cold stepping over the plate hand-off (200 steps): per-step wall time.
//! Run: `cargo bench -p grasp-transfer --bench warm_vs_cold`.
//!
//! Warm reuses the assembled program and Clarabel's workspace (only `b` is updated; the KKT
//! pattern and its symbolic factorisation are kept). Cold rebuilds the model (compliance
//! blocks), the program and the solver at every step. Clarabel 0.11 has no warm start of the
//! interior-point iterates, so iteration counts are equal by construction.

use std::path::Path;

use grasp_model::Scene;
use grasp_transfer::{Schedule, Stepper, TransferOptions};

fn stats(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    (mean, v[v.len() / 2], v[(v.len() * 9) / 10])
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let scene =
        Scene::from_json_str(&std::fs::read_to_string(dir.join("plate_transfer.json")).unwrap())
            .unwrap();
    let names: Vec<String> = scene.fingers.iter().map(|f| f.name.clone()).collect();
    let text = std::fs::read_to_string(dir.join("plate_transfer.schedule.json")).unwrap();
    let schedule = Schedule::from_json_str(&text, &names, &dir).unwrap();
    println!(
        "plate hand-off, {} steps, best of 3 runs per mode",
        schedule.times.len()
    );
    println!(
        "{:<6} {:>10} {:>14} {:>14} {:>14} {:>12}",
        "mode", "total [s]", "mean [ms/step]", "median [ms]", "p90 [ms]", "iterations"
    );
    for (label, warm) in [("warm", true), ("cold", false)] {
        let mut best: Option<(f64, Vec<f64>, u64)> = None;
        for _ in 0..3 {
            let opts = TransferOptions {
                warm_start: warm,
                ..TransferOptions::default()
            };
            let recs: Vec<_> = Stepper::new(&scene, &schedule, opts)
                .map(|r| r.unwrap())
                .collect();
            let times: Vec<f64> = recs.iter().map(|r| r.wall_time_s).collect();
            let total: f64 = times.iter().sum();
            let iters: u64 = recs
                .iter()
                .map(|r| r.solution.solver.iterations as u64)
                .sum();
            if best.as_ref().is_none_or(|b| total < b.0) {
                best = Some((total, times, iters));
            }
        }
        let (total, times, iters) = best.unwrap();
        let (mean, median, p90) = stats(times);
        println!(
            "{label:<6} {total:>10.3} {:>14.3} {:>14.3} {:>14.3} {iters:>12}",
            mean * 1e3,
            median * 1e3,
            p90 * 1e3
        );
    }
}
