//! The scene file: plain data as the user writes it (JSON, SI units).
//!
//! These types are the on-disk format. They carry no derived quantities; [`crate::GraspModel`]
//! is built from a validated scene (see [`crate::validation`]). Field names are part of the file
//! format and must stay stable between versions.
//!
//! Conventions (fixed by the format):
//! - lengths in metres, forces in newtons, moduli in pascals;
//! - `fingers[i].normal` points INTO the object: it is the direction of the normal force the
//!   finger applies to the object;
//! - `fingers[i].tangent` (optional) is the first tangent axis `t1` of the patch; `t2 = n x t1`
//!   so that `t1 x t2 = n`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A 3-vector as written in the file (`[x, y, z]`).
pub type Vec3 = [f64; 3];

/// A grasp scene: one object held by fingers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text: what the scene is and what it assumes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// `null` for a 3-D scene; otherwise the scene is planar, with every contact point and the
    /// centre of mass in one plane of this normal and every finger normal in that plane.
    #[serde(default)]
    pub planar: Option<PlanarSpec>,
    /// The grasped object.
    pub object: ObjectSpec,
    /// The fingers in contact with the object.
    pub fingers: Vec<FingerSpec>,
    /// Which contact law resolves the grasp.
    #[serde(default)]
    pub model: ModelKind,
}

/// The plane of a planar scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanarSpec {
    /// Normal of the plane of motion (any nonzero length; normalised on load).
    pub normal: Vec3,
}

/// The grasped object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    /// Weight `W` in newtons (>= 0).
    pub weight: f64,
    /// Centre of mass `r` in metres (world frame).
    pub center_of_mass: Vec3,
    /// Direction of gravity (any nonzero length; normalised on load). Default `[0, 0, -1]`.
    #[serde(default = "default_gravity")]
    pub gravity: Vec3,
    /// Material of the object near the contacts.
    pub material: MaterialSpec,
    /// Further external forces `R_j` (N) applied at points `d_j` (m).
    #[serde(default)]
    pub external_forces: Vec<ExternalForceSpec>,
}

fn default_gravity() -> Vec3 {
    [0.0, 0.0, -1.0]
}

/// An external force on the object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExternalForceSpec {
    /// Force in newtons (world frame).
    pub force: Vec3,
    /// Point of application in metres (world frame).
    pub at: Vec3,
}

/// A linear-elastic isotropic material, or `"rigid"` (`1/E = 0`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "expected a material: \"rigid\" or {\"youngs_modulus\": Pa, \"poisson_ratio\": -}"
)]
pub enum MaterialSpec {
    /// A rigid body.
    Rigid(RigidTag),
    /// An elastic body.
    Elastic(ElasticSpec),
}

/// The literal string `"rigid"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum RigidTag {
    /// A rigid body.
    Rigid,
}

/// Elastic constants.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElasticSpec {
    /// Young's modulus `E` in pascals (> 0).
    pub youngs_modulus: f64,
    /// Poisson's ratio `nu`, dimensionless, in `[0, 0.5)`.
    pub poisson_ratio: f64,
}

/// One finger in contact with the object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FingerSpec {
    /// Unique name, used in every report.
    pub name: String,
    /// Initial contact point `v_i` on the object surface, metres (world frame).
    pub contact_point: Vec3,
    /// Contact normal `n_i`, pointing INTO the object (any nonzero length; normalised).
    pub normal: Vec3,
    /// Optional first tangent axis `t1` (projected onto the plane normal to `n`). In a planar
    /// scene it must be omitted or lie in the plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangent: Option<Vec3>,
    /// Material of the fingertip.
    pub material: MaterialSpec,
    /// Fingertip radius of curvature in metres; `null` for a flat tip.
    #[serde(default)]
    pub tip_radius: Option<f64>,
    /// Local radius of curvature of the object at the contact in metres: `null` (flat), one
    /// number (sphere-like), or `[R1, R2]` principal radii along `t1` and `t2` (either may be
    /// `null`; a cylinder whose axis runs along `t2` is `[R, null]`).
    #[serde(default)]
    pub object_radius: Option<RadiusSpec>,
    /// The candidate contact patch.
    pub patch: PatchSpec,
    /// Friction law of this contact.
    pub friction: FrictionSpec,
    /// How the finger is driven.
    #[serde(default)]
    pub control: ControlSpec,
}

/// Curvature radius of the object at a contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "expected a radius in metres, or [R1, R2] with each a number or null"
)]
pub enum RadiusSpec {
    /// The same radius in every direction.
    Isotropic(f64),
    /// Principal radii along `t1` and `t2`; `null` for flat in that direction.
    Principal([Option<f64>; 2]),
}

/// The rectangular candidate contact patch centred on the contact point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PatchSpec {
    /// Side lengths `[Lx, Ly]` in metres along `t1`, `t2`.
    pub size: [f64; 2],
    /// Elements `[nx, ny]` along `t1`, `t2` (each >= 1).
    pub grid: [usize; 2],
}

/// Friction law of a contact (thesis section 2.6): `{"mu": c}`, `{"table": [[P, mu], ...]}` or
/// `{"elastic": {...}}` (thesis eq. 40).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "expected a friction law: {\"mu\": c}, {\"table\": [[P_N, mu], ...]} or \
                 {\"elastic\": {\"finger_radius\": m, \"object_radius\": m, \"contact_length\": m}}"
)]
pub enum FrictionSpec {
    /// A constant Coulomb coefficient.
    Coefficient(CoefficientSpec),
    /// A measured coefficient, piecewise linear in the finger's normal load.
    Table(TableSpec),
    /// Villaggio's elastic law (thesis eq. 40), `mu` growing like `sqrt(P)`.
    Elastic(ElasticLawSpec),
}

impl FrictionSpec {
    /// A constant coefficient `mu`.
    pub fn constant(mu: f64) -> Self {
        FrictionSpec::Coefficient(CoefficientSpec { mu })
    }

    /// True when `mu` is zero at every load (the finger then has no tangential unknowns).
    pub fn is_frictionless(&self) -> bool {
        match self {
            FrictionSpec::Coefficient(c) => c.mu == 0.0,
            FrictionSpec::Table(t) => t.table.iter().all(|p| p[1] == 0.0),
            FrictionSpec::Elastic(_) => false,
        }
    }
}

/// A constant Coulomb coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CoefficientSpec {
    /// Coulomb coefficient `mu` (>= 0; 0 is a frictionless finger with no tangential unknowns).
    pub mu: f64,
}

/// A measured friction coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// Points `[P, mu]`: the finger's total normal load `P` in newtons (>= 0, strictly
    /// increasing) and the coefficient there (>= 0). Linear in between, constant outside.
    pub table: Vec<[f64; 2]>,
}

/// The elastic friction law of thesis eq. (40).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElasticLawSpec {
    /// Parameters of eq. (40).
    pub elastic: ElasticLawParams,
}

/// Parameters of thesis eq. (40); the moduli and Poisson ratios are the finger's and the
/// object's materials (the object must be elastic).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElasticLawParams {
    /// `R1`: radius of curvature of the finger at the contact, m (> 0).
    pub finger_radius: f64,
    /// `R2`: radius of curvature of the object at the contact, m (> `R1`).
    pub object_radius: f64,
    /// `L`: length of the line contact, m (> 0). Eq. (40) is a plane-strain law in the load
    /// per unit length `P / L`.
    pub contact_length: f64,
}

/// How a finger is driven.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "expected a control: \"held\" or {\"normal_load\": N}"
)]
pub enum ControlSpec {
    /// Position-held: its load is found by the model.
    Held(HeldTag),
    /// Force-controlled: the total normal force is prescribed.
    Load(NormalLoadSpec),
}

impl Default for ControlSpec {
    fn default() -> Self {
        ControlSpec::Held(HeldTag::Held)
    }
}

impl ControlSpec {
    /// The prescribed normal load in newtons, if the finger is force-controlled.
    pub fn normal_load_n(&self) -> Option<f64> {
        match self {
            ControlSpec::Load(l) => Some(l.normal_load),
            _ => None,
        }
    }
}

/// The literal string `"held"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum HeldTag {
    /// Position-held.
    Held,
}

/// A prescribed normal load.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NormalLoadSpec {
    /// Total normal force `P_i` in newtons (>= 0).
    pub normal_load: f64,
}

/// The contact law that resolves the grasp.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema, Default)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// Minimum complementary energy with associated friction cones (model.md, "energy").
    #[default]
    Energy,
    /// Non-associated Coulomb friction: Tresca cones of radius `mu F_k` from the previous
    /// iterate, iterated to a fixed point, with slip memory between steps (model.md,
    /// "coulomb").
    Coulomb,
}

/// The JSON Schema of the scene format, generated from these types.
pub fn scene_json_schema() -> schemars::Schema {
    schemars::schema_for!(Scene)
}
