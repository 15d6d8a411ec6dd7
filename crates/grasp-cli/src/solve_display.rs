//! The display of one long solve on a terminal: a spinner with the phase (building the
//! influence spectra, then the Newton steps and conjugate-gradient iterations so far), the
//! elapsed time and an estimate of the whole, redrawn by its own thread from the counters the
//! solver stores (`grasp_model::SolveProgress`); nothing off a terminal or with `--quiet`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use grasp_model::SolveProgress;
use indicatif::ProgressBar;

/// Solves of more unknowns than this show the display (about a second and more on two cores:
/// a 256 x 256 frictionless patch).
pub const LONG_SOLVE_UNKNOWNS: usize = 65_536;

/// Seconds a solve of a million unknowns takes on two cores, model included: the README's
/// fine-patch figures (1024 x 1024 frictionless: model 0.9 s, solve 3.3-3.6 s).
const SECONDS_PER_MILLION_UNKNOWNS: f64 = 4.5;

/// Newton steps a fine patch's solve usually takes (the Hertz patches: 5), for the estimate
/// once the first steps are timed.
const USUAL_NEWTON_STEPS: u32 = 5;

/// A long solve's display.
pub struct SolveDisplay {
    bar: ProgressBar,
    unknowns: usize,
    /// When the model's build began.
    started: Instant,
    progress: Arc<SolveProgress>,
    stop: Arc<AtomicBool>,
    redraw: Option<JoinHandle<()>>,
}

impl SolveDisplay {
    /// The display of a solve of `unknowns` unknowns on `grid` (its largest patch, for the
    /// phase's text), or `None` for a short one.
    pub fn start(unknowns: usize, grid: [usize; 2]) -> Option<SolveDisplay> {
        if unknowns <= LONG_SOLVE_UNKNOWNS {
            return None;
        }
        let phase = format!(
            "building the influence spectra of {} x {}",
            grid[0], grid[1]
        );
        let display = SolveDisplay {
            bar: crate::progress::spinner(&message(&phase, unknowns, None)),
            unknowns,
            started: Instant::now(),
            progress: Arc::new(SolveProgress::new()),
            stop: Arc::new(AtomicBool::new(false)),
            redraw: None,
        };
        Some(display)
    }

    /// The counters the solver is to store its work in.
    pub fn progress(&self) -> Arc<SolveProgress> {
        Arc::clone(&self.progress)
    }

    /// The model is built: from now on the solve's counts, ten times a second (on a drawn
    /// bar, when a thread can be started for it: under an address-space limit it may not, and
    /// the solve goes on without).
    pub fn solving(&mut self) {
        if self.bar.is_hidden() {
            return;
        }
        let (bar, progress, stop) = (self.bar.clone(), self.progress(), Arc::clone(&self.stop));
        let (unknowns, started) = (self.unknowns, self.started);
        self.redraw = std::thread::Builder::new()
            .spawn(move || {
                // When each Newton step was seen to end: its pace, after the first (the cold
                // start's, which also prepares the solver).
                let mut ends: Vec<Instant> = Vec::new();
                while !stop.load(Ordering::Relaxed) {
                    let steps = progress.newton_steps();
                    let done = steps.saturating_sub(1);
                    while ends.len() < done as usize {
                        ends.push(Instant::now());
                    }
                    let pace = match ends.as_slice() {
                        [first, .., last] => {
                            Some((*last - *first).as_secs_f64() / (ends.len() - 1) as f64)
                        }
                        _ => None,
                    };
                    let timed = pace.map(|per_step_s| Pace {
                        elapsed_s: started.elapsed().as_secs_f64(),
                        per_step_s,
                        steps_done: done,
                    });
                    let phase = format!(
                        "{unknowns} unknowns: Newton step {}, {} CG iterations",
                        steps.max(1),
                        progress.cg_iterations()
                    );
                    bar.set_message(message(&phase, unknowns, timed));
                    std::thread::sleep(Duration::from_millis(100));
                }
            })
            .ok();
    }
}

/// Dropping the display (after the solve, or on an error) stops its thread and clears it.
impl Drop for SolveDisplay {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.redraw.take() {
            let _ = t.join();
        }
        self.bar.finish_and_clear();
    }
}

/// How a solve has gone so far: seconds since the model's build began, seconds a Newton step
/// takes (after the first), Newton steps finished.
#[derive(Debug, Clone, Copy)]
struct Pace {
    elapsed_s: f64,
    per_step_s: f64,
    steps_done: u32,
}

/// `phase` and the estimate of the whole run of `unknowns` unknowns: from the size until two
/// Newton steps after the first are timed, then the time so far and the steps' pace (`timed`)
/// times the steps left of the usual count (at least one).
fn message(phase: &str, unknowns: usize, timed: Option<Pace>) -> String {
    let total_s = match timed {
        None => {
            let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as f64;
            let millions = unknowns as f64 / (1u64 << 20) as f64;
            SECONDS_PER_MILLION_UNKNOWNS * millions * (2.0 / threads).powf(0.6)
        }
        Some(p) => {
            let left = USUAL_NEWTON_STEPS.saturating_sub(p.steps_done).max(1);
            p.elapsed_s + p.per_step_s * f64::from(left)
        }
    };
    format!("{phase}; about {} in all", seconds(total_s))
}

/// `s` seconds as a person reads an estimate: `3 s`, `40 s`, `2 min`.
fn seconds(s: f64) -> String {
    match s {
        s if s < 90.0 => format!("{:.0} s", s.max(1.0)),
        s => format!("{:.0} min", s / 60.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The estimate before steps are timed follows the size (a million unknowns: the README's
    /// 4.5 s on two cores, scaled for this machine's cores); after, the time so far plus the
    /// steps' pace times the steps left of the usual count, or one more step.
    #[test]
    fn estimates_come_from_the_size_then_from_the_steps() {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as f64;
        let want = 4.5 * (2.0 / threads).powf(0.6);
        let m = message("p", 1 << 20, None);
        assert_eq!(m, format!("p; about {} in all", seconds(want)));
        let pace = |elapsed_s, steps_done| Pace {
            elapsed_s,
            per_step_s: 1.5,
            steps_done,
        };
        // 3 of the usual 5 steps done at 1.5 s each after 4 s: 4 + 3 s.
        assert_eq!(message("p", 1, Some(pace(4.0, 3))), "p; about 7 s in all");
        // More steps than usual: one more.
        assert_eq!(message("p", 1, Some(pace(8.0, 8))), "p; about 10 s in all");
        assert_eq!(seconds(0.2), "1 s");
        assert_eq!(seconds(600.0), "10 min");
    }
}
