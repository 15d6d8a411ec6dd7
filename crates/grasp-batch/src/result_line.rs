//! One line of a batch's output (JSON): the scene's id and position, its status, per-finger
//! forces, residuals and time; an invalid scene's problems instead of forces.

use grasp_model::{InputProblem, Solution, SolveStatus};
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// Outcome of one scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResultStatus {
    /// Solved.
    Solved,
    /// Solved to reduced accuracy (check the residuals).
    ReducedAccuracy,
    /// The fingers cannot hold the object.
    NoEquilibrium,
    /// The solver gave no answer.
    NoConvergence,
    /// The scene is not usable, or its solve did not fit in the memory there is: see
    /// `problems`.
    Invalid,
}

/// One finger's resultants.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FingerForces {
    /// Finger name.
    pub name: String,
    /// Normal force `P`, N.
    pub normal_force_n: f64,
    /// Friction force `Q`, world frame, N.
    pub tangential_force_n: [f64; 3],
    /// `|Q|`, N.
    pub tangential_magnitude_n: f64,
    /// Torsional moment about the normal, N m.
    pub torsional_moment_nm: f64,
    /// `|Q| / (mu P)`.
    pub friction_utilization: f64,
    /// A finger on a mount: its core's displacement from the commanded pose (absent for a
    /// rigid core; `grasp_model::MountDisplacement`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mount_displacement: Option<grasp_model::MountDisplacement>,
    /// Elements in stick over elements in contact with friction (stick and slip): 1 fully
    /// stuck, 0 sliding as a whole; absent for a frictionless finger or one out of contact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stick_fraction: Option<f64>,
}

/// One output line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultLine {
    /// The scene's id.
    pub id: String,
    /// Position of the scene in the input (0-based).
    pub index: usize,
    /// Number of scenes in the whole input (every shard), for `--merge` to check completeness.
    pub of: usize,
    /// Outcome.
    pub status: ResultStatus,
    /// Why, when not solved.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The problems of an invalid scene.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub problems: Vec<InputProblem>,
    /// What the user should know about the answer: the scene's warnings (its shape checks)
    /// and the solve's (as the solution's `warnings`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The sweep variant's parameters, when the line came from `grasp sweep`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vary: Option<Value>,
    /// Per finger, scene order (empty without forces).
    #[serde(default)]
    pub fingers: Vec<FingerForces>,
    /// Per hand (`hands`), its load and its base's motion (absent without hands or forces).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hands: Vec<grasp_model::HandSolution>,
    /// Per servo (`servos`), its load and its jaws' travel (absent without servos or forces).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub servos: Vec<grasp_model::ServoSolution>,
    /// Relative equilibrium residual (absent without forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equilibrium_residual: Option<f64>,
    /// Largest relative residual of every kind (absent without forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_residual: Option<f64>,
    /// The tactile sensors' readings, as `grasp solve --json` writes them under `sensors`
    /// (one record per finger with a sensor; absent when the scene has none or no forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensors: Option<Value>,
    /// The same readings as the model gave them, for a tactile dataset's arrays
    /// (`crate::tactile_dataset`); not written to the line.
    #[serde(skip)]
    pub readings: Vec<grasp_model::SensorReadings>,
    /// Solver that answered (absent for an invalid scene).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<String>,
    /// Wall time of the model and the solve, s.
    pub time_s: f64,
}

/// `stick / (stick + slip)`, `None` when no element sticks or slips.
fn stick_fraction(stick: usize, slip: usize) -> Option<f64> {
    (stick + slip > 0).then(|| stick as f64 / (stick + slip) as f64)
}

impl ResultLine {
    /// The line of a solved (or unsolvable) scene.
    pub fn of_solution(id: String, index: usize, of: usize, sol: &Solution, time_s: f64) -> Self {
        let status = match sol.status {
            SolveStatus::Solved => ResultStatus::Solved,
            SolveStatus::ReducedAccuracy => ResultStatus::ReducedAccuracy,
            SolveStatus::NoEquilibrium => ResultStatus::NoEquilibrium,
            SolveStatus::NoConvergence => ResultStatus::NoConvergence,
        };
        ResultLine {
            id,
            index,
            of,
            status,
            reason: sol.reason.clone(),
            problems: Vec::new(),
            warnings: sol.warnings.clone(),
            vary: None,
            fingers: sol
                .fingers
                .iter()
                .map(|f| FingerForces {
                    name: f.name.clone(),
                    normal_force_n: f.normal_force_n,
                    tangential_force_n: f.tangential_force_n,
                    tangential_magnitude_n: f.tangential_magnitude_n,
                    torsional_moment_nm: f.torsional_moment_nm,
                    friction_utilization: f.friction_utilization,
                    mount_displacement: f.mount_displacement,
                    stick_fraction: stick_fraction(f.stick_count, f.slip_count),
                })
                .collect(),
            hands: sol.hands.clone(),
            servos: sol.servos.clone(),
            equilibrium_residual: sol.residuals.map(|r| r.equilibrium_relative),
            worst_residual: sol.residuals.map(|r| r.worst()),
            sensors: None,
            readings: Vec::new(),
            solver: Some(sol.solver.solver.to_string().to_lowercase()),
            time_s,
        }
    }

    /// The line of an invalid scene.
    pub fn invalid(id: String, index: usize, of: usize, problems: Vec<InputProblem>) -> Self {
        ResultLine {
            id,
            index,
            of,
            status: ResultStatus::Invalid,
            reason: problems
                .first()
                .map(|p| format!("{}: {}", p.path, p.message)),
            problems,
            warnings: Vec::new(),
            vary: None,
            fingers: Vec::new(),
            hands: Vec::new(),
            servos: Vec::new(),
            equilibrium_residual: None,
            worst_residual: None,
            sensors: None,
            readings: Vec::new(),
            solver: None,
            time_s: 0.0,
        }
    }
}
