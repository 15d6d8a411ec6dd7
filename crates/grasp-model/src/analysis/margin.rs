//! Disturbance margins (issue 13): for each direction of an extra wrench on the object, the
//! largest magnitude the grasp can take while it still holds in the scene's model.
//!
//! A direction is a unit vector `(f, t)` of the scaled wrench space; magnitude `s` (N) means a
//! force `s f` (N) at the centre of mass plus a couple `s L t` (N m), `L` the characteristic
//! length ([`MarginOptions::length_m`], by default the grasp's reach [`crate::Scales`]
//! `length_m`), so force and torque directions compare at the grasp's size.
//!
//! The grasp **holds** at `s` when
//! - energy model: the program has a solution, i.e. forces within the element cones (and the
//!   commanded loads) balance the load: the rigid-body bound of the patches' cones. (The energy
//!   model's minimum-energy grasp may slide as a whole at no disturbance at all: its held
//!   fingers squeeze no more than friction needs, so sliding is not its failure criterion.)
//! - coulomb model: an equilibrium exists and every loaded frictional finger keeps at least
//!   one sticking element (a finger whose every element slips slides as a whole). A finger
//!   that already slides as a whole without disturbance (a receiving finger settling in a
//!   hand-off) is listed apart and not judged by sliding.
//!
//! Search: the disturbance grows monotonically along the direction, each trial one
//! quasi-static step from the state at the last magnitude that held (so the coulomb model's
//! slip memory follows the loading path) and warm-started from its solution; the step doubles
//! from the load scale until the grasp fails (or the magnitude passes
//! [`MarginOptions::max_factor`] times the load scale: unbounded), then bisection narrows the
//! bracket to [`MarginOptions::relative_tolerance`]. Directions run in parallel; each is
//! deterministic.

use std::time::Instant;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::model::equilibrium::MotionPlane;
use crate::model::grasp_model::GraspModel;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::solution::{Solution, SolveStatus, LOADED_FRACTION};
use crate::solver::options::SolveOptions;

/// First growth step of the search, as a fraction of the load scale: small, because a trial
/// that holds is cheap (a warm-started step) and one that fails is not (the solver must certify
/// that no equilibrium exists), so the search should fail as few times as it can.
const INITIAL_STEP: f64 = 1e-2;

/// Below this fraction of the load scale a margin counts as zero: the bisection stops (the
/// solves themselves balance the load only to about 1e-10 of it).
const ZERO_MARGIN: f64 = 1e-6;

/// A direction of disturbance: a unit vector of the scaled wrench space.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WrenchDirection {
    /// Force part (world frame, dimensionless).
    pub force: [f64; 3],
    /// Torque part (world frame, dimensionless; times `s L` gives N m).
    pub torque: [f64; 3],
}

impl WrenchDirection {
    /// The direction of a wrench `force_n` (N) plus `torque_nm` (N m) at length `length_m`:
    /// `(f, t / L)` normalised; `None` for a zero or non-finite wrench.
    pub fn of_wrench(force_n: [f64; 3], torque_nm: [f64; 3], length_m: f64) -> Option<Self> {
        let t = torque_nm.map(|v| v / length_m);
        let norm = force_n.iter().chain(&t).map(|v| v * v).sum::<f64>().sqrt();
        (norm.is_finite() && norm > 0.0).then(|| WrenchDirection {
            force: force_n.map(|v| v / norm),
            torque: t.map(|v| v / norm),
        })
    }
}

/// Options of the margin search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarginOptions {
    /// Characteristic length `L`, m: torque `s L t` per magnitude `s`. `None`: the grasp's
    /// reach (`Scales::length_m`).
    pub length_m: Option<f64>,
    /// Bisection stops when the bracket is below this fraction of its upper end.
    pub relative_tolerance: f64,
    /// Magnitudes above this multiple of the load scale count as unbounded.
    pub max_factor: f64,
}

impl Default for MarginOptions {
    fn default() -> Self {
        MarginOptions {
            length_m: None,
            relative_tolerance: 1e-3,
            max_factor: 1e3,
        }
    }
}

/// Why the grasp stopped holding.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Failure {
    /// No equilibrium: the solve's reason.
    NoEquilibrium {
        /// The solver's explanation.
        reason: String,
    },
    /// A loaded finger slides as a whole (coulomb model: no sticking element left).
    Slides {
        /// The finger.
        finger: String,
    },
    /// The solver gave no answer at this magnitude (counted as a failure; the reason says
    /// why).
    NoConvergence {
        /// The solver's explanation.
        reason: String,
    },
}

/// The margin along one direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DirectionMargin {
    /// The direction.
    pub direction: WrenchDirection,
    /// Largest magnitude found to hold, N (the lower end of the final bracket; the cap when
    /// unbounded).
    pub margin_n: f64,
    /// Smallest magnitude found to fail, N (absent when unbounded).
    pub fails_at_n: Option<f64>,
    /// Force part of the wrench at the margin, N (at the centre of mass).
    pub force_n: [f64; 3],
    /// Torque part of the wrench at the margin, N m.
    pub torque_nm: [f64; 3],
    /// False when the grasp still held at the cap.
    pub bounded: bool,
    /// The finger that fails first: the one that slides, else the loaded frictional finger
    /// with the highest friction utilisation at the margin.
    pub failing_finger: Option<String>,
    /// How the grasp failed just above the margin.
    pub failure: Option<Failure>,
    /// Solves spent on this direction.
    pub solves: u32,
    /// Wall time of this direction, s.
    pub time_s: f64,
}

/// Margins of a grasp.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MarginReport {
    /// The model whose criterion was used.
    pub model: ModelKind,
    /// Characteristic length `L`, m.
    pub length_m: f64,
    /// Load scale, N (the unit of the growth step; the cap is `max_factor` times it).
    pub load_scale_n: f64,
    /// Loaded fingers that already slide as a whole without disturbance (coulomb model; a
    /// receiving finger settling, a releasing one letting go): not judged by sliding, since the
    /// disturbance is not what makes them slide.
    pub sliding_undisturbed: Vec<String>,
    /// Per direction, in the order given.
    pub directions: Vec<DirectionMargin>,
    /// Index of the direction with the smallest margin among those the grasp resists at all
    /// (among all when it resists none).
    pub smallest: usize,
    /// Directions the grasp does not resist at all (margin 0 although it holds undisturbed:
    /// with commanded loads, a push along the squeeze axis has no equilibrium).
    pub unresisted: Vec<usize>,
    /// Solves over all directions (the undisturbed solve included).
    pub solves: u32,
    /// Wall time of the whole search, s.
    pub time_s: f64,
}

/// The 12 axis directions in 3-D (force `+-x, +-y, +-z`, then torque), the 6 in-plane ones of
/// a planar scene (force `+-e1, +-e2`, torque `+-p`).
pub fn axis_directions(model: &GraspModel) -> Vec<WrenchDirection> {
    let axes: Vec<Vector3<f64>> = match model.plane {
        None => vec![Vector3::x(), Vector3::y(), Vector3::z()],
        Some(p) => vec![p.e1, p.e2],
    };
    let torques: Vec<Vector3<f64>> = match model.plane {
        None => vec![Vector3::x(), Vector3::y(), Vector3::z()],
        Some(p) => vec![p.normal],
    };
    let arr = |v: Vector3<f64>| [v.x, v.y, v.z];
    let mut out = Vec::new();
    for a in axes {
        for sign in [1.0, -1.0] {
            out.push(WrenchDirection {
                force: arr(a * sign),
                torque: [0.0; 3],
            });
        }
    }
    for a in torques {
        for sign in [1.0, -1.0] {
            out.push(WrenchDirection {
                force: [0.0; 3],
                torque: arr(a * sign),
            });
        }
    }
    out
}

/// Force directions spread evenly around each coordinate plane, `per_plane` per plane (3-D: the
/// `xy`, `yz` and `zx` planes, the axes listed once; planar: the plane of motion), then the
/// couple axes (both signs): the directions a polar plot of the margins draws.
pub fn plane_directions(model: &GraspModel, per_plane: usize) -> Vec<WrenchDirection> {
    let planes: Vec<(Vector3<f64>, Vector3<f64>)> = match model.plane {
        None => vec![
            (Vector3::x(), Vector3::y()),
            (Vector3::y(), Vector3::z()),
            (Vector3::z(), Vector3::x()),
        ],
        Some(p) => vec![(p.e1, p.e2)],
    };
    let mut out: Vec<WrenchDirection> = Vec::new();
    for (a, b) in planes {
        for k in 0..per_plane {
            let angle = std::f64::consts::TAU * k as f64 / per_plane as f64;
            let mut f = a * angle.cos() + b * angle.sin();
            f.iter_mut().for_each(|c| {
                if c.abs() < 1e-15 {
                    *c = 0.0;
                }
            });
            let d = WrenchDirection {
                force: [f.x, f.y, f.z],
                torque: [0.0; 3],
            };
            let same =
                |o: &WrenchDirection| (0..3).all(|c| (o.force[c] - d.force[c]).abs() < 1e-12);
            if !out.iter().any(same) {
                out.push(d);
            }
        }
    }
    let torques = axis_directions(model)
        .into_iter()
        .filter(|d| d.torque.iter().any(|c| *c != 0.0));
    out.extend(torques);
    out
}

/// `n` directions: the axis directions first, then combined ones spread quasi-uniformly over
/// the unit sphere of the scaled wrench space (3 dimensions planar, 6 in 3-D): the additive
/// recurrence of the generalised golden ratio (Roberts' `R_d` sequence) mapped to Gaussians by
/// Box-Muller and normalised. Deterministic.
pub fn spread_directions(model: &GraspModel, n: usize) -> Vec<WrenchDirection> {
    let mut out = axis_directions(model);
    if n <= out.len() {
        out.truncate(n);
        return out;
    }
    let basis: Vec<[f64; 6]> = match model.plane {
        None => (0..6)
            .map(|i| {
                let mut b = [0.0; 6];
                b[i] = 1.0;
                b
            })
            .collect(),
        Some(MotionPlane { e1, e2, normal: p }) => vec![
            [e1.x, e1.y, e1.z, 0.0, 0.0, 0.0],
            [e2.x, e2.y, e2.z, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, p.x, p.y, p.z],
        ],
    };
    let dim = basis.len();
    // phi_d: the positive root of x^(d+1) = x + 1 (Roberts 2018).
    let mut phi: f64 = 2.0;
    for _ in 0..50 {
        phi = (1.0 + phi).powf(1.0 / (dim as f64 + 1.0));
    }
    let alpha: Vec<f64> = (1..=2 * dim)
        .map(|j| phi.powi(-(j as i32)).fract())
        .collect();
    let mut k = 1usize;
    while out.len() < n {
        let u: Vec<f64> = alpha.iter().map(|a| (0.5 + a * k as f64).fract()).collect();
        k += 1;
        let g: Vec<f64> = (0..dim)
            .map(|i| {
                let (u1, u2) = (u[2 * i].max(1e-12), u[2 * i + 1]);
                (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            })
            .collect();
        let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm < 1e-9 {
            continue;
        }
        let mut w = [0.0; 6];
        for (gi, b) in g.iter().zip(&basis) {
            for c in 0..6 {
                w[c] += gi / norm * b[c];
            }
        }
        out.push(WrenchDirection {
            force: [w[0], w[1], w[2]],
            torque: [w[3], w[4], w[5]],
        });
    }
    out
}

/// The loaded frictional fingers of `sol` that slide as a whole (no sticking element).
fn sliding_fingers(sol: &Solution) -> Vec<String> {
    sol.fingers_sliding_as_a_whole()
        .map(|f| f.name.clone())
        .collect()
}

/// Whether `sol` holds in `model`'s criterion (see the module); fingers in `exempt` (those
/// already sliding without disturbance) are not judged by sliding.
pub fn holds(model: &GraspModel, sol: &Solution, exempt: &[String]) -> Result<(), Failure> {
    match sol.status {
        SolveStatus::NoEquilibrium => {
            return Err(Failure::NoEquilibrium {
                reason: sol.reason.clone().unwrap_or_default(),
            })
        }
        SolveStatus::NoConvergence => {
            return Err(Failure::NoConvergence {
                reason: sol.reason.clone().unwrap_or_default(),
            })
        }
        _ => {}
    }
    if model.kind == ModelKind::Coulomb {
        if let Some(finger) = sliding_fingers(sol)
            .into_iter()
            .find(|f| !exempt.contains(f))
        {
            return Err(Failure::Slides { finger });
        }
    }
    Ok(())
}

/// The loaded frictional finger with the highest friction utilisation.
fn most_utilised(model: &GraspModel, sol: &Solution) -> Option<String> {
    let loaded = LOADED_FRACTION * sol.load_scale_n;
    sol.fingers
        .iter()
        .zip(&model.fingers)
        .filter(|(f, fm)| fm.n_tangential > 0 && f.normal_force_n > loaded)
        .max_by(|a, b| {
            a.0.friction_utilization
                .total_cmp(&b.0.friction_utilization)
        })
        .map(|(f, _)| f.name.clone())
}

/// The search along one direction.
struct Search<'a> {
    model: &'a GraspModel,
    loads: Vec<f64>,
    solver: GraspSolver,
    direction: WrenchDirection,
    length_m: f64,
    solves: u32,
    exempt: &'a [String],
}

impl Search<'_> {
    /// The wrench about `O` of magnitude `s` (N) along the direction.
    fn model_at(&self, s: f64) -> GraspModel {
        let d = &self.direction;
        let f = Vector3::from(d.force) * s;
        let t = Vector3::from(d.torque) * (s * self.length_m);
        self.model
            .with_extra_wrench(&self.model.wrench_at_center_of_mass(&f, &t))
    }

    /// One quasi-static step to magnitude `s` from `state`.
    fn trial(
        &mut self,
        s: f64,
        state: &ContactState,
    ) -> Result<Result<(ContactState, Solution), Failure>, ModelError> {
        let m = self.model_at(s);
        let mut next = state.clone();
        let sol = self.solver.solve_step(&m, &self.loads, &mut next)?;
        self.solves += 1;
        Ok(holds(&m, &sol, self.exempt).map(|()| (next, sol)))
    }
}

/// The margin along `direction` from the undisturbed `state` and solution `base`; fingers in
/// `exempt` already slide undisturbed.
fn along(
    model: &GraspModel,
    solve_options: SolveOptions,
    options: &MarginOptions,
    (length_m, exempt): (f64, &[String]),
    direction: WrenchDirection,
    base: (&ContactState, &Solution),
) -> Result<DirectionMargin, ModelError> {
    let clock = Instant::now();
    let mut search = Search {
        model,
        loads: model.scene_loads_n(),
        solver: GraspSolver::new(model, solve_options),
        direction,
        length_m,
        solves: 0,
        exempt,
    };
    let scale = model.scales.load_n;
    let cap = options.max_factor * scale;
    let (mut lo, mut lo_state, mut lo_sol) = (0.0, base.0.clone(), base.1.clone());
    let mut step = INITIAL_STEP * scale;
    let mut hi: Option<(f64, Failure)> = None;
    while hi.is_none() && lo < cap {
        let s = (lo + step).min(cap);
        match search.trial(s, &lo_state)? {
            Ok((state, sol)) => (lo, lo_state, lo_sol, step) = (s, state, sol, 2.0 * step),
            Err(f) => hi = Some((s, f)),
        }
    }
    if let Some((h, f)) = &mut hi {
        // Failed at the first step: is the direction resisted at all? (One solve, not a
        // bisection down to zero: commanded loads leave some directions unresisted.)
        if lo == 0.0 {
            let tiny = ZERO_MARGIN * scale;
            match search.trial(tiny, &lo_state)? {
                Ok((state, sol)) => (lo, lo_state, lo_sol) = (tiny, state, sol),
                Err(g) => (*h, *f) = (tiny, g),
            }
        }
        while *h - lo > options.relative_tolerance * *h && *h > ZERO_MARGIN * scale {
            // Geometric while the bracket spans more than a factor 2, then arithmetic.
            let mid = if lo > 0.0 && *h > 2.0 * lo {
                (lo * *h).sqrt()
            } else {
                0.5 * (lo + *h)
            };
            match search.trial(mid, &lo_state)? {
                Ok((state, sol)) => (lo, lo_state, lo_sol) = (mid, state, sol),
                Err(g) => (*h, *f) = (mid, g),
            }
        }
    }
    let failing_finger = match &hi {
        Some((_, Failure::Slides { finger })) => Some(finger.clone()),
        Some(_) => most_utilised(model, &lo_sol),
        None => None,
    };
    Ok(DirectionMargin {
        direction,
        margin_n: lo,
        fails_at_n: hi.as_ref().map(|(h, _)| *h),
        force_n: direction.force.map(|v| v * lo),
        torque_nm: direction.torque.map(|v| v * lo * length_m),
        bounded: hi.is_some(),
        failing_finger,
        failure: hi.map(|(_, f)| f),
        solves: search.solves,
        time_s: clock.elapsed().as_secs_f64(),
    })
}

/// The margins of `model` (with its scene loads) along `directions`, starting from `state`
/// (a fresh [`ContactState`] for a single grasp; a hand-off step's state to continue its
/// path). If the grasp does not hold undisturbed every margin is 0 with that failure.
pub fn disturbance_margins(
    model: &GraspModel,
    state: &ContactState,
    solve_options: SolveOptions,
    directions: &[WrenchDirection],
    options: &MarginOptions,
) -> Result<MarginReport, ModelError> {
    use rayon::prelude::*;
    let clock = Instant::now();
    let length_m = options.length_m.unwrap_or(model.scales.length_m);
    let mut base_state = state.clone();
    let base = GraspSolver::new(model, solve_options).solve_step(
        model,
        &model.scene_loads_n(),
        &mut base_state,
    )?;
    let sliding_undisturbed = match model.kind {
        ModelKind::Coulomb if base.status.has_forces() => sliding_fingers(&base),
        _ => Vec::new(),
    };
    let margins: Vec<DirectionMargin> = match holds(model, &base, &sliding_undisturbed) {
        Err(f) => directions
            .iter()
            .map(|&d| DirectionMargin {
                direction: d,
                margin_n: 0.0,
                fails_at_n: Some(0.0),
                force_n: [0.0; 3],
                torque_nm: [0.0; 3],
                bounded: true,
                failing_finger: match &f {
                    Failure::Slides { finger } => Some(finger.clone()),
                    _ => None,
                },
                failure: Some(f.clone()),
                solves: 0,
                time_s: 0.0,
            })
            .collect(),
        Ok(()) => directions
            .par_iter()
            .map(|&d| {
                let geometry = (length_m, sliding_undisturbed.as_slice());
                along(
                    model,
                    solve_options,
                    options,
                    geometry,
                    d,
                    (&base_state, &base),
                )
            })
            .collect::<Result<_, _>>()?,
    };
    // Directions not resisted at all: searched, and failing at the smallest magnitude.
    let searched = margins.iter().any(|m| m.solves > 0);
    let unresisted: Vec<usize> = (0..margins.len())
        .filter(|&i| searched && margins[i].margin_n == 0.0 && margins[i].failure.is_some())
        .collect();
    let smallest = (0..margins.len())
        .filter(|i| !unresisted.contains(i) || unresisted.len() == margins.len())
        .min_by(|&a, &b| margins[a].margin_n.total_cmp(&margins[b].margin_n))
        .unwrap_or(0);
    Ok(MarginReport {
        model: model.kind,
        length_m,
        load_scale_n: model.scales.load_n,
        solves: 1 + margins.iter().map(|m| m.solves).sum::<u32>(),
        sliding_undisturbed,
        directions: margins,
        smallest,
        unresisted,
        time_s: clock.elapsed().as_secs_f64(),
    })
}
