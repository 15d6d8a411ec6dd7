//! What changes from one solve of a model to the next while the model stays the same: the
//! commanded loads, an extra wrench on the object, the commanded approaches and, along a time
//! history, the step's length ([`StepInputs`]). What the solves leave behind (slip memory, warm start, viscoelastic
//! history) is the [`crate::ContactState`]'s; what does not change is the
//! [`crate::GraspModel`]'s (the split MuJoCo makes between `mjModel`, the controls and
//! `mjData`).

use nalgebra::Vector3;

use crate::error::ModelError;
use crate::model::equilibrium::Wrench;
use crate::model::grasp_model::{Control, GraspModel};
use crate::model::shared_spring::SpringKind;

/// The inputs of one solve of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct StepInputs {
    /// Prescribed total normal load `P_i` of each force-controlled finger, N, in the model's
    /// finger order (one per finger whose [`Control`] is `NormalLoad`).
    pub loads_n: Vec<f64>,
    /// Extra wrench on the object beyond the scene's weight and external forces: force, N, and
    /// moment, N m, about the model's reference point `O` ([`GraspModel::reference_point_m`]);
    /// `None` by default. [`StepInputs::with_load_at_center_of_mass`] writes one from a force
    /// at the centre of mass and a couple.
    pub extra_wrench: Option<Wrench>,
    /// Commanded approaches, m: `(finger index in the model, d)`. The finger is pressed `d`
    /// along its inward normal from first touch (every element's gap closes by `d`), its load
    /// an unknown; a finger not listed keeps its model's control (a position-controlled
    /// finger its scene approach, a held one none). Refused on a force-controlled finger.
    pub approaches_m: Vec<(usize, f64)>,
    /// Commanded hand poses: `(hand's index among the model's shared springs
    /// ([`GraspModel::springs`]), [dx, dy, dz, rx, ry, rz])`, the base's displacement from the
    /// scene's placement (m, and a small rotation in rad about the hand's origin; world frame).
    /// Every finger on the hand moves with it; the hand's spring then gives way from there. A
    /// hand not listed stays where the scene puts it.
    pub hand_poses: Vec<(usize, [f64; 6])>,
    /// The length of the step, s, when the solve is one step of a viscoelastic model's time
    /// history (`f64::INFINITY`: fully relaxed; 0: the loads applied as a step): the solve
    /// takes the compliance over the step and the history the state carries
    /// (`crate::model::viscoelasticity`). `None` (the default): a solve outside a time
    /// history, the model's instantaneous response. An elastic model ignores it.
    pub time_step_s: Option<f64>,
}

impl StepInputs {
    /// Inputs with prescribed loads `loads_n` (N, one per force-controlled finger), no extra
    /// wrench and the model's approaches.
    pub fn loads(loads_n: Vec<f64>) -> Self {
        StepInputs {
            loads_n,
            extra_wrench: None,
            approaches_m: Vec::new(),
            hand_poses: Vec::new(),
            time_step_s: None,
        }
    }

    /// The scene's own inputs: its prescribed loads ([`GraspModel::scene_loads_n`]).
    pub fn of_scene(model: &GraspModel) -> Self {
        Self::loads(model.scene_loads_n())
    }

    /// These inputs with `extra` (N, N m about `O`) added to the extra wrench.
    pub fn with_extra_wrench(mut self, extra: &Wrench) -> Self {
        self.extra_wrench = Some(match self.extra_wrench {
            Some(w) => w + extra,
            None => *extra,
        });
        self
    }

    /// These inputs with a force `force_n` (N, world) at the object's centre of mass and a
    /// couple `torque_nm` (N m, world) added to the extra wrench (thesis eq. 49's moment of an
    /// external force).
    pub fn with_load_at_center_of_mass(
        self,
        model: &GraspModel,
        force_n: &Vector3<f64>,
        torque_nm: &Vector3<f64>,
    ) -> Self {
        let w = model.wrench_at_center_of_mass(force_n, torque_nm);
        self.with_extra_wrench(&w)
    }

    /// These inputs as one step of `dt_s` seconds of a time history (see
    /// [`StepInputs::time_step_s`]).
    pub fn with_time_step(mut self, dt_s: f64) -> Self {
        self.time_step_s = Some(dt_s);
        self
    }

    /// These inputs with finger `finger` (index in the model) pressed in by `metres`.
    pub fn with_approach(mut self, finger: usize, metres: f64) -> Self {
        self.approaches_m.push((finger, metres));
        self
    }

    /// These inputs with hand `hand` (its index among [`GraspModel::springs`]) commanded to
    /// `pose` (`[dx, dy, dz]` m, then a small rotation `[rx, ry, rz]` rad about its origin;
    /// world frame) from where the scene puts it.
    pub fn with_hand_pose(mut self, hand: usize, pose: [f64; 6]) -> Self {
        self.hand_poses.push((hand, pose));
        self
    }

    /// Checks the inputs against `model`: one finite, non-negative load per force-controlled
    /// finger, approaches of existing fingers that are not force-controlled, poses of hands. (An extra wrench
    /// or an approach that is not finite reaches the program, which refuses it as an outcome
    /// with its reason, as any data that are not finite.)
    pub fn check(&self, model: &GraspModel) -> Result<(), ModelError> {
        model.check_loads(&self.loads_n)?;
        if let Some(dt) = self.time_step_s.filter(|dt| dt.is_nan() || *dt < 0.0) {
            return Err(ModelError::BadInput(format!(
                "a time step of {dt} s: give a step of 0 s or more (infinity: fully relaxed)"
            )));
        }
        for &(i, _) in &self.approaches_m {
            let Some(f) = model.fingers.get(i) else {
                return Err(ModelError::BadInput(format!(
                    "an approach names finger {i}; the model has {} fingers",
                    model.fingers.len()
                )));
            };
            if matches!(f.control, Control::NormalLoad { .. }) {
                return Err(ModelError::BadInput(format!(
                    "finger `{}` is force-controlled: it takes a load, not an approach",
                    f.name
                )));
            }
        }
        for &(j, _) in &self.hand_poses {
            let hand = model.springs.get(j).map(|s| s.kind());
            if !matches!(hand, Some(SpringKind::Hand { .. })) {
                return Err(ModelError::BadInput(format!(
                    "a hand pose names shared spring {j}, which is not a hand of the model"
                )));
            }
        }
        Ok(())
    }

    /// Each finger's commanded approach, m (model order): the one given here, else its
    /// control's ([`Control::approach_m`]; 0 for held and force-controlled fingers).
    pub fn approaches_per_finger_m(&self, model: &GraspModel) -> Vec<f64> {
        let mut d: Vec<f64> = model
            .fingers
            .iter()
            .map(|f| f.control.approach_m())
            .collect();
        for &(i, metres) in &self.approaches_m {
            d[i] = metres;
        }
        d
    }

    /// The external wrench of the solve (N, N m about `O`): the model's plus the extra one.
    pub(crate) fn external_wrench(&self, model: &GraspModel) -> Wrench {
        match &self.extra_wrench {
            Some(w) => model.external_wrench + w,
            None => model.external_wrench,
        }
    }
}
