//! The validation pass of a scene: every value checked, every problem found listed with its
//! JSON path and the fix (the object, each finger, the memory the dense patches need, the
//! reach of the contacts, a planar scene's plane). Every number is checked against the
//! physical range a grasp can have ([`crate::scene::limits`], stated in the JSON Schema and the
//! guide, docs/guide/scenes.md): outside it the input is a unit mistake or garbage, and a solve would overflow. A
//! direction that is zero or not finite is refused.

use crate::error::SceneError;
use crate::scene::field_checks::{number, FieldChecks};
use crate::scene::limits::*;
use crate::scene::scene_format::{ControlSpec, FingerSpec, MaterialSpec, RadiusSpec, Scene, Vec3};
use crate::scene::scene_geometry::SceneGeometry;
use crate::scene::texture_spec::{GapSpec, HeightGrid};
use crate::scene::vector_math::{cross, dot, norm, sub, unit, unit_vector};

/// A tangent whose angle with the normal has a sine below this (about 0.2 arc seconds) is
/// parallel to it and cannot give a frame.
const PARALLEL_SINE: f64 = 1e-6;

impl Scene {
    /// Checks every value; returns all problems found, each with path and fix. A plain scene
    /// holds no height map's heights: a texture's height map is a problem here
    /// ([`crate::scene::loaded_scene::LoadedScene::validate`] checks the maps it read).
    pub fn validate(&self) -> Result<(), SceneError> {
        self.validate_with(&SceneGeometry::default())
    }

    /// [`Scene::validate`], the height maps those of `geometry` (each read, finite, covering
    /// its patch).
    pub(crate) fn validate_with(&self, geometry: &SceneGeometry) -> Result<(), SceneError> {
        let mut v = FieldChecks::default();
        self.validate_object(&mut v);
        validate_gap("", self.gap, self.object.shape.is_some(), &mut v);
        if self.fingers.is_empty() {
            v.push(
                "fingers",
                "is empty".into(),
                "list at least one finger in contact with the object",
            );
        }
        for (i, f) in self.fingers.iter().enumerate() {
            self.validate_finger(i, f, geometry.height_map(i), &mut v);
        }
        crate::scene::shared_spring_checks::check_shared_springs(self, &mut v);
        self.check_memory(geometry, &mut v);
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

    fn validate_object(&self, v: &mut FieldChecks) {
        let o = &self.object;
        v.force("object.weight", o.weight, "give the weight in newtons");
        v.point("object.center_of_mass", &o.center_of_mass);
        v.direction(
            "object.gravity",
            &o.gravity,
            "give a nonzero direction, e.g. [0, 0, -1]",
        );
        v.material("object.material", &o.material);
        for (j, r) in o.external_forces.iter().enumerate() {
            let p = format!("object.external_forces[{j}]");
            for (k, c) in r.force.iter().enumerate() {
                v.signed_force(&format!("{p}.force[{k}]"), *c);
            }
            v.point(&format!("{p}.at"), &r.at);
        }
    }

    /// Checks finger `i`, `map` its height map's heights (when its texture is one and they
    /// were read).
    fn validate_finger(
        &self,
        i: usize,
        f: &FingerSpec,
        map: Option<&HeightGrid>,
        v: &mut FieldChecks,
    ) {
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
        v.point(&format!("{p}.contact_point"), &f.contact_point);
        let n_ok = v.direction(
            &format!("{p}.normal"),
            &f.normal,
            "give the contact normal pointing into the object, e.g. [0, 0, 1]",
        );
        if let Some(t) = &f.tangent {
            let t_ok = v.direction(
                &format!("{p}.tangent"),
                t,
                "give a nonzero tangent or omit it",
            );
            if t_ok && n_ok && norm(&cross(&unit(&f.normal), &unit(t))) < PARALLEL_SINE {
                v.push(
                    &format!("{p}.tangent"),
                    "is parallel to the normal".into(),
                    "give a tangent perpendicular to the normal, or omit it",
                );
            }
        }
        v.material(&format!("{p}.material"), &f.material);
        let object_rigid = matches!(self.object.material, MaterialSpec::Rigid(_));
        if object_rigid && matches!(f.material, MaterialSpec::Rigid(_)) {
            v.push(
                &format!("{p}.material"),
                "is rigid and so is the object: the contact has no compliance and its \
                 forces are indeterminate"
                    .into(),
                "make the finger or the object elastic ({youngs_modulus, poisson_ratio})",
            );
        }
        let exact = self.object.shape.is_some() && f.gap.or(self.gap) != Some(GapSpec::Quadratic);
        validate_radii(&p, f, exact, v);
        validate_tip(&p, f, self.planar.as_ref().map(|pl| pl.normal), v);
        validate_tip_shape(&p, f, exact, v);
        validate_gap(&p, f.gap, self.object.shape.is_some(), v);
        validate_patch(&p, f, v);
        crate::scene::texture_checks::check_texture(&p, f, map, v);
        crate::scene::sensor_checks::check_sensor(&p, f, v);
        crate::scene::mount_checks::check_mount(&p, f, v);
        v.friction(&format!("{p}.friction"), &f.friction, object_rigid);
        validate_control(&p, f, v);
    }

    /// Refuses scenes whose dense compliance blocks (the patches the automatic choice keeps
    /// dense, up to [`AUTO_FFT_ABOVE_UNKNOWNS`] unknowns) could not fit in any machine's
    /// memory (callers check the full estimate of the path that runs,
    /// [`memory_budget::estimate_memory_bytes_with`], against the machine they run on).
    fn check_memory(&self, geometry: &SceneGeometry, v: &mut FieldChecks) {
        let auto_dense = |f: &crate::scene::scene_format::FingerSpec| {
            crate::scene::memory_budget::finger_unknowns(self, f) <= AUTO_FFT_ABOVE_UNKNOWNS as u64
        };
        if let Some(p) =
            crate::scene::memory_budget::dense_blocks_problem(self, geometry, auto_dense)
        {
            v.push(&p.path, p.message, &p.fix);
        }
    }

    /// Flags contact points implausibly far from the centre of mass (a unit mistake).
    fn check_reach(&self, v: &mut FieldChecks) {
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
    fn check_planar(&self, p: &[f64; 3], v: &mut FieldChecks) {
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

/// A finger's control (`p` is `fingers[i]`): a prescribed load or approach in range.
fn validate_control(p: &str, f: &FingerSpec, v: &mut FieldChecks) {
    match f.control {
        ControlSpec::Load(l) => {
            v.force(
                &format!("{p}.control.normal_load"),
                l.normal_load,
                "give the prescribed normal load in newtons",
            );
        }
        ControlSpec::Approach(a) => {
            v.range(
                &format!("{p}.control.approach_m"),
                a.approach_m,
                APPROACH_RANGE_M,
                "m",
                "give how far the finger is pressed in from first touch, in metres (0.1 mm \
                 = 1e-4; negative withdraws it, a jaw opened), or use \"held\"",
            );
        }
        ControlSpec::Held(_) => {}
    }
}

/// Radii of curvature of the tip and the object.
/// With exact gaps (`exact`) the object's radius may be smaller than half the patch: the
/// elements past a thin part's silhouette face no surface and carry nothing.
fn validate_radii(p: &str, f: &FingerSpec, exact: bool, v: &mut FieldChecks) {
    let half = 0.5 * f.patch.size[0].max(f.patch.size[1]);
    if let Some(r) = f.tip_radius {
        v.radius(&format!("{p}.tip_radius"), r, half);
    }
    let object_half = if exact { 0.0 } else { half };
    match f.object_radius {
        Some(RadiusSpec::Isotropic(r)) => v.radius(&format!("{p}.object_radius"), r, object_half),
        Some(RadiusSpec::Principal(rs)) => {
            for (k, r) in rs.iter().enumerate() {
                if let Some(r) = r {
                    let h = if exact { 0.0 } else { 0.5 * f.patch.size[k] };
                    v.radius(&format!("{p}.object_radius[{k}]"), *r, h);
                }
            }
        }
        None => {}
    }
}

/// The fingertip's shape: one kind, not with `tip_radius`; a cylinder's axis tangent and
/// along `t1` or `t2`; a flat pad at least as large as the patch.
fn validate_tip(p: &str, f: &FingerSpec, planar: Option<Vec3>, v: &mut FieldChecks) {
    let Some(tip) = &f.tip else { return };
    let kinds = [
        tip.sphere.is_some(),
        tip.cylinder.is_some(),
        tip.flat.is_some(),
        tip.disc.is_some(),
        tip.shape.is_some(),
    ];
    if kinds.iter().filter(|k| **k).count() != 1 {
        let fix = "give one of {\"sphere\": {...}}, {\"cylinder\": {...}}, {\"flat\": {...}}, \
                   {\"disc\": {...}}, {\"shape\": {...}}";
        return v.push(
            &format!("{p}.tip"),
            "needs exactly one of sphere, cylinder, flat, disc, shape".into(),
            fix,
        );
    }
    if f.tip_radius.is_some() {
        let fix = "remove tip_radius (a spherical tip is {\"sphere\": {\"radius\": R}})";
        v.push(
            &format!("{p}.tip"),
            "is given together with tip_radius".into(),
            fix,
        );
    }
    let half = 0.5 * f.patch.size[0].max(f.patch.size[1]);
    if let Some(s) = &tip.sphere {
        v.radius(&format!("{p}.tip.sphere.radius"), s.radius, half);
    }
    if let Some(c) = &tip.cylinder {
        v.radius(&format!("{p}.tip.cylinder.radius"), c.radius, half);
        let axis_ok = v.direction(
            &format!("{p}.tip.cylinder.axis"),
            &c.axis,
            "give the tip's axis, e.g. [1, 0, 0]",
        );
        if axis_ok && unit_vector(&f.normal).is_some() {
            check_tip_axis(p, f, &unit(&c.axis), planar, v);
        }
    }
    if let Some(disc) = &tip.disc {
        validate_disc(p, f, disc, v);
    }
    if let Some(flat) = &tip.flat {
        let smaller = flat.size[0].min(flat.size[1]);
        v.edge_radius(
            &format!("{p}.tip.flat.edge_radius"),
            flat.edge_radius,
            smaller,
        );
        for k in 0..2 {
            // False for a NaN pad side too.
            let fits = f.patch.size[k] <= flat.size[k] * (1.0 + 1e-12);
            if !fits {
                v.push(
                    &format!("{p}.patch.size[{k}]"),
                    format!(
                        "{} m is larger than the flat pad's {} m",
                        number(f.patch.size[k]),
                        number(flat.size[k])
                    ),
                    "make the patch no larger than the pad (the pad is all that can touch)",
                );
            }
        }
    }
}

/// A tip given as a solid (`tip.shape`) needs exact gaps: the object's shape, and no
/// `"gap": "quadratic"` (the thesis's form has no curvature of a mesh to read).
fn validate_tip_shape(p: &str, f: &FingerSpec, exact: bool, v: &mut FieldChecks) {
    if f.tip.as_ref().is_some_and(|t| t.shape.is_some()) && !exact {
        v.push(
            &format!("{p}.tip.shape"),
            "needs exact gaps, measured on the object's shape".into(),
            "give object.shape and leave `gap` \"exact\" (the default with a shape), or give \
             the tip as a sphere, cylinder, flat or disc",
        );
    }
}

/// A disc pad: its diameter a length, its rim's radius at most its radius, the patch no wider
/// than the disc (the patch's corners past the rim face no surface).
fn validate_disc(
    p: &str,
    f: &FingerSpec,
    disc: &crate::scene::shape_spec::TipDiscSpec,
    v: &mut FieldChecks,
) {
    let path = format!("{p}.tip.disc.diameter");
    if v.range(
        &path,
        disc.diameter,
        PATCH_SIDE_RANGE_M,
        "m",
        "give the pad's diameter in metres",
    ) {
        v.edge_radius(
            &format!("{p}.tip.disc.edge_radius"),
            disc.edge_radius,
            disc.diameter,
        );
        for k in 0..2 {
            // False for a NaN patch side too.
            let fits = f.patch.size[k] <= disc.diameter * (1.0 + 1e-12);
            if !fits {
                v.push(
                    &format!("{p}.patch.size[{k}]"),
                    format!(
                        "{} m is wider than the disc pad's diameter {} m",
                        number(f.patch.size[k]),
                        number(disc.diameter)
                    ),
                    "make the patch no wider than the pad (the pad is all that can touch)",
                );
            }
        }
    }
}

/// `gap` (a finger's or the scene's): `"exact"` needs the object's shape.
pub(crate) fn validate_gap(p: &str, gap: Option<GapSpec>, has_shape: bool, v: &mut FieldChecks) {
    if gap == Some(GapSpec::Exact) && !has_shape {
        let path = match p {
            "" => "gap".to_string(),
            _ => format!("{p}.gap"),
        };
        v.push(
            &path,
            "is \"exact\" but the object has no shape to measure the gaps on".into(),
            "give object.shape, or set the gap to \"quadratic\" (the thesis's form from the radii)",
        );
    }
}

/// A cylindrical tip's axis must be tangent to the contact and along `t1` or `t2`, so that
/// the tip's and the object's curvatures add along common directions.
fn check_tip_axis(p: &str, f: &FingerSpec, axis: &Vec3, planar: Option<Vec3>, v: &mut FieldChecks) {
    let v3 = |a: &Vec3| nalgebra::Vector3::new(a[0], a[1], a[2]);
    let frame = crate::geometry::contact_frame::ContactFrame::new(
        v3(&f.contact_point),
        v3(&f.normal),
        f.tangent.as_ref().map(v3),
        planar.as_ref().map(v3),
    );
    let a = v3(axis);
    let along = a.dot(&frame.t1).abs().max(a.dot(&frame.t2).abs());
    if along < 1.0 - PLANAR_TOLERANCE {
        v.push(
            &format!("{p}.tip.cylinder.axis"),
            format!(
                "is not along the patch's t1 [{:.4}, {:.4}, {:.4}] or t2 [{:.4}, {:.4}, {:.4}]",
                frame.t1.x, frame.t1.y, frame.t1.z, frame.t2.x, frame.t2.y, frame.t2.z
            ),
            "give the finger's tangent along the tip's axis (or across it), or turn the axis into the contact's tangent plane",
        );
    }
}

/// Patch sides and grid.
fn validate_patch(p: &str, f: &FingerSpec, v: &mut FieldChecks) {
    for k in 0..2 {
        let s = f.patch.size[k];
        if !(s.is_finite() && s > 0.0) {
            v.push(
                &format!("{p}.patch.size[{k}]"),
                format!("is {} m", number(s)),
                "give the patch side length in metres, > 0",
            );
        } else {
            v.range(
                &format!("{p}.patch.size[{k}]"),
                s,
                PATCH_SIDE_RANGE_M,
                "m",
                "give the side in metres",
            );
        }
        if f.patch.grid[k] == 0 {
            v.push(
                &format!("{p}.patch.grid[{k}]"),
                "is 0".into(),
                "give at least one element along each side",
            );
        } else if f.patch.grid[k] > MAX_GRID_SIDE {
            v.push(
                &format!("{p}.patch.grid[{k}]"),
                format!(
                    "is {}, more than {MAX_GRID_SIDE} elements along a side",
                    f.patch.grid[k]
                ),
                "use at most 2048 elements a side (the largest patch is 2048 x 2048)",
            );
        }
    }
    let ne = f.patch.grid[0].saturating_mul(f.patch.grid[1]);
    if ne > MAX_ELEMENTS_PER_PATCH {
        v.push(
            &format!("{p}.patch.grid"),
            format!("has {ne} elements, more than {MAX_ELEMENTS_PER_PATCH}"),
            "use a coarser grid",
        );
    }
}
