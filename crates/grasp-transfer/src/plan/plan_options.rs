//! What the planner is asked: which fingers let go and which take over, the constraints every
//! step must keep, the objective, and the planner's own limits; each checked, a problem named
//! by its option with the fix.

/// What the plan optimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objective {
    /// The shortest duration that keeps every constraint (needs a load-rate limit: without
    /// one, a quasi-static hand-off has no shortest duration).
    #[default]
    Duration,
    /// The largest smallest slip margin within the given (or the template's) duration.
    Margin,
}

/// The planner's question (forces N, times s, rates N/s).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Fingers that let go: their load ends at 0 N (released at the last step).
    pub releasing: Vec<String>,
    /// Fingers that take over: their load starts at 0 N (not in contact at the first step).
    pub receiving: Vec<String>,
    /// Smallest slip margin `1 - |Q| / (mu P)` at every step, over the fingers carrying at
    /// least 5 % of the load scale (`--min-slip-margin`, in `[0, 1)`).
    pub min_slip_margin: f64,
    /// Smallest disturbance margin at every step, N (`--min-margin`): the smallest, over the
    /// axis directions of force and couple, of the wrench the grasp resists on top of the
    /// step's loads (`grasp transfer --margins`); `None`: not constrained.
    pub min_margin_n: Option<f64>,
    /// Smallest commanded load of a planned finger between its ends, N (`--min-load`).
    pub min_load_n: f64,
    /// Largest commanded load of a planned finger, N (`--max-load`).
    pub max_load_n: f64,
    /// Largest load rate of a planned finger, N/s (`--max-rate`); `None`: no limit.
    pub max_rate_n_per_s: Option<f64>,
    /// Shortest duration, s (`--min-duration`).
    pub min_duration_s: f64,
    /// Longest duration, s (`--max-duration`).
    pub max_duration_s: f64,
    /// The objective (`--objective`).
    pub objective: Objective,
    /// The duration, s (`--duration`): fixed with the margin objective, the first guess with
    /// the duration objective; `None`: the template's, or the shortest the rate allows.
    pub duration_s: Option<f64>,
    /// Steps after the first (`--steps`, 2 to 10,000); `None`: the template's, or 60.
    pub steps: Option<usize>,
    /// Keyframes per finger, the ends included (`--keyframes`, 2 to 20).
    pub keyframes: usize,
    /// Largest number of hand-off runs the planner may make (`--max-runs`), the final check
    /// included.
    pub max_runs: usize,
    /// Options of every solve of the planner's runs.
    pub solve: grasp_model::SolveOptions,
    /// The planner stops when a step's predicted improvement of its merit is below this
    /// (`--plan-tolerance`; the merit is the duration relative to the current one plus 100
    /// times the largest violation of the margin threshold, or minus the smallest margin).
    pub tolerance: f64,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            releasing: Vec::new(),
            receiving: Vec::new(),
            min_slip_margin: 0.0,
            min_margin_n: None,
            min_load_n: 0.0,
            max_load_n: f64::INFINITY,
            max_rate_n_per_s: None,
            min_duration_s: 0.0,
            max_duration_s: f64::INFINITY,
            objective: Objective::Duration,
            duration_s: None,
            steps: None,
            keyframes: 5,
            max_runs: 30,
            solve: grasp_model::SolveOptions::default(),
            tolerance: 1e-4,
        }
    }
}

impl PlanOptions {
    /// Every problem of the options against the scene's finger names, as `(option, problem
    /// and fix)`.
    pub fn problems(&self, finger_names: &[String]) -> Vec<(String, String)> {
        let mut out = self.finger_problems(finger_names);
        out.extend(self.range_problems());
        out
    }

    /// The planned fingers: named in the scene, at least one releasing, none in both lists.
    fn finger_problems(&self, finger_names: &[String]) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let mut say = |o: &str, m: String| out.push((o.to_string(), m));
        for (option, list) in [
            ("releasing", &self.releasing),
            ("receiving", &self.receiving),
        ] {
            for name in list {
                if !finger_names.contains(name) {
                    let known = finger_names.join(", ");
                    say(
                        option,
                        format!("no finger named `{name}` in the scene; use one of: {known}"),
                    );
                }
            }
        }
        if self.releasing.is_empty() {
            say("releasing", "name at least one finger that lets go".into());
        }
        if let Some(both) = self.releasing.iter().find(|n| self.receiving.contains(n)) {
            say(
                "receiving",
                format!("`{both}` is also releasing; a finger is one or the other"),
            );
        }
        out
    }

    /// The numbers: each within its range, and the objective given what it needs.
    fn range_problems(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let mut say = |o: &str, m: String| out.push((o.to_string(), m));
        if !(0.0..1.0).contains(&self.min_slip_margin) {
            say(
                "min-slip-margin",
                format!(
                    "{} is outside [0, 1): 1 - |Q|/(mu P) is below 1",
                    self.min_slip_margin
                ),
            );
        }
        if self
            .min_margin_n
            .is_some_and(|n| !(n > 0.0 && n.is_finite()))
        {
            say(
                "min-margin",
                "must be a positive number of newtons (a disturbance the grasp resists)".into(),
            );
        }
        if !(self.min_load_n >= 0.0 && self.min_load_n < self.max_load_n) {
            say(
                "min-load",
                format!(
                    "needs 0 <= min-load < max-load (got {} and {})",
                    self.min_load_n, self.max_load_n
                ),
            );
        }
        if self
            .max_rate_n_per_s
            .is_some_and(|r| !(r > 0.0 && r.is_finite()))
        {
            say(
                "max-rate",
                "must be a positive number of newtons per second".into(),
            );
        }
        if !(self.min_duration_s >= 0.0 && self.min_duration_s <= self.max_duration_s) {
            say(
                "min-duration",
                "needs 0 <= min-duration <= max-duration".into(),
            );
        }
        if self.objective == Objective::Duration && self.max_rate_n_per_s.is_none() {
            say("objective", "the shortest duration needs a load-rate limit (a quasi-static hand-off is as fast as its rates allow): give --max-rate, or --objective margin".into());
        }
        if self.duration_s.is_some_and(|d| !(d > 0.0 && d <= 1e9)) {
            say(
                "duration",
                "must be a positive number of seconds (at most 1e9)".into(),
            );
        }
        if self.steps.is_some_and(|s| !(2..=10_000).contains(&s)) {
            say("steps", "must be 2 to 10,000".into());
        }
        if !(2..=20).contains(&self.keyframes) {
            say(
                "keyframes",
                format!("{} is outside 2 to 20", self.keyframes),
            );
        }
        if !(2..=1000).contains(&self.max_runs) {
            say(
                "max-runs",
                format!("{} is outside 2 to 1000", self.max_runs),
            );
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            say("plan-tolerance", "must be in (0, 1)".into());
        }
        out
    }
}
