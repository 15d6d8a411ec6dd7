//! Parsing and validating a scene: every problem with its JSON path and the fix.

use crate::error::{SceneError, SceneProblem};
use crate::scene::{ControlSpec, FrictionSpec, MaterialSpec, RadiusSpec, Scene, Vec3};

/// Largest number of elements allowed in one patch. The compliance block of a patch is dense
/// (`(3 nx ny)^2` entries), so 64 x 64 elements already means a 12288 x 12288 block.
pub const MAX_ELEMENTS_PER_PATCH: usize = 64 * 64;

/// A contact point farther from the centre of mass than this multiple of the median distance of
/// all contact points is taken as a unit mistake (millimetres written as metres, say).
pub const PLAUSIBLE_REACH_FACTOR: f64 = 100.0;

/// Physical range of Young's modulus, Pa (soft gels to beyond diamond); outside it the input is
/// almost surely in the wrong unit.
pub const MODULUS_RANGE_PA: (f64, f64) = (1.0, 1e15);

/// Physical range of a patch side, m.
pub const PATCH_SIDE_RANGE_M: (f64, f64) = (1e-9, 10.0);

/// Largest memory the dense patch compliance blocks may take, bytes (the cone solver needs a
/// few times more).
pub const MAX_COMPLIANCE_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// Relative tolerance of the planarity checks (normalised directions, distances over the
/// scene's length scale).
pub const PLANAR_TOLERANCE: f64 = 1e-6;

impl Scene {
    /// Parses a scene from JSON text and validates it (see [`Scene::validate`]).
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            SceneError::Parse {
                path,
                message: e.inner().to_string(),
            }
        })?;
        scene.validate()?;
        Ok(scene)
    }

    /// Checks every value; returns all problems found, each with path and fix.
    pub fn validate(&self) -> Result<(), SceneError> {
        let mut v = Problems::default();
        let o = &self.object;
        if !(o.weight.is_finite() && o.weight >= 0.0) {
            v.push(
                "object.weight",
                format!("is {} N", o.weight),
                "give the weight in newtons, finite and >= 0",
            );
        }
        v.finite3("object.center_of_mass", &o.center_of_mass);
        v.direction(
            "object.gravity",
            &o.gravity,
            "give a nonzero direction, e.g. [0, 0, -1]",
        );
        v.material("object.material", &o.material);
        for (j, r) in o.external_forces.iter().enumerate() {
            v.finite3(&format!("object.external_forces[{j}].force"), &r.force);
            v.finite3(&format!("object.external_forces[{j}].at"), &r.at);
        }
        if self.fingers.is_empty() {
            v.push(
                "fingers",
                "is empty".into(),
                "list at least one finger in contact with the object",
            );
        }
        let object_rigid = matches!(o.material, MaterialSpec::Rigid(_));
        for (i, f) in self.fingers.iter().enumerate() {
            let p = format!("fingers[{i}]");
            if f.name.trim().is_empty() {
                v.push(
                    &format!("{p}.name"),
                    "is empty".into(),
                    "give each finger a unique name",
                );
            }
            if let Some(j) = self.fingers[..i].iter().position(|g| g.name == f.name) {
                v.push(
                    &format!("{p}.name"),
                    format!("`{}` is also the name of fingers[{j}]", f.name),
                    "give each finger a unique name",
                );
            }
            v.finite3(&format!("{p}.contact_point"), &f.contact_point);
            let n_ok = v.direction(
                &format!("{p}.normal"),
                &f.normal,
                "give the contact normal pointing into the object, e.g. [0, 0, 1]",
            );
            if let Some(t) = &f.tangent {
                if v.direction(
                    &format!("{p}.tangent"),
                    t,
                    "give a nonzero tangent or omit it",
                ) && n_ok
                {
                    let (n, t) = (unit(&f.normal), unit(t));
                    if cross(&n, &t).iter().map(|x| x * x).sum::<f64>().sqrt() < 1e-6 {
                        v.push(
                            &format!("{p}.tangent"),
                            "is parallel to the normal".into(),
                            "give a tangent perpendicular to the normal, or omit it",
                        );
                    }
                }
            }
            v.material(&format!("{p}.material"), &f.material);
            if object_rigid && matches!(f.material, MaterialSpec::Rigid(_)) {
                v.push(
                    &format!("{p}.material"),
                    "is rigid and so is the object: the contact has no compliance and its \
                     forces are indeterminate"
                        .into(),
                    "make the finger or the object elastic ({youngs_modulus, poisson_ratio})",
                );
            }
            let half = 0.5 * f.patch.size[0].max(f.patch.size[1]);
            if let Some(r) = f.tip_radius {
                v.radius(&format!("{p}.tip_radius"), r, half);
            }
            match f.object_radius {
                Some(RadiusSpec::Isotropic(r)) => {
                    v.radius(&format!("{p}.object_radius"), r, half);
                }
                Some(RadiusSpec::Principal(rs)) => {
                    for (k, r) in rs.iter().enumerate() {
                        if let Some(r) = r {
                            let h = 0.5 * f.patch.size[k];
                            v.radius(&format!("{p}.object_radius[{k}]"), *r, h);
                        }
                    }
                }
                None => {}
            }
            for k in 0..2 {
                let s = f.patch.size[k];
                if !(s.is_finite() && s > 0.0) {
                    v.push(
                        &format!("{p}.patch.size[{k}]"),
                        format!("is {s} m"),
                        "give the patch side length in metres, > 0",
                    );
                } else if !(PATCH_SIDE_RANGE_M.0..=PATCH_SIDE_RANGE_M.1).contains(&s) {
                    v.push(
                        &format!("{p}.patch.size[{k}]"),
                        format!(
                            "is {s:e} m, outside [{:e}, {}] m",
                            PATCH_SIDE_RANGE_M.0, PATCH_SIDE_RANGE_M.1
                        ),
                        "give the side in metres",
                    );
                }
                if f.patch.grid[k] == 0 {
                    v.push(
                        &format!("{p}.patch.grid[{k}]"),
                        "is 0".into(),
                        "give at least one element along each side",
                    );
                }
            }
            let ne = f.patch.grid[0].saturating_mul(f.patch.grid[1]);
            if ne > MAX_ELEMENTS_PER_PATCH {
                v.push(
                    &format!("{p}.patch.grid"),
                    format!("has {ne} elements, more than {MAX_ELEMENTS_PER_PATCH}"),
                    "use a coarser grid (the patch compliance is a dense matrix)",
                );
            }
            v.friction(&format!("{p}.friction"), &f.friction, object_rigid);
            if let ControlSpec::Load(l) = f.control {
                if !(l.normal_load.is_finite() && l.normal_load >= 0.0) {
                    v.push(
                        &format!("{p}.control.normal_load"),
                        format!("is {} N", l.normal_load),
                        "give the prescribed normal load in newtons, finite and >= 0",
                    );
                }
            }
        }
        self.check_memory(&mut v);
        self.check_reach(&mut v);
        if let Some(pl) = &self.planar {
            if v.direction(
                "planar.normal",
                &pl.normal,
                "give the normal of the plane of motion",
            ) {
                self.check_planar(&unit(&pl.normal), &mut v);
            }
        }
        v.finish()
    }

    /// Refuses scenes whose dense compliance blocks would not fit in memory.
    fn check_memory(&self, v: &mut Problems) {
        let bytes: f64 = self
            .fingers
            .iter()
            .map(|f| {
                let tangential = if f.friction.is_frictionless() {
                    0
                } else if self.planar.is_some() {
                    1
                } else {
                    2
                };
                let n = (f.patch.grid[0].saturating_mul(f.patch.grid[1]) * (1 + tangential)) as f64;
                8.0 * n * n
            })
            .sum();
        if bytes > MAX_COMPLIANCE_BYTES {
            v.push(
                "fingers",
                format!(
                    "the patch compliance blocks need {:.1} GiB, more than {:.0} GiB",
                    bytes / 1073741824.0,
                    MAX_COMPLIANCE_BYTES / 1073741824.0
                ),
                "use coarser grids (see `grasp study` for the accuracy each grid gives)",
            );
        }
    }

    /// Flags contact points implausibly far from the centre of mass (a unit mistake).
    fn check_reach(&self, v: &mut Problems) {
        let r = self.object.center_of_mass;
        let d: Vec<f64> = self
            .fingers
            .iter()
            .map(|f| norm(&sub(&f.contact_point, &r)))
            .collect();
        if d.len() < 2 || d.iter().any(|x| !x.is_finite()) {
            return;
        }
        let mut s = d.clone();
        s.sort_by(f64::total_cmp);
        let median = s[s.len() / 2];
        if median <= 0.0 {
            return;
        }
        for (i, di) in d.iter().enumerate() {
            if *di > PLAUSIBLE_REACH_FACTOR * median {
                v.push(
                    &format!("fingers[{i}].contact_point"),
                    format!(
                        "is {di:.3e} m from the centre of mass, over {PLAUSIBLE_REACH_FACTOR}x \
                         the median of all contacts ({median:.3e} m): no plausible object \
                         reaches it"
                    ),
                    "check the units (metres) and the coordinates of this contact point",
                );
            }
        }
    }

    /// A planar scene keeps every point in one plane and every force direction in it.
    fn check_planar(&self, p: &[f64; 3], v: &mut Problems) {
        let r = self.object.center_of_mass;
        let scale = self
            .fingers
            .iter()
            .map(|f| norm(&sub(&f.contact_point, &r)))
            .chain(
                self.fingers
                    .iter()
                    .map(|f| f.patch.size[0].max(f.patch.size[1])),
            )
            .fold(0.0_f64, f64::max)
            .max(f64::MIN_POSITIVE);
        let off_plane = |x: &Vec3| dot(&sub(x, &r), p).abs() > PLANAR_TOLERANCE * scale;
        let out_dir = |x: &Vec3| {
            let n = norm(x);
            n > 0.0 && (dot(x, p) / n).abs() > PLANAR_TOLERANCE
        };
        if self.object.weight > 0.0 && out_dir(&self.object.gravity) {
            v.push(
                "object.gravity",
                "leaves the plane of a planar scene".into(),
                "give gravity perpendicular to planar.normal, or make the scene 3-D (planar: null)",
            );
        }
        for (j, e) in self.object.external_forces.iter().enumerate() {
            if out_dir(&e.force) {
                v.push(
                    &format!("object.external_forces[{j}].force"),
                    "leaves the plane of a planar scene".into(),
                    "give a force perpendicular to planar.normal",
                );
            }
            if off_plane(&e.at) {
                v.push(
                    &format!("object.external_forces[{j}].at"),
                    "is off the plane through the centre of mass".into(),
                    "move the point into that plane",
                );
            }
        }
        for (i, f) in self.fingers.iter().enumerate() {
            if out_dir(&f.normal) {
                v.push(
                    &format!("fingers[{i}].normal"),
                    "leaves the plane of a planar scene".into(),
                    "give a normal perpendicular to planar.normal",
                );
            }
            if off_plane(&f.contact_point) {
                v.push(
                    &format!("fingers[{i}].contact_point"),
                    "is off the plane through the centre of mass".into(),
                    "move the contact point into that plane",
                );
            }
            if let Some(t) = &f.tangent {
                if out_dir(t) {
                    v.push(
                        &format!("fingers[{i}].tangent"),
                        "leaves the plane of a planar scene".into(),
                        "omit the tangent (it is taken in the plane) or give one in the plane",
                    );
                }
            }
        }
    }
}

#[derive(Default)]
struct Problems(Vec<SceneProblem>);

impl Problems {
    fn push(&mut self, path: &str, message: String, fix: &str) {
        self.0.push(SceneProblem {
            path: path.to_string(),
            message,
            fix: fix.to_string(),
        });
    }

    fn finite3(&mut self, path: &str, x: &Vec3) -> bool {
        if x.iter().all(|c| c.is_finite()) {
            return true;
        }
        self.push(
            path,
            "has a non-finite component".into(),
            "give three finite numbers",
        );
        false
    }

    fn direction(&mut self, path: &str, x: &Vec3, fix: &str) -> bool {
        if !self.finite3(path, x) {
            return false;
        }
        if norm(x) == 0.0 {
            self.push(path, "has zero length".into(), fix);
            return false;
        }
        true
    }

    fn material(&mut self, path: &str, m: &MaterialSpec) {
        if let MaterialSpec::Elastic(e) = m {
            if !(e.youngs_modulus.is_finite() && e.youngs_modulus > 0.0) {
                self.push(
                    &format!("{path}.youngs_modulus"),
                    format!("is {} Pa", e.youngs_modulus),
                    "give Young's modulus in pascals, > 0 (or write \"rigid\" for the material)",
                );
            } else if !(MODULUS_RANGE_PA.0..=MODULUS_RANGE_PA.1).contains(&e.youngs_modulus) {
                self.push(
                    &format!("{path}.youngs_modulus"),
                    format!(
                        "is {:e} Pa, outside the physical range [{:e}, {:e}] Pa",
                        e.youngs_modulus, MODULUS_RANGE_PA.0, MODULUS_RANGE_PA.1
                    ),
                    "give Young's modulus in pascals (1 MPa = 1e6 Pa), or \"rigid\"",
                );
            }
            if !(e.poisson_ratio.is_finite() && (0.0..0.5).contains(&e.poisson_ratio)) {
                self.push(
                    &format!("{path}.poisson_ratio"),
                    format!("is {}", e.poisson_ratio),
                    "give Poisson's ratio in [0, 0.5) (rubber is about 0.49)",
                );
            }
        }
    }

    fn radius(&mut self, path: &str, r: f64, half_patch: f64) {
        if !(r.is_finite() && r > 0.0) {
            self.push(
                path,
                format!("is {r} m"),
                "give the radius of curvature in metres, > 0, or null for flat",
            );
        } else if half_patch.is_finite() && half_patch > r {
            self.push(
                path,
                format!("is {r} m, smaller than half the patch ({half_patch} m)"),
                "shrink patch.size below the diameter, or check the radius (the gap is the \
                 parabolic approximation of the surface)",
            );
        }
    }

    /// Checks a friction law (thesis section 2.6).
    fn friction(&mut self, path: &str, spec: &FrictionSpec, object_rigid: bool) {
        match spec {
            FrictionSpec::Coefficient(c) => {
                if !(c.mu.is_finite() && c.mu >= 0.0) {
                    self.push(
                        &format!("{path}.mu"),
                        format!("is {}", c.mu),
                        "give a friction coefficient >= 0 (0 for a frictionless finger)",
                    );
                }
            }
            FrictionSpec::Table(t) => {
                if t.table.is_empty() {
                    self.push(
                        &format!("{path}.table"),
                        "is empty".into(),
                        "list at least one [P_N, mu] point (one point is a constant mu)",
                    );
                }
                for (j, pt) in t.table.iter().enumerate() {
                    if !(pt[0].is_finite() && pt[0] >= 0.0) {
                        self.push(
                            &format!("{path}.table[{j}][0]"),
                            format!("is {} N", pt[0]),
                            "give the finger's normal load in newtons, finite and >= 0",
                        );
                    }
                    if !(pt[1].is_finite() && pt[1] >= 0.0) {
                        self.push(
                            &format!("{path}.table[{j}][1]"),
                            format!("is {}", pt[1]),
                            "give a friction coefficient >= 0",
                        );
                    }
                    if j > 0 && !(pt[0] > t.table[j - 1][0]) {
                        self.push(
                            &format!("{path}.table[{j}][0]"),
                            format!(
                                "is {} N, not above the previous load {} N",
                                pt[0],
                                t.table[j - 1][0]
                            ),
                            "sort the points by strictly increasing load",
                        );
                    }
                }
            }
            FrictionSpec::Elastic(e) => {
                let q = &e.elastic;
                for (name, val) in [
                    ("finger_radius", q.finger_radius),
                    ("object_radius", q.object_radius),
                    ("contact_length", q.contact_length),
                ] {
                    if !(val.is_finite() && val > 0.0) {
                        self.push(
                            &format!("{path}.elastic.{name}"),
                            format!("is {val} m"),
                            "give a length in metres, finite and > 0",
                        );
                    }
                }
                if q.finger_radius.is_finite()
                    && q.object_radius.is_finite()
                    && q.finger_radius >= q.object_radius
                {
                    self.push(
                        &format!("{path}.elastic.object_radius"),
                        format!(
                            "is {} m, not larger than finger_radius {} m",
                            q.object_radius, q.finger_radius
                        ),
                        "thesis eq. (40) needs R1 < R2 (finger radius below the object's); \
                         use a table or a constant mu otherwise",
                    );
                }
                if object_rigid {
                    self.push(
                        &format!("{path}.elastic"),
                        "needs an elastic object (eq. 40 uses the object's shear modulus)".into(),
                        "give object.material elastic constants, or use a table or constant mu",
                    );
                }
            }
        }
    }

    fn finish(self) -> Result<(), SceneError> {
        if self.0.is_empty() {
            Ok(())
        } else {
            Err(SceneError::Invalid(self.0))
        }
    }
}

fn norm(x: &Vec3) -> f64 {
    dot(x, x).sqrt()
}
fn dot(a: &Vec3, b: &Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: &Vec3, b: &Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn unit(a: &Vec3) -> Vec3 {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}
fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
