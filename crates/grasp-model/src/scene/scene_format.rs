//! The scene file: plain data as the user writes it (JSON, SI units).
//!
//! These types are the on-disk format, plain data and nothing else: what reading a scene finds
//! beyond them (the posed shapes, the height maps' heights) travels beside them
//! ([`crate::scene::scene_geometry::SceneGeometry`], in a
//! [`crate::scene::loaded_scene::LoadedScene`]); [`crate::GraspModel`] is built from a
//! validated scene (see [`crate::scene::scene_validation`]). Field names are part of the file
//! format and must stay stable between versions.
//!
//! Conventions (fixed by the format):
//! - lengths in metres, forces in newtons, moduli in pascals;
//! - `fingers[i].normal` points INTO the object: it is the direction of the normal force the
//!   finger applies to the object;
//! - `fingers[i].tangent` (optional) is the first tangent axis `t1` of the patch; `t2 = n x t1`
//!   so that `t1 x t2 = n`.

use schemars::JsonSchema;
use serde::de::Deserializer;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::scene::strict_json::{describe, variant, StrictValue};

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
    /// How every finger's smooth initial gap is computed, unless the finger says otherwise:
    /// `"exact"` (the default when the object has a shape) or `"quadratic"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<crate::scene::texture_spec::GapSpec>,
    /// Bases that carry several fingers on one stiffness to the world (an arm, a wrist):
    /// `{"name": h, "fingers": [..], "origin_m": p, "translational_n_per_m": k,
    /// "rotational_nm_per_rad": kr}` or a 6x6 `matrix` (world frame, about `origin_m`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hands: Vec<crate::scene::shared_spring_spec::HandSpec>,
    /// Drives that move several jaws equal and opposite on one stiffness: `{"name": s,
    /// "fingers": [a, b], "stiffness_n_per_m": k}` (`sum F_jaw = k (x_commanded - x)`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub servos: Vec<crate::scene::shared_spring_spec::ServoSpec>,
}

impl Scene {
    /// The fingers' names, in scene order (a schedule's and a history's finger names).
    pub fn finger_names(&self) -> Vec<String> {
        self.fingers.iter().map(|f| f.name.clone()).collect()
    }
}

/// The plane of a planar scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanarSpec {
    /// Normal of the plane of motion (any finite nonzero length; normalised on load, scaled by
    /// its largest component first).
    pub normal: Vec3,
}

/// The grasped object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    /// Weight `W` in newtons: 0 or in `[1e-15, 1e7]`. Required unless `density` is given.
    pub weight: f64,
    /// Centre of mass `r` in metres (world frame), each coordinate in `[-1e3, 1e3]`. Required
    /// unless `density` is given.
    pub center_of_mass: Vec3,
    /// The object's shape and pose (optional): fingers can then be placed on it (`place`),
    /// and explicit frames are checked against it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<crate::scene::shape_spec::ShapeSpec>,
    /// Density, kg/m^3, in `[1e-3, 1e5]`: with a shape, the weight (`rho V g0`, g0 = 9.80665
    /// m/s^2) and centre of mass (the centroid) follow; give it instead of `weight` and
    /// `center_of_mass`.
    #[serde(default, skip_serializing)]
    pub density: Option<f64>,
    /// Direction of gravity (any finite nonzero length; normalised on load, scaled by its
    /// largest component first). Default `[0, 0, -1]`.
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
    /// Force in newtons (world frame), each component 0 or of magnitude in `[1e-15, 1e7]`.
    pub force: Vec3,
    /// Point of application in metres (world frame), each coordinate in `[-1e3, 1e3]`.
    pub at: Vec3,
}

/// A linear-elastic isotropic material, or `"rigid"` (`1/E = 0`).
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElasticSpec {
    /// Young's modulus `E` in pascals, in `[1, 1e15]`.
    pub youngs_modulus: f64,
    /// Poisson's ratio `nu`, dimensionless, in `[0, 0.5)`.
    pub poisson_ratio: f64,
    /// Thickness `h` in metres of an elastic layer of this material bonded to a rigid core (a
    /// fingertip pad on its phalanx, a coating on a rigid object), in `[1e-6, 1]`; absent: the
    /// body is an elastic half-space. A layer is stiffer than the half-space where the contact
    /// is wider than about `h`: normally (towards `E (1 - nu)/((1 + nu)(1 - 2 nu) h)` per unit
    /// area, the Winkler limit) and tangentially (towards `G / h`), and it couples the normal
    /// and tangential responses even against a rigid partner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_thickness_m: Option<f64>,
    /// How the material relaxes (a viscoelastic pad): a Prony series of the shear modulus,
    /// `[{"fraction": g_i, "time_s": tau_i}, ...]` (`G(t) = G_0 (1 - sum g_i) + sum g_i G_0
    /// exp(-t / tau_i)`, each `g_i` in `[0, 1)` with `sum g_i < 1`, each `tau_i` in `[1e-6,
    /// 1e9]` s), or a standard linear solid `{"long_term_modulus": Pa, "time_s": tau}` (`E`
    /// relaxing from `youngs_modulus` to `long_term_modulus` with the one relaxation time).
    /// `youngs_modulus` is then the instantaneous modulus; Poisson's ratio stays constant, so
    /// every compliance of the body follows the same creep function. Absent, or all fractions
    /// zero: elastic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relaxation: Option<RelaxationSpec>,
}

/// A material's relaxation law.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum RelaxationSpec {
    /// A Prony series of the shear modulus (at most 32 terms).
    Prony(Vec<PronyTermSpec>),
    /// A standard linear solid: instantaneous modulus `youngs_modulus`, long-term modulus and
    /// one relaxation time.
    StandardLinearSolid(StandardLinearSolidSpec),
}

/// One term of a Prony series.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PronyTermSpec {
    /// `g_i`: the fraction of the instantaneous shear modulus that relaxes with this time, in
    /// `[0, 1)` (the fractions sum below 1).
    pub fraction: f64,
    /// `tau_i`: relaxation time, s, in `[1e-6, 1e9]`.
    pub time_s: f64,
}

/// A standard linear solid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StandardLinearSolidSpec {
    /// Young's modulus after full relaxation, Pa, in `(0, youngs_modulus]`.
    pub long_term_modulus: f64,
    /// Relaxation time, s, in `[1e-6, 1e9]`.
    pub time_s: f64,
}

impl MaterialSpec {
    /// The layer thickness, m, of a material that is a layer on a rigid core.
    pub fn layer_thickness_m(&self) -> Option<f64> {
        match self {
            MaterialSpec::Rigid(_) => None,
            MaterialSpec::Elastic(e) => e.layer_thickness_m,
        }
    }

    /// The relaxation law of a viscoelastic material, as written.
    pub fn relaxation(&self) -> Option<&RelaxationSpec> {
        match self {
            MaterialSpec::Rigid(_) => None,
            MaterialSpec::Elastic(e) => e.relaxation.as_ref(),
        }
    }
}

/// One finger in contact with the object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FingerSpec {
    /// Unique name, used in every report.
    pub name: String,
    /// Where the finger touches the object's shape (`object.shape` required): a point on or
    /// near the surface, or an approach ray. The contact point, normal, tangent and object
    /// radii are then derived; give none of them.
    #[serde(default, skip_serializing)]
    pub place: Option<crate::scene::shape_spec::PlaceSpec>,
    /// Initial contact point `v_i` on the object surface, metres (world frame), each
    /// coordinate in `[-1e3, 1e3]`. Required unless `place` is given.
    pub contact_point: Vec3,
    /// Contact normal `n_i`, pointing INTO the object (any finite nonzero length; normalised
    /// on load, scaled by its largest component first). Required unless `place` is given.
    pub normal: Vec3,
    /// Optional first tangent axis `t1` (projected onto the plane normal to `n`). In a planar
    /// scene it must be omitted or lie in the plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangent: Option<Vec3>,
    /// Material of the fingertip.
    pub material: MaterialSpec,
    /// Fingertip radius of curvature in metres, in `[1e-9, 1e3]` and at least half the larger
    /// patch side; `null` for a flat tip.
    #[serde(default)]
    pub tip_radius: Option<f64>,
    /// The fingertip's shape near the contact: `{"sphere": {"radius": R}}`, `{"cylinder":
    /// {"radius": R, "axis": [x, y, z]}}` or `{"flat": {"size": [a, b]}}` (instead of
    /// `tip_radius`; omitted: flat).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip: Option<crate::scene::shape_spec::TipSpec>,
    /// Local radius of curvature of the object at the contact in metres: `null` (flat), one
    /// number (sphere-like), or `[R1, R2]` principal radii along `t1` and `t2` (either may be
    /// `null`; a cylinder whose axis runs along `t2` is `[R, null]`). Each radius in
    /// `[1e-9, 1e3]` and at least half the patch side along it.
    #[serde(default)]
    pub object_radius: Option<RadiusSpec>,
    /// The candidate contact patch.
    pub patch: PatchSpec,
    /// Friction law of this contact.
    pub friction: FrictionSpec,
    /// How the finger is driven.
    #[serde(default)]
    pub control: ControlSpec,
    /// How the smooth initial gap is computed: `"exact"` (from the shapes: the default when
    /// the object has a shape) or `"quadratic"` (the thesis's form from the curvatures; the
    /// default, and the only form, without a shape). Overrides the scene's `gap`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<crate::scene::texture_spec::GapSpec>,
    /// The surfaces' texture under the patch (heights added to the gap): `{"heights": {"file":
    /// "h.npy", "pixel_m": [dx, dy]}}`, `{"ridges": {...}}` or `{"random": {...}}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<crate::scene::texture_spec::TextureSpec>,
    /// A tactile sensor in the pad, read from the solved tractions (`grasp solve` prints and
    /// writes its readings): taxels at a depth, `{"taxels": {"count": [nx, ny], "pitch_m": p,
    /// "size_m": s, "depth_m": d}}`, markers on the surface, `{"markers": {"count": [nx, ny],
    /// "pitch_m": p}}`, or both. Omitted: none, and nothing is computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor: Option<crate::scene::sensor_spec::SensorSpec>,
    /// The stiffness behind the finger's rigid core: a spring to its commanded pose
    /// (`{"normal_n_per_m": k, "tangential_n_per_m": kt, "rotational_nm_per_rad": kr}` or
    /// `{"matrix": K}` in the contact frame, and `preload_n`). Omitted: the core is rigid
    /// (held where the control puts it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mount: Option<crate::scene::mount_spec::MountSpec>,
}

impl FingerSpec {
    /// Tangential unknowns per element of this finger (the program's layout, model.md): 0 for
    /// a frictionless finger, 1 in a planar scene (`planar`), 2 otherwise.
    pub fn tangential_unknowns(&self, planar: bool) -> usize {
        match (self.friction.is_frictionless(), planar) {
            (true, _) => 0,
            (false, true) => 1,
            (false, false) => 2,
        }
    }
}

/// Curvature radius of the object at a contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
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
    /// Side lengths `[Lx, Ly]` in metres along `t1`, `t2`, each in `[1e-9, 10]`.
    pub size: [f64; 2],
    /// Elements `[nx, ny]` along `t1`, `t2` (each in `[1, 2048]`, `nx ny <= 2048 x 2048`). The memory a
    /// solve needs grows like `(nx ny)^2` on the dense path and like `nx ny` on the FFT path;
    /// `grasp` refuses grids whose estimate exceeds `--max-memory`.
    pub grid: [usize; 2],
}

/// Friction law of a contact (thesis section 2.6): `{"mu": c}`, `{"table": [[P, mu], ...]}` or
/// `{"elastic": {...}}` (thesis eq. 40).
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
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
    /// Coulomb coefficient `mu`: 0 (a frictionless finger with no tangential unknowns) or in
    /// `[1e-6, 1e3]`.
    pub mu: f64,
}

/// A measured friction coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// Points `[P, mu]`: the finger's total normal load `P` in newtons (in `[0, 1e7]`,
    /// strictly increasing) and the coefficient there (0 or in `[1e-6, 1e3]`). Linear in between,
    /// constant outside.
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
    /// `R1`: radius of curvature of the finger at the contact, m, in `[1e-9, 1e3]`.
    pub finger_radius: f64,
    /// `R2`: radius of curvature of the object at the contact, m (> `R1`, <= 1e3).
    pub object_radius: f64,
    /// `L`: length of the line contact, m, in `[1e-9, 1e3]`. Eq. (40) is a plane-strain law in the load
    /// per unit length `P / L`.
    pub contact_length: f64,
}

/// How a finger is driven.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum ControlSpec {
    /// Position-held: its load is found by the model.
    Held(HeldTag),
    /// Force-controlled: the total normal force is prescribed.
    Load(NormalLoadSpec),
    /// Position-controlled: pressed in by a prescribed approach from first touch; its load is
    /// found by the model.
    Approach(ApproachSpec),
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

    /// The prescribed approach in metres, if the finger is position-controlled.
    pub fn approach_m(&self) -> Option<f64> {
        match self {
            ControlSpec::Approach(a) => Some(a.approach_m),
            _ => None,
        }
    }
}

/// A prescribed approach.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ApproachSpec {
    /// How far the finger is moved along its normal from first touch, m, in `[-1, 1]`: the gaps
    /// of its elements close by this much (the object still finds its equilibrium). 0 is a
    /// held finger; negative withdraws it (a jaw opened). With a `mount` it is the commanded
    /// position of the mount's far end (a servo's jaw position).
    pub approach_m: f64,
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
    /// Total normal force `P_i` in newtons: 0 or in `[1e-15, 1e7]`.
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

/// What a material looks like, for messages.
const EXPECT_MATERIAL: &str =
    "expected a material: \"rigid\" or {\"youngs_modulus\": Pa, \"poisson_ratio\": -}";
/// What a friction law looks like, for messages.
const EXPECT_FRICTION: &str = "expected a friction law: {\"mu\": c}, {\"table\": [[P_N, mu], \
     ...]} or {\"elastic\": {\"finger_radius\": m, \"object_radius\": m, \"contact_length\": m}}";
/// What a control looks like, for messages.
const EXPECT_CONTROL: &str =
    "expected a control: \"held\", {\"normal_load\": N} or {\"approach_m\": m}";
/// What a relaxation law looks like, for messages.
const EXPECT_RELAXATION: &str = "expected a relaxation law: [{\"fraction\": g, \"time_s\": s}, \
     ...] or {\"long_term_modulus\": Pa, \"time_s\": s}";
/// What a radius looks like, for messages.
const EXPECT_RADIUS: &str = "expected a radius in metres, or [R1, R2] with each a number or null";

/// The error for a value of the wrong shape: what was expected and what was found.
fn shape_error<E: serde::de::Error>(expected: &str, found: &Value) -> E {
    E::custom(format!("{expected}; found {}", describe(found)))
}

impl<'de> Deserialize<'de> for MaterialSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        match v {
            Value::String(ref s) if s == "rigid" => variant(v).map(MaterialSpec::Rigid),
            Value::Object(_) => variant(v).map(MaterialSpec::Elastic),
            v => Err(shape_error(EXPECT_MATERIAL, &v)),
        }
    }
}

impl<'de> Deserialize<'de> for RadiusSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        match v {
            Value::Number(_) => variant(v).map(RadiusSpec::Isotropic),
            Value::Array(_) => variant(v).map(RadiusSpec::Principal),
            v => Err(shape_error(EXPECT_RADIUS, &v)),
        }
    }
}

impl<'de> Deserialize<'de> for FrictionSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        let has = |k: &str| v.get(k).is_some();
        if has("mu") {
            variant(v).map(FrictionSpec::Coefficient)
        } else if has("table") {
            variant(v).map(FrictionSpec::Table)
        } else if has("elastic") {
            variant(v).map(FrictionSpec::Elastic)
        } else {
            Err(shape_error(EXPECT_FRICTION, &v))
        }
    }
}

impl<'de> Deserialize<'de> for ControlSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        match v {
            Value::String(ref s) if s == "held" => variant(v).map(ControlSpec::Held),
            Value::Object(ref o) if o.contains_key("approach_m") => {
                variant(v).map(ControlSpec::Approach)
            }
            Value::Object(_) => variant(v).map(ControlSpec::Load),
            v => Err(shape_error(EXPECT_CONTROL, &v)),
        }
    }
}

impl<'de> Deserialize<'de> for RelaxationSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        match v {
            Value::Array(_) => variant(v).map(RelaxationSpec::Prony),
            Value::Object(_) => variant(v).map(RelaxationSpec::StandardLinearSolid),
            v => Err(shape_error(EXPECT_RELAXATION, &v)),
        }
    }
}

/// The JSON Schema of the scene format, generated from these types (a finger's frame is
/// not required when it has `place`, nor the object's weight and centre of mass with a
/// `density`: the schema lists them as optional, the loader checks which applies).
pub fn scene_json_schema() -> schemars::Schema {
    let mut schema = schemars::schema_for!(Scene);
    for (def, keys) in [
        ("FingerSpec", ["contact_point", "normal"]),
        ("ObjectSpec", ["weight", "center_of_mass"]),
    ] {
        let required = schema
            .get_mut("$defs")
            .and_then(|d| d.get_mut(def))
            .and_then(|d| d.get_mut("required"))
            .and_then(Value::as_array_mut);
        if let Some(r) = required {
            r.retain(|k| !keys.iter().any(|key| k == key));
        }
    }
    schema
}
