//! Parsing and validating a scene: every problem with its JSON path and the fix.
//!
//! Every number is checked against the physical range a grasp can have (the constants below,
//! stated in the JSON Schema and the README): outside it the input is a unit mistake or
//! garbage, and a solve would overflow. Direction vectors are normalised on load by scaling
//! with their largest component first, so `[1e200, 0, 0]` is `[1, 0, 0]`; a direction that is
//! zero or not finite is refused.

use crate::error::{InputProblem, SceneError};
use crate::geometry::mesh_surface::TriangleMesh;
use crate::geometry::shape_spec::MeshSpec;
use crate::scene::scene_format::{
    ControlSpec, ElasticLawParams, FingerSpec, FrictionSpec, MaterialSpec, RadiusSpec,
    RelaxationSpec, Scene, Vec3,
};
use crate::scene::strict_json::StrictValue;

use crate::scene::limits::*;

/// A tangent whose angle with the normal has a sine below this (about 0.2 arc seconds) is
/// parallel to it and cannot give a frame.
const PARALLEL_SINE: f64 = 1e-6;

/// `x / |x|` computed without overflow or underflow (scaled by the largest component first);
/// `None` if `x` is zero or not finite.
pub fn unit_vector(x: &Vec3) -> Option<Vec3> {
    let m = x.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(m.is_finite() && m > 0.0) || x.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let y = [x[0] / m, x[1] / m, x[2] / m];
    let n = norm(&y);
    Some([y[0] / n, y[1] / n, y[2] / n])
}

impl Scene {
    /// Parses a scene from JSON text (one document, nothing after it; duplicate keys refused),
    /// normalises its directions (see [`Scene::normalize_directions`]) and validates it (see
    /// [`Scene::validate`]).
    ///
    /// A scene with `object.shape` is resolved first (fingers placed on it, the weight from a
    /// density, explicit frames checked: `crate::scene::finger_placement`); this entry point reads
    /// no files, so a mesh shape needs [`Scene::from_json_str_with_meshes`].
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        Scene::from_json_str_with_meshes(text, &|m: &MeshSpec| {
            Err(format!(
                "{}: this loader reads no files; load the scene with the grasp CLI, grasp.Scene \
                 or grasp_io",
                m.file
            ))
        })
    }

    /// As [`Scene::from_json_str`], reading a mesh shape's file with `load_mesh`.
    pub fn from_json_str_with_meshes(
        text: &str,
        load_mesh: &dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>,
    ) -> Result<Scene, SceneError> {
        let parse_error = |e: crate::scene::strict_json::JsonError| structure_error(text, e);
        // Most scenes name no shape: read them once, as written (a key inside a string only
        // sends a scene down the resolving path, which reads it the same way).
        if !["\"shape\"", "\"place\"", "\"density\""]
            .iter()
            .any(|k| text.contains(k))
        {
            let mut scene: Scene =
                crate::scene::strict_json::from_str_strict(text).map_err(parse_error)?;
            scene.normalize_directions();
            scene.validate()?;
            return Ok(scene);
        }
        let StrictValue(mut value) =
            crate::scene::strict_json::from_str_strict::<StrictValue>(text).map_err(parse_error)?;
        let report = crate::scene::finger_placement::resolve_shapes(&mut value, load_mesh)?;
        let mut scene: Scene = match report {
            // Without a shape the text is read as written (positions in messages are its own).
            None => crate::scene::strict_json::from_str_strict(text).map_err(parse_error)?,
            Some(_) => {
                let resolved = serde_json::to_string_pretty(&value).unwrap_or_default();
                crate::scene::strict_json::from_str_strict(&resolved).map_err(parse_error)?
            }
        };
        scene.shape_report = report;
        scene.normalize_directions();
        scene.validate()?;
        Ok(scene)
    }

    /// As [`Scene::from_json_str_with_meshes`], from a JSON value already parsed strictly (no
    /// key twice: [`StrictValue`]), so a scene inside a larger document (a batch line) is
    /// parsed once: its shape resolved on the value, then the typed scene read from it.
    pub fn from_value_with_meshes(
        mut value: serde_json::Value,
        load_mesh: &dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>,
    ) -> Result<Scene, SceneError> {
        // As written, for the structural problems of a scene that does not parse.
        let written = value.clone();
        let report = crate::scene::finger_placement::resolve_shapes(&mut value, load_mesh)?;
        let mut scene: Scene = crate::scene::strict_json::from_value_strict(value)
            .map_err(|e| structure_error_of(&written, e))?;
        scene.shape_report = report;
        scene.normalize_directions();
        scene.validate()?;
        Ok(scene)
    }

    /// Replaces every direction (gravity, planar normal, finger normals and tangents) by its
    /// unit vector, computed without overflow (`unit_vector`); zero or non-finite directions
    /// are left for [`Scene::validate`] to refuse.
    pub fn normalize_directions(&mut self) {
        let fix = |x: &mut Vec3| {
            if let Some(u) = unit_vector(x) {
                *x = u;
            }
        };
        fix(&mut self.object.gravity);
        if let Some(p) = &mut self.planar {
            fix(&mut p.normal);
        }
        for f in &mut self.fingers {
            fix(&mut f.normal);
            if let Some(t) = &mut f.tangent {
                fix(t);
            }
        }
    }

    /// Checks every value; returns all problems found, each with path and fix.
    pub fn validate(&self) -> Result<(), SceneError> {
        let mut v = Problems::default();
        self.validate_object(&mut v);
        if self.fingers.is_empty() {
            v.push(
                "fingers",
                "is empty".into(),
                "list at least one finger in contact with the object",
            );
        }
        for (i, f) in self.fingers.iter().enumerate() {
            self.validate_finger(i, f, &mut v);
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

    fn validate_object(&self, v: &mut Problems) {
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

    fn validate_finger(&self, i: usize, f: &FingerSpec, v: &mut Problems) {
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
        validate_radii(&p, f, v);
        validate_tip(&p, f, self.planar.as_ref().map(|pl| pl.normal), v);
        validate_patch(&p, f, v);
        v.friction(&format!("{p}.friction"), &f.friction, object_rigid);
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
                     = 1e-4), or use \"held\"",
                );
            }
            ControlSpec::Held(_) => {}
        }
    }

    /// Refuses scenes whose dense compliance blocks (the patches the automatic choice keeps
    /// dense, up to [`AUTO_FFT_ABOVE_UNKNOWNS`] unknowns) could not fit in any machine's
    /// memory (callers check the full estimate of the path that runs,
    /// [`work_bounds::estimate_memory_bytes_with`], against the machine they run on).
    fn check_memory(&self, v: &mut Problems) {
        let bytes = crate::scene::work_bounds::compliance_bytes_of(self, |f| {
            crate::scene::work_bounds::finger_unknowns(self, f) <= AUTO_FFT_ABOVE_UNKNOWNS as u64
        }) as f64;
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

/// Radii of curvature of the tip and the object.
fn validate_radii(p: &str, f: &FingerSpec, v: &mut Problems) {
    let half = 0.5 * f.patch.size[0].max(f.patch.size[1]);
    if let Some(r) = f.tip_radius {
        v.radius(&format!("{p}.tip_radius"), r, half);
    }
    match f.object_radius {
        Some(RadiusSpec::Isotropic(r)) => v.radius(&format!("{p}.object_radius"), r, half),
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
}

/// The fingertip's shape: one kind, not with `tip_radius`; a cylinder's axis tangent and
/// along `t1` or `t2`; a flat pad at least as large as the patch.
fn validate_tip(p: &str, f: &FingerSpec, planar: Option<Vec3>, v: &mut Problems) {
    let Some(tip) = &f.tip else { return };
    let kinds = [
        tip.sphere.is_some(),
        tip.cylinder.is_some(),
        tip.flat.is_some(),
    ];
    if kinds.iter().filter(|k| **k).count() != 1 {
        let fix = "give one of {\"sphere\": {...}}, {\"cylinder\": {...}}, {\"flat\": {...}}";
        return v.push(
            &format!("{p}.tip"),
            "needs exactly one of sphere, cylinder, flat".into(),
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
    if let Some(flat) = &tip.flat {
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

/// A cylindrical tip's axis must be tangent to the contact and along `t1` or `t2`, so that
/// the tip's and the object's curvatures add along common directions.
fn check_tip_axis(p: &str, f: &FingerSpec, axis: &Vec3, planar: Option<Vec3>, v: &mut Problems) {
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
fn validate_patch(p: &str, f: &FingerSpec, v: &mut Problems) {
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

/// The error of a scene text the typed reader stopped on (`e`): every structural problem of
/// the document (missing, unknown and mistyped fields, each with a fix;
/// [`crate::scene::schema_check`]) when it is valid JSON, the reader's own error kept among
/// them; else `e` alone (a syntax error).
fn structure_error(text: &str, e: crate::scene::strict_json::JsonError) -> SceneError {
    match crate::scene::strict_json::from_str_strict::<StrictValue>(text) {
        Ok(StrictValue(value)) => structure_error_of(&value, e),
        // Not even a JSON document: the reader's error, with its position.
        Err(_) => single_problem(e),
    }
}

/// A reader's error as the one problem of a scene.
fn single_problem(e: crate::scene::strict_json::JsonError) -> SceneError {
    SceneError::Parse {
        path: e.path,
        message: e.message,
    }
}

/// serde_json's data error without its trailing ` at line L column C`.
fn without_position(message: &str) -> &str {
    match message.rfind(" at line ") {
        Some(i)
            if message[i + 9..]
                .split(" column ")
                .all(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())) =>
        {
            &message[..i]
        }
        _ => message,
    }
}

/// [`structure_error`] of a scene already parsed into `value` (as written, before any shape
/// was resolved). The reader's message loses its position (` at line L column C`): the JSON
/// path locates a data error, and a scene parsed from text or from a value (a batch line)
/// reports it alike.
fn structure_error_of(
    value: &serde_json::Value,
    e: crate::scene::strict_json::JsonError,
) -> SceneError {
    let e = crate::scene::strict_json::JsonError {
        message: without_position(&e.message).to_string(),
        path: e.path,
    };
    let single = single_problem;
    let schema = crate::scene::scene_format::scene_json_schema();
    let found = crate::scene::schema_check::structural_problems(value, schema.as_value());
    if found.is_empty() {
        return single(e);
    }
    let mut problems = Problems(found);
    // Where the walk only knows that no form fits, the reader's message says which it expected.
    for p in problems.0.iter_mut() {
        if p.path == e.path && p.message.contains(NO_FORM_FITS) {
            p.message = e.message.clone();
        }
    }
    // The walk knows the format's structure, the reader its details: keep the reader's error
    // when no problem found lies on its path.
    let related = |p: &InputProblem| p.path.starts_with(&e.path) || e.path.starts_with(&p.path);
    if !problems.0.iter().any(related) {
        match missing_field(&e.message) {
            // A field the schema leaves optional (a placed finger derives its frame) but this
            // scene needs.
            Some(name) => {
                let path = if e.path == "." {
                    name.to_string()
                } else {
                    format!("{}.{name}", e.path)
                };
                let fix = format!("add `{name}` (see `grasp schema`)");
                problems.push(&path, "is missing".into(), &fix);
            }
            None => problems.push(
                &e.path,
                e.message.clone(),
                "correct the JSON (see `grasp schema`)",
            ),
        }
    }
    problems.finish().err().unwrap_or_else(|| single(e))
}

/// What [`crate::scene::schema_check`] says of a value that fits none of a field's forms.
const NO_FORM_FITS: &str = crate::scene::schema_check::NO_FORM_FITS;

/// The field named by serde's "missing field `name` at line ..." message.
fn missing_field(message: &str) -> Option<&str> {
    message.strip_prefix("missing field `")?.split('`').next()
}

#[derive(Default)]
struct Problems(Vec<InputProblem>);

impl Problems {
    fn push(&mut self, path: &str, message: String, fix: &str) {
        self.0.push(InputProblem {
            path: path.to_string(),
            message,
            fix: fix.to_string(),
        });
    }

    /// A finite value inside `[lo, hi]`; `what` is the unit.
    fn range(&mut self, path: &str, x: f64, (lo, hi): (f64, f64), unit: &str, fix: &str) -> bool {
        if x.is_finite() && (lo..=hi).contains(&x) {
            return true;
        }
        let u = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        self.push(
            path,
            format!("is {}{u}, outside [{lo:e}, {hi:e}]{u}", number(x)),
            fix,
        );
        false
    }

    /// A force magnitude: 0 or in `[MIN_NONZERO_FORCE_N, MAX_FORCE_N]`.
    fn force(&mut self, path: &str, x: f64, fix: &str) -> bool {
        if force_in_range(x) {
            return true;
        }
        self.push(
            path,
            format!(
                "is {} N, neither 0 nor in [{MIN_NONZERO_FORCE_N:e}, {MAX_FORCE_N:e}] N",
                number(x)
            ),
            &format!("{fix}: 0 or between {MIN_NONZERO_FORCE_N:e} and {MAX_FORCE_N:e} N"),
        );
        false
    }

    /// A force component: its magnitude is a force (see [`Problems::force`]).
    fn signed_force(&mut self, path: &str, x: f64) -> bool {
        self.force(path, x.abs(), "give the component in newtons")
    }

    /// A point with every coordinate in `[-MAX_COORDINATE_M, MAX_COORDINATE_M]`.
    fn point(&mut self, path: &str, x: &Vec3) -> bool {
        let fix = format!("give coordinates in metres, |x| <= {MAX_COORDINATE_M:e} m");
        let b = (-MAX_COORDINATE_M, MAX_COORDINATE_M);
        let mut ok = true;
        for (k, c) in x.iter().enumerate() {
            // Every coordinate is checked (and reported), not only up to the first bad one.
            ok &= self.range(&format!("{path}[{k}]"), *c, b, "m", &fix);
        }
        ok
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

    /// A direction: finite and nonzero, and of a length whose square neither overflows nor
    /// underflows (a scene read from a file is normalised on load, see
    /// [`Scene::normalize_directions`]; a scene built in code must keep its directions so).
    fn direction(&mut self, path: &str, x: &Vec3, fix: &str) -> bool {
        if !self.finite3(path, x) {
            return false;
        }
        let n2 = dot(x, x);
        if n2 == 0.0 {
            self.push(path, "has zero length".into(), fix);
            return false;
        }
        if !(n2.is_finite() && n2 >= f64::MIN_POSITIVE) {
            self.push(
                path,
                format!("has a length ({:e}) whose square is out of range", norm(x)),
                "give a direction with components between 1e-150 and 1e150, e.g. a unit vector",
            );
            return false;
        }
        true
    }

    fn material(&mut self, path: &str, m: &MaterialSpec) {
        if let MaterialSpec::Elastic(e) = m {
            if !(e.youngs_modulus.is_finite() && e.youngs_modulus > 0.0) {
                self.push(
                    &format!("{path}.youngs_modulus"),
                    format!("is {} Pa", number(e.youngs_modulus)),
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
                    format!("is {}", number(e.poisson_ratio)),
                    "give Poisson's ratio in [0, 0.5) (rubber is about 0.49)",
                );
            }
            if let Some(r) = &e.relaxation {
                self.relaxation(&format!("{path}.relaxation"), r, e.youngs_modulus);
            }
            if let Some(h) = e.layer_thickness_m {
                self.range(
                    &format!("{path}.layer_thickness_m"),
                    h,
                    LAYER_THICKNESS_RANGE_M,
                    "m",
                    "give the thickness of the elastic layer on its rigid core in metres (1 mm = \
                     0.001), or omit layer_thickness_m for an elastic half-space",
                );
            }
        }
    }

    /// A relaxation law: times in range, fractions in `[0, 1)` summing below 1 (a long-term
    /// modulus remains), a standard linear solid's long-term modulus in `(0, E_0]`.
    fn relaxation(&mut self, path: &str, r: &RelaxationSpec, youngs_modulus: f64) {
        let time_fix = "give the relaxation time in seconds (1 ms = 0.001)";
        match r {
            RelaxationSpec::Prony(terms) => {
                let mut sum = 0.0;
                for (i, t) in terms.iter().enumerate() {
                    let p = format!("{path}[{i}]");
                    if !(t.fraction.is_finite() && (0.0..1.0).contains(&t.fraction)) {
                        self.push(
                            &format!("{p}.fraction"),
                            format!("is {}", number(t.fraction)),
                            "give the fraction of the instantaneous modulus that relaxes with \
                             this time, in [0, 1)",
                        );
                    } else {
                        sum += t.fraction;
                    }
                    self.range(
                        &format!("{p}.time_s"),
                        t.time_s,
                        RELAXATION_TIME_RANGE_S,
                        "s",
                        time_fix,
                    );
                }
                if sum >= 1.0 {
                    self.push(
                        path,
                        format!("has fractions summing to {}", number(sum)),
                        "make the fractions sum below 1: the modulus left after full relaxation \
                         is (1 - their sum) times youngs_modulus, and must stay above zero",
                    );
                }
            }
            RelaxationSpec::StandardLinearSolid(sls) => {
                let e = sls.long_term_modulus;
                if !(e.is_finite() && e > 0.0 && e <= youngs_modulus) {
                    self.push(
                        &format!("{path}.long_term_modulus"),
                        format!("is {} Pa", number(e)),
                        "give the modulus after full relaxation in pascals, above 0 and at most \
                         youngs_modulus (the instantaneous modulus)",
                    );
                }
                self.range(
                    &format!("{path}.time_s"),
                    sls.time_s,
                    RELAXATION_TIME_RANGE_S,
                    "s",
                    time_fix,
                );
            }
        }
    }

    fn radius(&mut self, path: &str, r: f64, half_patch: f64) {
        if !(r.is_finite() && r > 0.0) {
            self.push(
                path,
                format!("is {} m", number(r)),
                "give the radius of curvature in metres, > 0, or null for flat",
            );
            return;
        }
        let fix = "give the radius in metres, or null for a flat surface";
        if self.range(path, r, LENGTH_RANGE_M, "m", fix) && half_patch.is_finite() && half_patch > r
        {
            self.push(
                path,
                format!(
                    "is {} m, smaller than half the patch ({} m)",
                    number(r),
                    number(half_patch)
                ),
                "shrink patch.size below the diameter, or check the radius (the gap is the \
                 parabolic approximation of the surface)",
            );
        }
    }

    /// Checks a friction law (thesis section 2.6).
    fn friction(&mut self, path: &str, spec: &FrictionSpec, object_rigid: bool) {
        match spec {
            FrictionSpec::Coefficient(c) => {
                self.coefficient(&format!("{path}.mu"), c.mu);
            }
            FrictionSpec::Table(t) => self.friction_table(&format!("{path}.table"), &t.table),
            FrictionSpec::Elastic(e) => {
                self.elastic_law(&format!("{path}.elastic"), &e.elastic, object_rigid)
            }
        }
    }

    /// A friction coefficient: 0, or in `[MIN_NONZERO_FRICTION_COEFFICIENT,
    /// MAX_FRICTION_COEFFICIENT]`.
    fn coefficient(&mut self, path: &str, mu: f64) -> bool {
        let b = (MIN_NONZERO_FRICTION_COEFFICIENT, MAX_FRICTION_COEFFICIENT);
        if mu == 0.0 || (b.0..=b.1).contains(&mu) {
            return true;
        }
        self.push(
            path,
            format!("is {}, neither 0 nor in [{:e}, {:e}]", number(mu), b.0, b.1),
            &format!(
                "give a friction coefficient between {:e} and {:e}, or 0 for a frictionless \
                 finger",
                b.0, b.1
            ),
        );
        false
    }

    // `!(a > b)` is meant: a NaN load must fail the ordering check too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn friction_table(&mut self, path: &str, table: &[[f64; 2]]) {
        if table.is_empty() {
            self.push(
                path,
                "is empty".into(),
                "list at least one [P_N, mu] point (one point is a constant mu)",
            );
        }
        for (j, pt) in table.iter().enumerate() {
            self.force(
                &format!("{path}[{j}][0]"),
                pt[0],
                "give the finger's normal load in newtons",
            );
            self.coefficient(&format!("{path}[{j}][1]"), pt[1]);
            if j > 0 && !(pt[0] > table[j - 1][0]) {
                self.push(
                    &format!("{path}[{j}][0]"),
                    format!(
                        "is {} N, not above the previous load {} N",
                        number(pt[0]),
                        number(table[j - 1][0])
                    ),
                    "sort the points by strictly increasing load",
                );
            }
        }
    }

    fn elastic_law(&mut self, path: &str, q: &ElasticLawParams, object_rigid: bool) {
        for (name, val) in [
            ("finger_radius", q.finger_radius),
            ("object_radius", q.object_radius),
            ("contact_length", q.contact_length),
        ] {
            if !(val.is_finite() && val > 0.0) {
                self.push(
                    &format!("{path}.{name}"),
                    format!("is {} m", number(val)),
                    "give a length in metres, finite and > 0",
                );
            } else {
                self.range(
                    &format!("{path}.{name}"),
                    val,
                    LENGTH_RANGE_M,
                    "m",
                    "give the length in metres",
                );
            }
        }
        if q.finger_radius.is_finite()
            && q.object_radius.is_finite()
            && q.finger_radius >= q.object_radius
        {
            self.push(
                &format!("{path}.object_radius"),
                format!(
                    "is {} m, not larger than finger_radius {} m",
                    number(q.object_radius),
                    number(q.finger_radius)
                ),
                "thesis eq. (40) needs R1 < R2 (finger radius below the object's); \
                 use a table or a constant mu otherwise",
            );
        }
        if object_rigid {
            self.push(
                path,
                "needs an elastic object (eq. 40 uses the object's shear modulus)".into(),
                "give object.material elastic constants, or use a table or constant mu",
            );
        }
    }

    /// Every problem, the first [`MAX_LISTED_PROBLEMS`] listed and the rest counted.
    fn finish(mut self) -> Result<(), SceneError> {
        if self.0.is_empty() {
            return Ok(());
        }
        if self.0.len() > MAX_LISTED_PROBLEMS {
            let more = self.0.len() - MAX_LISTED_PROBLEMS;
            self.0.truncate(MAX_LISTED_PROBLEMS);
            self.push(
                "(more)",
                format!("{more} more problem(s) not listed"),
                "correct the ones above and run again",
            );
        }
        Err(SceneError::Invalid(self.0))
    }
}

/// A number as a reader wants it: plain when moderate, in exponent form otherwise.
fn number(x: f64) -> String {
    crate::number_text::readable(x)
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
