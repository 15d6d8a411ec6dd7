//! A validated load schedule, evaluated in time: the command of every finger and the external
//! wrench at each step (ramps eased between their keyframes, holds keeping the phase before's
//! last command, `"current"` resolved to the load a finger carried when its phase began).
//! Built from the file ([`crate::schedule_spec`]) by [`crate::schedule_builder`].

use grasp_io::RunInputs;
use serde::{Deserialize, Serialize};

use crate::easing::Easing;

/// What a finger is told to do at one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Command {
    /// Position-held.
    Held,
    /// Prescribed normal load, N (> 0).
    Load(f64),
    /// Load zero: out of the problem.
    Released,
    /// Pressed in by a prescribed approach from first touch, m (negative: withdrawn); its
    /// load is found by the model.
    Approach(f64),
}

impl Command {
    /// How the commanded finger is driven in the step's grasp (`None`: released, out of it).
    pub fn control(&self) -> Option<grasp_model::Control> {
        use grasp_model::Control;
        match *self {
            Command::Held => Some(Control::Held),
            Command::Load(p) => Some(Control::NormalLoad { newtons: p }),
            Command::Approach(d) => Some(Control::Approach { metres: d }),
            Command::Released => None,
        }
    }
}

/// A validated phase with resolved keyframes.
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// Held until the time (inclusive), or forever.
    Held {
        /// End, s.
        until: Option<f64>,
    },
    /// Load keyframes; `None` values are `"current"`.
    Ramp {
        /// `(time s, load N or current)`.
        keyframes: Vec<(f64, Option<f64>)>,
        /// Interpolation.
        easing: Easing,
    },
    /// Approach keyframes.
    Approach {
        /// `(time s, approach m)`.
        keyframes: Vec<(f64, f64)>,
        /// Interpolation.
        easing: Easing,
    },
    /// The phase before's last command (or the scene's control), until the time.
    Hold {
        /// End, s.
        until: f64,
    },
}

impl Phase {
    /// When the phase ends, s (`None`: it lasts forever).
    pub(crate) fn end(&self) -> Option<f64> {
        match self {
            Phase::Held { until } => *until,
            Phase::Ramp { keyframes, .. } => keyframes.last().map(|k| k.0),
            Phase::Approach { keyframes, .. } => keyframes.last().map(|k| k.0),
            Phase::Hold { until } => Some(*until),
        }
    }
}

/// A validated schedule, ready to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// Step times, s.
    pub times: Vec<f64>,
    /// Per scene finger (scene order): its phases, or `None` to keep the scene's control.
    pub phases: Vec<Option<Vec<Phase>>>,
    /// The ramped external wrench, if any.
    pub external: Option<ExternalRamp>,
    /// Per scheduled hand, by name: its pose ramp (keyframes `(time s, [m; rad])`, easing).
    pub hand_poses: Vec<(String, ExternalRamp)>,
    /// The CSV files read (no output of a run may replace one of them).
    pub input_files: RunInputs,
}

/// The scheduled external wrench at one time (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExternalWrench {
    /// Force at the centre of mass, N.
    pub force_n: [f64; 3],
    /// Couple, N m.
    pub torque_nm: [f64; 3],
}

/// A validated external wrench ramp: keyframes `(time s, [force N; couple N m])` and easing.
pub type ExternalRamp = (Vec<(f64, [f64; 6])>, Easing);

impl Schedule {
    /// The scheduled external wrench at time `t`; `None` when the schedule has none.
    pub fn external_at(&self, t: f64) -> Option<ExternalWrench> {
        let (keys, easing) = self.external.as_ref()?;
        let mut w = [0.0; 6];
        for (c, wc) in w.iter_mut().enumerate() {
            let comp: Vec<(f64, Option<f64>)> = keys.iter().map(|k| (k.0, Some(k.1[c]))).collect();
            *wc = ramp_load(&comp, *easing, t, 0.0);
        }
        Some(ExternalWrench {
            force_n: [w[0], w[1], w[2]],
            torque_nm: [w[3], w[4], w[5]],
        })
    }

    /// Each scheduled hand's commanded pose at time `t`, by name: `[dx, dy, dz]` m, then a small
    /// rotation `[rx, ry, rz]` rad about the hand's origin (world frame).
    pub fn hand_poses_at(&self, t: f64) -> Vec<(&str, [f64; 6])> {
        self.hand_poses
            .iter()
            .map(|(name, (keys, easing))| {
                let mut pose = [0.0; 6];
                for (c, pc) in pose.iter_mut().enumerate() {
                    let comp: Vec<(f64, Option<f64>)> =
                        keys.iter().map(|k| (k.0, Some(k.1[c]))).collect();
                    *pc = ramp_load(&comp, *easing, t, 0.0);
                }
                (name.as_str(), pose)
            })
            .collect()
    }

    /// The largest force or couple component of the scheduled external wrench (N or N m; 0
    /// without one).
    pub fn external_scale(&self) -> f64 {
        self.external.as_ref().map_or(0.0, |(keys, _)| {
            keys.iter()
                .flat_map(|k| k.1.iter())
                .fold(0.0_f64, |a, v| a.max(v.abs()))
        })
    }

    /// Index of the phase of finger `i` active at time `t` (the first whose end is >= t;
    /// the last phase after every end), or `None` if the finger is unscheduled.
    pub fn phase_index(&self, i: usize, t: f64) -> Option<usize> {
        let list = self.phases.get(i)?.as_ref()?;
        let last = list.len().checked_sub(1)?;
        Some(
            list.iter()
                .position(|p| p.end().is_none_or(|e| t <= e + 1e-9 * e.abs().max(1.0)))
                .unwrap_or(last),
        )
    }

    /// The command for finger `i` at time `t`, given the resolved value of `"current"` for its
    /// active phase (N) and the scene's own command (for unscheduled fingers).
    pub fn command(&self, i: usize, t: f64, current_n: f64, scene: Command) -> Command {
        match self.phase_index(i, t) {
            None => scene,
            Some(p) => self.phase_command(i, p, t, current_n, scene),
        }
    }

    /// The command of phase `p` of finger `i` at time `t` (a hold: the phase before's at its
    /// end, or the scene's).
    fn phase_command(&self, i: usize, p: usize, t: f64, current_n: f64, scene: Command) -> Command {
        let Some(list) = self.phases.get(i).and_then(Option::as_ref) else {
            return scene;
        };
        match &list[p] {
            Phase::Held { .. } => Command::Held,
            Phase::Ramp { keyframes, easing } => {
                let load = ramp_load(keyframes, *easing, t, current_n);
                if load > 0.0 {
                    Command::Load(load)
                } else {
                    Command::Released
                }
            }
            Phase::Approach { keyframes, easing } => {
                let k: Vec<(f64, Option<f64>)> =
                    keyframes.iter().map(|k| (k.0, Some(k.1))).collect();
                let d = ramp_load(&k, *easing, t, 0.0);
                // Negative: opened short of first touch (withdrawn); 0 is held.
                if d != 0.0 {
                    Command::Approach(d)
                } else {
                    Command::Held
                }
            }
            Phase::Hold { .. } => match p.checked_sub(1) {
                None => scene,
                Some(q) => {
                    let end = list[q].end().unwrap_or(t);
                    self.phase_command(i, q, end, current_n, scene)
                }
            },
        }
    }
}

/// The load of a ramp at time `t`: constant before the first and after the last keyframe,
/// eased in between; `"current"` keyframes (and an empty ramp) take `current_n`.
fn ramp_load(keyframes: &[(f64, Option<f64>)], easing: Easing, t: f64, current_n: f64) -> f64 {
    let val = |k: &(f64, Option<f64>)| k.1.unwrap_or(current_n);
    let (Some(first), Some(last)) = (keyframes.first(), keyframes.last()) else {
        return current_n;
    };
    if t <= first.0 {
        return val(first);
    }
    if t >= last.0 {
        return val(last);
    }
    // first.0 < t < last.0: keyframes[k].0 <= t < keyframes[k + 1].0 with 0 <= k < len - 1.
    let k = keyframes.partition_point(|kf| kf.0 <= t).saturating_sub(1);
    let k = k.min(keyframes.len() - 2);
    let (a, b) = (&keyframes[k], &keyframes[k + 1]);
    let s = easing.apply((t - a.0) / (b.0 - a.0));
    val(a) + (val(b) - val(a)) * s
}
