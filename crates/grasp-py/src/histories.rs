//! The force histories of a hand-off (time x finger), kept step by step in flat arrays as the
//! driver streams its steps, and the memory a run will keep: the histories, and (unless
//! `keep_solutions=False`) every step's full solution, estimated before the run so a long
//! schedule is refused up front rather than filling the machine.

use grasp_model::{ElementSolution, FingerSolution};
use grasp_transfer::{Command, StepRecord};

use crate::sensor_histories::SensorHistories;

/// Per step and finger, in scene order: the values `grasp.Transfer` returns as arrays.
#[derive(Debug, Default)]
pub struct Histories {
    /// Scene finger names (the columns).
    pub names: Vec<String>,
    /// Step times, s, `(T,)`.
    pub times_s: Vec<f64>,
    /// Normal forces, N, `(T, F)`.
    pub normal_n: Vec<f64>,
    /// Friction forces (world), N, `(T, F, 3)`.
    pub tangential_n: Vec<f64>,
    /// Commanded loads, N, `(T, F)`: NaN held, 0 released.
    pub commanded_n: Vec<f64>,
    /// Scheduled external force, N, `(T, 3)`.
    pub external_n: Vec<f64>,
    /// Step statuses, `(T,)`.
    pub statuses: Vec<&'static str>,
    /// Wall time per step, s, `(T,)`.
    pub wall_times_s: Vec<f64>,
    /// Solver iterations per step, `(T,)`.
    pub iterations: Vec<i64>,
    /// Smallest disturbance margin per step, N: infinite where unbounded (every direction held
    /// to the search's cap), NaN where undetermined or not computed, `(T,)`.
    pub margins_n: Vec<f64>,
    /// The tactile readings of the fingers with a sensor.
    pub sensors: SensorHistories,
}

impl Histories {
    /// Empty histories of the fingers of `scene`.
    pub fn new(scene: &grasp_model::Scene) -> Histories {
        Histories {
            names: scene.finger_names(),
            sensors: SensorHistories::of(scene),
            ..Histories::default()
        }
    }

    /// Number of steps kept.
    pub fn len(&self) -> usize {
        self.times_s.len()
    }

    /// Appends one step.
    pub fn push(&mut self, r: &StepRecord) {
        self.times_s.push(r.time_s);
        for name in &self.names {
            let f = r.solution.finger(name);
            self.normal_n.push(f.map_or(0.0, |f| f.normal_force_n));
            self.tangential_n
                .extend(f.map_or([0.0; 3], |f| f.tangential_force_n));
            let command = r.commands.iter().find(|c| c.name == *name);
            self.commanded_n.push(match command.map(|c| &c.command) {
                Some(Command::Load(l)) => *l,
                Some(Command::Released) => 0.0,
                _ => f64::NAN,
            });
        }
        self.external_n.extend(r.external_force_n);
        self.statuses.push(r.solution.status.as_str());
        self.wall_times_s.push(r.wall_time_s);
        self.iterations
            .push(i64::from(r.solution.solver.iterations));
        // Unbounded: infinite; undetermined or not computed: NaN (never the search's cap).
        self.margins_n.push(match &r.margin {
            Some(m) if m.undetermined.is_none() => m.margin_or_bound_n(),
            _ => f64::NAN,
        });
        self.sensors.push(&r.sensors);
    }

    /// Bytes one step adds to the histories of `scene`'s fingers and sensors.
    pub fn bytes_per_step(scene: &grasp_model::Scene) -> u64 {
        let per_finger = 8 * (1 + 3 + 1);
        let per_step = 8 * (1 + 3 + 1 + 1 + 1) + std::mem::size_of::<&str>();
        (per_step + scene.fingers.len() * per_finger) as u64
            + SensorHistories::bytes_per_step(scene)
    }
}

/// About the bytes of one step's full solution (`Transfer.step(i)`) for `scene`: the record,
/// each finger's resultants and command, each element's fields.
pub fn solution_bytes_per_step(scene: &grasp_model::Scene) -> u64 {
    let fingers = scene.fingers.len() as u64;
    let elements: u64 = scene
        .fingers
        .iter()
        .map(|f| f.patch.grid[0] as u64 * f.patch.grid[1] as u64)
        .sum();
    let names: u64 = scene.fingers.iter().map(|f| 2 * f.name.len() as u64).sum();
    // The sensors' readings a record holds: per taxel or marker its reading and its point.
    let readings = SensorHistories::bytes_per_step(scene) * 5 / 3;
    std::mem::size_of::<StepRecord>() as u64
        + readings
        + fingers
            * (std::mem::size_of::<FingerSolution>()
                + std::mem::size_of::<grasp_transfer::FingerCommand>()) as u64
        + elements * std::mem::size_of::<ElementSolution>() as u64
        + names
}
