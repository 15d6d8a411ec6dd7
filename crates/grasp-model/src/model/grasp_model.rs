//! The grasp model: everything derived once from a validated scene and never mutated while
//! solving (frames, patches, compliance blocks, the equilibrium map, scales).
//!
//! Unknown layout: fingers in scene order; within finger `i`, `[F_1..F_N, G1_1..G1_N,
//! G2_1..G2_N]` truncated to `1 + n_tangential` blocks, where `n_tangential` is 0 for a
//! frictionless finger, 1 in a planar scene and 2 otherwise. Forces in newtons.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::error::{ModelError, OutOfMemory};
use crate::geometry::contact_frame::ContactFrame;
use crate::geometry::mesh_surface::TriangleMesh;
use crate::model::contact_pair::ContactPair;
use crate::model::equilibrium::{unit_wrench, EquilibriumMap, MotionPlane, Wrench};
use crate::model::finger_mount::FingerMount;
use crate::model::friction::FrictionLaw;
use crate::model::material::Material;
use crate::model::patch::Patch;
use crate::model::patch_compliance::PatchCompliance;
use crate::model::shared_spring::SharedSpring;
use crate::model::viscous_contact::ViscousContact;
use crate::scene::memory_budget::SolveSize;
use crate::scene::scene_format::{ModelKind, RelaxationSpec};
use crate::scene::scene_geometry::SharedShape;
use crate::scene::texture_spec::GapSpec;

/// How a finger is driven.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// Position-held: its normal load is an unknown of the program.
    Held,
    /// Force-controlled: `sum_k F_k = P` with `P` in newtons.
    NormalLoad {
        /// Prescribed total normal force `P_i`, N.
        newtons: f64,
    },
    /// Position-controlled: moved `d` metres along its inward normal from first touch (every
    /// element's gap closes by `d`); its normal load is an unknown of the program, as a held
    /// finger's (`d = 0`).
    Approach {
        /// The prescribed approach `d`, m.
        metres: f64,
    },
}

impl Control {
    /// The prescribed approach, m: `d` for a position-controlled finger, 0 otherwise (a held
    /// finger is the reference; a force-controlled one's approach is an unknown).
    pub fn approach_m(&self) -> f64 {
        match *self {
            Control::Approach { metres } => metres,
            _ => 0.0,
        }
    }
}

/// One finger, fully prepared: read-only outside this crate (its accessors below); a model
/// changes only where its matrices change ([`GraspModel::restricted`],
/// a viscoelastic model's time step, `GraspModel::for_time_step`).
#[derive(Debug, Clone)]
pub struct FingerModel {
    /// Name from the scene.
    pub(crate) name: String,
    /// Its index among the scene's fingers (`fingers[i]` in messages), kept by a model
    /// restricted to some of them ([`GraspModel::restricted`]), whose own order differs.
    pub(crate) scene_index: usize,
    /// Contact frame (`normal` into the object).
    pub(crate) frame: ContactFrame,
    /// Patch geometry and initial gaps.
    pub(crate) patch: Patch,
    /// Fingertip material.
    pub(crate) material: Material,
    /// The contact's two bodies (finger, object): their half-space constants and layers.
    pub(crate) contact: ContactPair,
    /// Friction law.
    pub(crate) friction: FrictionLaw,
    /// Tangential unknowns per element: 0 (frictionless), 1 (planar) or 2.
    pub(crate) n_tangential: usize,
    /// Patch compliance `C`, m/N, `(1 + n_tangential) N` square (`model/influence.rs`), dense
    /// or as the FFT operator; shared by the models restricted to some fingers.
    pub(crate) compliance_m_per_n: PatchCompliance,
    /// How the finger is driven (as in the scene; loads and approaches are given per solve).
    pub(crate) control: Control,
    /// The spring behind the finger's rigid core (`fingers[i].mount`; `None`: rigid), already
    /// in `compliance_m_per_n`; kept for its preload and the core's displacement.
    pub(crate) mount: Option<Arc<FingerMount>>,
    /// The contact's viscoelastic bodies (`None`: both elastic or rigid): their own
    /// compliances and creep functions (`model/viscous_contact.rs`).
    pub(crate) viscous: Option<Arc<ViscousContact>>,
    /// Index of this finger's first unknown in the program's `x`.
    pub(crate) offset: usize,
    /// True when the initial gaps are the exact ones from the shapes (`model/surface_gap.rs`),
    /// false for the thesis's quadratic form.
    pub(crate) exact_gaps: bool,
}

impl FingerModel {
    /// Name from the scene.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Contact frame (`normal` into the object).
    pub fn frame(&self) -> &ContactFrame {
        &self.frame
    }

    /// Patch geometry (grid, element centres) and initial gaps.
    pub fn patch(&self) -> &Patch {
        &self.patch
    }

    /// The spring behind the finger's rigid core (`None`: rigid).
    pub fn mount(&self) -> Option<&FingerMount> {
        self.mount.as_deref()
    }

    /// Fingertip material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// Tangential unknowns per element: 0 (frictionless), 1 (planar) or 2.
    pub fn n_tangential(&self) -> usize {
        self.n_tangential
    }

    /// Which form the patch compliance takes: `true` for the FFT operator, `false` for the
    /// dense matrix.
    pub fn compliance_is_fft(&self) -> bool {
        self.compliance_m_per_n.is_fft()
    }

    /// The patch compliance `C`, m/N (`(1 + n_tangential) N` square, the unknown layout of
    /// the module docs), written out: the dense matrix, or the FFT operator's entries for a
    /// patch small enough to write out; `None` for a larger FFT patch.
    pub fn compliance_matrix_m_per_n(&self) -> Option<Arc<nalgebra::DMatrix<f64>>> {
        self.compliance_m_per_n.matrix()
    }

    /// How the finger is driven, as the scene (or the restriction that made this model) says.
    pub fn control(&self) -> Control {
        self.control
    }

    /// True when the contact has a viscoelastic body.
    pub fn is_viscoelastic(&self) -> bool {
        self.viscous.is_some()
    }

    /// True when the initial gaps are the exact ones from the shapes, false for the thesis's
    /// quadratic form.
    pub fn has_exact_gaps(&self) -> bool {
        self.exact_gaps
    }

    /// Friction coefficient of the finger's law at total normal load `p_n` (N).
    pub fn mu_at(&self, p_n: f64) -> f64 {
        self.friction.mu_at(p_n)
    }

    /// Index of this finger's first unknown in the program's `x`.
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// Number of unknowns of this finger.
    pub fn n_unknowns(&self) -> usize {
        self.patch.len() * (1 + self.n_tangential)
    }

    /// True when this finger's compliance is an FFT operator too large to write out as a
    /// matrix (more than `MATERIALISED_UNKNOWNS`, 3,072, unknowns):
    /// Clarabel, the interior-point fallback and the sensitivities cannot take it.
    pub fn is_matrix_free(&self) -> bool {
        self.compliance_m_per_n.is_fft()
            && self.n_unknowns() > crate::model::patch_compliance::MATERIALISED_UNKNOWNS
    }

    /// Unit direction (world) of component `c` (0 normal, 1 `t1`, 2 `t2`).
    pub fn direction(&self, c: usize) -> Vector3<f64> {
        match c {
            0 => self.frame.normal,
            1 => self.frame.t1,
            _ => self.frame.t2,
        }
    }

    /// World position of element `k`'s centre, m.
    pub fn element_point(&self, k: usize) -> Vector3<f64> {
        let [x, y] = self.patch.centres_m[k];
        self.frame.point(x, y)
    }
}

/// Non-dimensionalisation of the program (model.md, "Scale before solving").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// Load scale, N: the largest of the weight, external forces and prescribed loads (1 N if
    /// all vanish).
    pub load_n: f64,
    /// Element force unit `Fu = load / (largest element count of a patch)`, N.
    pub element_force_n: f64,
    /// Compliance unit `Cu`, m/N: the largest diagonal entry of any patch compliance.
    pub compliance_m_per_n: f64,
    /// Length unit `Lu`, m, for moment rows: the largest distance of a contact point or patch
    /// corner from the reference point.
    pub length_m: f64,
}

impl Scales {
    /// Displacement unit `Fu Cu`, m: the size of a typical elastic approach.
    pub fn displacement_m(&self) -> f64 {
        self.element_force_n * self.compliance_m_per_n
    }
}

/// A force on the object (weight or external force): world vector, N, at a world point, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExternalLoad {
    /// Force, N.
    pub force_n: Vector3<f64>,
    /// Point of application, m.
    pub point_m: Vector3<f64>,
}

/// What a model keeps of the scene besides its fingers (to restrict it to some fingers).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ObjectModel {
    /// Object centre of mass, m.
    pub center_of_mass_m: Vector3<f64>,
    /// Weight (first, when nonzero) and external forces.
    pub loads: Vec<ExternalLoad>,
    /// Object material.
    pub material: Material,
    /// Thickness of the object's elastic layer on a rigid core, m (`None`: a half-space).
    pub layer_thickness_m: Option<f64>,
    /// The object material's relaxation law, as written (`None`: elastic).
    pub relaxation: Option<RelaxationSpec>,
    /// Plane of motion of a planar scene.
    pub plane: Option<MotionPlane>,
    /// Contact law.
    pub kind: ModelKind,
    /// The scene's warnings (its shape checks: a patch over an edge, overlapping patches, an
    /// open mesh), carried by every solution of the model.
    pub scene_warnings: Vec<String>,
    /// The object's posed shape (`None` without `object.shape`), for exact gaps.
    pub shape: Option<SharedShape>,
    /// The object shape's surface as triangles, world frame, m (`None` without
    /// `object.shape`), for drawing.
    pub surface: Option<Arc<TriangleMesh>>,
    /// Per finger, its posed `tip.shape` (empty without `object.shape`), for exact gaps.
    pub tip_shapes: Vec<Option<SharedShape>>,
    /// The scene's `gap`: how every finger's smooth gap is computed unless it says otherwise.
    pub gap: Option<GapSpec>,
    /// The springs several fingers share (`hands`, `servos`), their fingers by scene index.
    pub springs: Vec<SharedSpring>,
}

/// The immutable grasp model: read-only outside this crate (its accessors below).
#[derive(Debug, Clone)]
pub struct GraspModel {
    /// Fingers in scene order.
    pub(crate) fingers: Vec<FingerModel>,
    /// Reference point `O` of moments and of the rigid displacement: centroid of the contact
    /// points, m.
    pub(crate) reference_point_m: Vector3<f64>,
    /// External wrench on the object (weight and external forces), moments about `O`.
    pub(crate) external_wrench: Wrench,
    /// Scales of the program.
    pub(crate) scales: Scales,
    /// Scaled equilibrium map.
    pub(crate) equilibrium: EquilibriumMap,
    /// Total number of unknowns.
    pub(crate) n_unknowns: usize,
    /// The springs several of these fingers share, their fingers by model index (those with
    /// none of their fingers in the model left out).
    pub(crate) springs: Vec<SharedSpring>,
    /// The scene's object and loads (also for [`GraspModel::restricted`]).
    pub(crate) object: ObjectModel,
}

/// Smallest frozen friction coefficient of a frictional finger. The energy model's cone
/// `(mu F, G)` implies `F >= 0` only while `mu > 0`, and a very thin cone stalls an
/// interior-point method: with a floor of 1e-6, the unloaded finger f4 of the plate example
/// under the law of thesis eq. (40) (`mu(0) = 0`) came back "almost solved" with a negative
/// load. A finger frozen at this floor carries at most `1e-3` of its normal force as friction.
pub const MU_FLOOR: f64 = 1e-3;

impl GraspModel {
    /// Fingers in scene order.
    pub fn fingers(&self) -> &[FingerModel] {
        &self.fingers
    }

    /// The finger named `name`, with its index.
    pub fn finger(&self, name: &str) -> Option<(usize, &FingerModel)> {
        self.fingers
            .iter()
            .enumerate()
            .find(|(_, f)| f.name == name)
    }

    /// Plane of motion of a planar scene.
    pub fn plane(&self) -> Option<MotionPlane> {
        self.object.plane
    }

    /// Reference point `O` of moments and of the rigid displacement: the centroid of the
    /// contact points, m.
    pub fn reference_point_m(&self) -> Vector3<f64> {
        self.reference_point_m
    }

    /// Object centre of mass, m.
    pub fn center_of_mass_m(&self) -> Vector3<f64> {
        self.object.center_of_mass_m
    }

    /// External wrench on the object from the scene (weight and external forces; N, N m
    /// about `O`); a solve adds its [`crate::StepInputs`]' extra wrench.
    pub fn external_wrench(&self) -> Wrench {
        self.external_wrench
    }

    /// Scales of the program (model.md, "Scale before solving").
    pub fn scales(&self) -> Scales {
        self.scales
    }

    /// Number of equilibrium rows: 6 in 3-D, 3 in a planar scene (thesis eqs. 48-49).
    pub fn equilibrium_rows(&self) -> usize {
        self.equilibrium.rows()
    }

    /// Total number of unknowns (the program's `x`).
    pub fn n_unknowns(&self) -> usize {
        self.n_unknowns
    }

    /// Contact law.
    pub fn kind(&self) -> ModelKind {
        self.object.kind
    }

    /// Object material.
    pub fn object_material(&self) -> &Material {
        &self.object.material
    }

    /// The scene's warnings (its shape checks, the layers' resolution), carried by every
    /// solution of the model.
    pub fn scene_warnings(&self) -> &[String] {
        &self.object.scene_warnings
    }

    /// The object shape's surface as triangles, world frame, m, for drawing (`None` without
    /// `object.shape`).
    pub fn object_surface(&self) -> Option<&TriangleMesh> {
        self.object.surface.as_deref()
    }

    /// A first guess of each finger's total normal load, N: the prescribed load of a
    /// force-controlled finger, an equal share of the load scale for a held one.
    pub fn guess_loads(&self, loads_n: &[f64]) -> Vec<f64> {
        let share = self.scales.load_n / self.fingers.len().max(1) as f64;
        let mut j = 0;
        self.fingers
            .iter()
            .map(|f| match f.control {
                Control::NormalLoad { .. } => {
                    j += 1;
                    loads_n.get(j - 1).copied().unwrap_or(share)
                }
                Control::Held | Control::Approach { .. } => share,
            })
            .collect()
    }

    /// Each finger's friction coefficient to freeze at finger loads `p_n` (N): its law at that
    /// load, at least `MU_FLOOR`; 0 for frictionless fingers.
    pub fn mu_at(&self, p_n: &[f64]) -> Vec<f64> {
        self.fingers
            .iter()
            .zip(p_n)
            .map(|(f, &p)| {
                if f.n_tangential == 0 {
                    0.0
                } else {
                    f.friction.mu_at(p).max(MU_FLOOR)
                }
            })
            .collect()
    }

    /// The size of a solve of this model's work (its memory:
    /// [`SolveSize::bytes`]).
    pub fn solve_size(&self) -> SolveSize {
        // A shared spring adds its coordinates as unknowns and as equality rows.
        let springs: usize = self.springs.iter().map(|s| s.coordinates()).sum();
        SolveSize {
            unknowns: self.n_unknowns + springs,
            equality_rows: self.equilibrium_rows() + self.fingers.len() + springs,
            elements: self.fingers.iter().map(|f| f.patch.len()).sum(),
        }
    }

    /// The model of the fingers `active` (index into this model's fingers, with the control
    /// each has), in that order, sharing their compliance blocks: the grasp of one hand-off
    /// step. `None` when `active` is empty or names a finger this model does not have.
    pub fn restricted(&self, active: &[(usize, Control)]) -> Option<GraspModel> {
        if active.is_empty() {
            return None;
        }
        let fingers = active
            .iter()
            .map(|&(i, control)| {
                let mut f = self.fingers.get(i)?.clone();
                f.control = control;
                Some(f)
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Self::from_parts(fingers, self.object.clone()))
    }

    /// True when a contact has a viscoelastic body.
    pub fn is_viscoelastic(&self) -> bool {
        self.fingers.iter().any(|f| f.viscous.is_some())
    }

    /// The model of one time step of `dt_s` seconds (`f64::INFINITY`: fully relaxed): every
    /// viscoelastic contact's compliance is its compliance over the step
    /// (`ViscousContact::step_compliance`; `dt_s = 0` gives the instantaneous one, this
    /// model's), the elastic fingers' are shared. A solve of a time step builds it
    /// ([`crate::GraspSolver::solve_step`] with [`crate::StepInputs::time_step_s`]).
    pub(crate) fn for_time_step(&self, dt_s: f64) -> Result<GraspModel, OutOfMemory> {
        if !self.is_viscoelastic() {
            return Ok(self.clone());
        }
        let fingers = self
            .fingers
            .iter()
            .map(|f| {
                let mut f = f.clone();
                if let Some(v) = &f.viscous {
                    f.compliance_m_per_n = v.step_compliance(dt_s)?;
                    // The mount is elastic: its retreat is the same at every time step.
                    if let Some(m) = &f.mount {
                        f.compliance_m_per_n = f.compliance_m_per_n.clone().with_mount(m);
                    }
                }
                Ok(f)
            })
            .collect::<Result<_, OutOfMemory>>()?;
        Ok(Self::from_parts(fingers, self.object.clone()))
    }

    /// Offsets, reference point, external wrench, scales and equilibrium map of `fingers` (at
    /// least one) holding `object`.
    pub(crate) fn from_parts(mut fingers: Vec<FingerModel>, object: ObjectModel) -> GraspModel {
        let mut offset = 0;
        for f in &mut fingers {
            f.offset = offset;
            offset += f.n_unknowns();
        }
        let reference_point_m = fingers
            .iter()
            .map(|f| f.frame.origin_m)
            .sum::<Vector3<f64>>()
            / fingers.len() as f64;
        let mut external_wrench = Wrench::zeros();
        let mut load_n: f64 = 0.0;
        for l in &object.loads {
            let mag = l.force_n.norm();
            if mag > 0.0 {
                external_wrench +=
                    unit_wrench(&(l.force_n / mag), &l.point_m, &reference_point_m) * mag;
            }
            load_n = load_n.max(mag);
        }
        for f in &fingers {
            if let Control::NormalLoad { newtons } = f.control {
                load_n = load_n.max(newtons);
            }
        }
        if load_n <= 0.0 {
            load_n = 1.0;
        }
        let scales = scales_of(&fingers, load_n, &reference_point_m);
        let equilibrium = EquilibriumMap::new(scales.length_m, object.plane);
        let springs = springs_of(&fingers, &object.springs);
        GraspModel {
            springs,
            fingers,
            reference_point_m,
            external_wrench,
            scales,
            equilibrium,
            n_unknowns: offset,
            object,
        }
    }

    /// The springs several of the fingers share (hands, servos), their fingers by model index.
    pub fn springs(&self) -> &[SharedSpring] {
        &self.springs
    }

    /// Indices of the force-controlled fingers, in scene order.
    pub fn force_controlled(&self) -> Vec<usize> {
        (0..self.fingers.len())
            .filter(|&i| matches!(self.fingers[i].control, Control::NormalLoad { .. }))
            .collect()
    }

    /// The prescribed loads of the scene (N), one per force-controlled finger.
    pub fn scene_loads_n(&self) -> Vec<f64> {
        self.force_controlled()
            .iter()
            .map(|&i| match self.fingers[i].control {
                Control::NormalLoad { newtons } => newtons,
                Control::Held | Control::Approach { .. } => 0.0,
            })
            .collect()
    }

    /// Checks a vector of prescribed loads (one per force-controlled finger, N).
    pub fn check_loads(&self, loads_n: &[f64]) -> Result<(), ModelError> {
        let fc = self.force_controlled();
        if fc.len() != loads_n.len() {
            return Err(ModelError::LoadCount {
                expected: fc.len(),
                got: loads_n.len(),
            });
        }
        for (&i, &p) in fc.iter().zip(loads_n) {
            if !(p.is_finite() && p >= 0.0) {
                return Err(ModelError::BadLoad {
                    finger: self.fingers[i].name.clone(),
                    value: p,
                });
            }
        }
        Ok(())
    }

    /// World wrench (moments about `O`) of a unit force in component `c` of element `k` of
    /// finger `i`: the column of the equilibrium matrix (thesis eqs. 48-49).
    pub fn unit_wrench(&self, i: usize, k: usize, c: usize) -> Wrench {
        let f = &self.fingers[i];
        unit_wrench(
            &f.direction(c),
            &f.element_point(k),
            &self.reference_point_m,
        )
    }

    /// Wrench about `O` (N, N m) of a force `force_n` (N, world) applied at the centre of mass
    /// plus a couple `torque_nm` (N m, world): `(f, t + (r - O) x f)` (thesis eq. 49's moment
    /// of an external force).
    pub fn wrench_at_center_of_mass(
        &self,
        force_n: &Vector3<f64>,
        torque_nm: &Vector3<f64>,
    ) -> Wrench {
        let m = torque_nm + (self.center_of_mass_m() - self.reference_point_m).cross(force_n);
        Wrench::new(force_n.x, force_n.y, force_n.z, m.x, m.y, m.z)
    }

    /// Net wrench (N, N m about `O`) of contact forces `x` (N, program layout) plus the external
    /// wrench `external` (N, N m about `O`): zero at equilibrium (thesis eqs. 48-49).
    pub fn net_wrench(&self, x_n: &[f64], external: &Wrench) -> Wrench {
        let mut w = *external;
        for (i, f) in self.fingers.iter().enumerate() {
            let n = f.patch.len();
            for c in 0..=f.n_tangential {
                for k in 0..n {
                    let v = x_n[f.offset + c * n + k];
                    if v != 0.0 {
                        w += self.unit_wrench(i, k, c) * v;
                    }
                }
            }
        }
        w
    }
}

/// Scales of a model (model.md, "Scale before solving"): `load_n` over the largest element
/// count, the largest compliance diagonal, the largest reach from the reference point.
fn scales_of(fingers: &[FingerModel], load_n: f64, reference_point_m: &Vector3<f64>) -> Scales {
    let max_elems = fingers.iter().map(|f| f.patch.len()).max().unwrap_or(1);
    let compliance = fingers
        .iter()
        .map(|f| f.compliance_m_per_n.max_diagonal())
        .fold(0.0_f64, f64::max);
    let length_m = fingers
        .iter()
        .map(|f| {
            let half = 0.5
                * (f.patch.grid.hx * f.patch.grid.nx as f64)
                    .hypot(f.patch.grid.hy * f.patch.grid.ny as f64);
            (f.frame.origin_m - reference_point_m).norm() + half
        })
        .fold(0.0_f64, f64::max);
    Scales {
        load_n,
        element_force_n: load_n / max_elems as f64,
        compliance_m_per_n: compliance,
        length_m,
    }
}

/// The shared springs `scene_springs` (fingers by scene index) as they act on `fingers`: each
/// one's fingers by index into `fingers`, the springs with none of them left out.
fn springs_of(fingers: &[FingerModel], scene_springs: &[SharedSpring]) -> Vec<SharedSpring> {
    scene_springs
        .iter()
        .filter_map(|s| {
            let members: Vec<usize> = (0..fingers.len())
                .filter(|&i| s.fingers.contains(&fingers[i].scene_index))
                .collect();
            (!members.is_empty()).then(|| SharedSpring {
                fingers: members,
                ..s.clone()
            })
        })
        .collect()
}
