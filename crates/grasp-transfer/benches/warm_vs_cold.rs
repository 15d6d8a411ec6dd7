//! Warm versus cold stepping over the plate hand-off (energy model, 200 steps) and the
//! coulomb plate hand-off (121 steps): per-step wall time, interior-point iterations and, for
//! the coulomb model, the convex solves of the sequential loop.
//! Run: `cargo bench -p grasp-transfer --bench warm_vs_cold`.
//!
//! Warm reuses the assembled program and Clarabel's workspace (only `b` is updated; the KKT
//! pattern and its symbolic factorisation are kept). Cold rebuilds the model (compliance
//! blocks), the program and the solver at every step, and starts every sequential solve from an
//! energy-model solve. Clarabel 0.11 has no warm start of the interior-point iterates, so for
//! the energy model iteration counts are equal by construction; for the coulomb model the warm
//! start is the previous step's forces, which saves sequential iterates.

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
    println!("best of 3 runs per mode; iterations: interior-point iterations over all steps; convex solves: sequential iterates over all steps (coulomb)");
    println!(
        "{:<24} {:<6} {:>6} {:>10} {:>14} {:>12} {:>12} {:>12} {:>14}",
        "hand-off",
        "mode",
        "steps",
        "total [s]",
        "mean [ms/step]",
        "median [ms]",
        "p90 [ms]",
        "iterations",
        "convex solves"
    );
    for name in ["plate_transfer", "plate_handoff_coulomb"] {
        let scene = Scene::from_json_str(
            &std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap(),
        )
        .unwrap();
        let names: Vec<String> = scene.fingers.iter().map(|f| f.name.clone()).collect();
        let text = std::fs::read_to_string(dir.join(format!("{name}.schedule.json"))).unwrap();
        let schedule = Schedule::from_json_str(&text, &names, &dir).unwrap();
        for (label, warm) in [("warm", true), ("cold", false)] {
            let mut best: Option<(f64, Vec<f64>, u64, u64)> = None;
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
                let solves: u64 = recs
                    .iter()
                    .map(|r| r.solution.sequential.map_or(1, |s| s.iterations as u64))
                    .sum();
                if best.as_ref().is_none_or(|b| total < b.0) {
                    best = Some((total, times, iters, solves));
                }
            }
            let (total, times, iters, solves) = best.unwrap();
            let steps = times.len();
            let (mean, median, p90) = stats(times);
            println!(
                "{name:<24} {label:<6} {steps:>6} {total:>10.3} {:>14.3} {:>12.3} {:>12.3} {iters:>12} {solves:>14}",
                mean * 1e3,
                median * 1e3,
                p90 * 1e3
            );
        }
    }
}
