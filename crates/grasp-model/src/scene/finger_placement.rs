//! Fingers placed on the object's shape (scene format `fingers[i].place`), the object's mass
//! from a density (`object.density`), and the checks that use the shape. Runs on the parsed
//! JSON before the typed scene is read: a placed finger gets the `contact_point`, inward
//! `normal`, `tangent` (a principal direction) and `object_radius` (principal radii) derived
//! from the surface, so the rest of the model sees an explicit frame; what was derived is kept
//! in a [`ShapeReport`], the posed shapes and the surface in a [`SceneGeometry`].

use nalgebra::Vector3;
use serde_json::{json, Map, Value};

use crate::error::{InputProblem, SceneError};
use crate::geometry::mesh_surface::TriangleMesh;
use crate::geometry::mesh_topology::MeshDefects;
use crate::geometry::shape::Shape;
use crate::geometry::surface_point::{SurfaceFeature, SurfacePoint};
use crate::scene::patch_on_shape::{overhang_warning, overlap_warnings};
use crate::scene::shape_checks::check_shape_spec;
use crate::scene::shape_spec::PlaceSpec;
use crate::scene::shape_spec::{MeshSpec, ShapeSpec};

/// Principal curvatures equal to this fraction of the larger are an umbilic point (a sphere's):
/// every tangent is a principal direction.
const UMBILIC_FRACTION: f64 = 1e-9;
/// A principal direction within `acos(1 - this)` (about 0.08 degrees) of the plane of motion's
/// normal counts as along it.
const ALIGNED_COSINE_GAP: f64 = 1e-6;
/// A tangent hint whose part in the tangent plane is below this fraction of it (it is along
/// the normal) is ignored.
const NORMAL_HINT_FRACTION: f64 = 1e-9;
use crate::scene::scene_geometry::{SceneGeometry, SharedShape};
use crate::scene::shape_report::{DerivedFrame, ShapeReport};

type Vec3 = [f64; 3];

/// Standard gravity, m/s^2 (weight from a density: `W = rho V g0`).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Default largest distance of a finger's point from the surface, m.
use crate::scene::shape_spec::DEFAULT_SURFACE_TOLERANCE_M;

/// A principal curvature below this magnitude counts as flat, 1/m (radius above 1 km).
pub const FLAT_CURVATURE_PER_M: f64 = 1e-3;

fn problem(path: &str, message: String, fix: &str) -> InputProblem {
    InputProblem {
        path: path.into(),
        message,
        fix: fix.into(),
    }
}

/// `v` as an array, negative zeros made positive (for printing).
fn arr(v: &Vector3<f64>) -> Vec3 {
    [v.x + 0.0, v.y + 0.0, v.z + 0.0]
}

fn vec3_at(v: &Value) -> Option<Vector3<f64>> {
    let a: Vec3 = serde_json::from_value(v.clone()).ok()?;
    a.iter().all(|x| x.is_finite()).then(|| Vector3::from(a))
}

/// Resolves `object.shape`, `object.density` and every `fingers[i].place` in `scene` (the
/// parsed JSON), reading meshes with `load_mesh`: what the shape gave (its report, the posed
/// object and tip shapes, the object's triangles; no height maps). `None` when the scene has
/// no shape.
pub fn resolve_shapes(
    scene: &mut Value,
    load_mesh: &dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>,
) -> Result<Option<SceneGeometry>, SceneError> {
    let Some(shape_value) = scene.pointer("/object/shape").cloned() else {
        return no_shape(scene).map(|_| None);
    };
    let spec: ShapeSpec = crate::scene::strict_json::variant::<ShapeSpec, serde_json::Error>(
        shape_value,
    )
    .map_err(|e| {
        let (path, message) = crate::scene::strict_json::join_path("object.shape", &e.to_string());
        SceneError::Parse { path, message }
    })?;
    check_shape_spec("object.shape", &spec)?;
    let mesh = match &spec.mesh {
        Some(m) => Some(load_mesh(m).map_err(|e| {
            SceneError::Invalid(vec![problem(
                "object.shape.mesh.file",
                e,
                "give the path of an OBJ or STL file, relative to the scene file",
            )])
        })?),
        None => None,
    };
    if let Some(m) = &mesh {
        crate::scene::shape_checks::check_mesh("object.shape", m)
            .map_err(|p| SceneError::Invalid(vec![p]))?;
    }
    let shape = spec
        .posed(mesh)
        .map_err(|e| SceneError::Invalid(vec![problem("object.shape", e, "give a closed mesh")]))?;
    let (volume_m3, centroid) = shape.volume_and_centroid();
    let open = shape.open_mesh();
    let mass_kg = apply_density(scene, volume_m3, &centroid, open)?;
    let plane = scene
        .pointer("/planar/normal")
        .and_then(vec3_at)
        .map(|p| p.normalize());
    let mut fingers = Vec::new();
    let mut problems = Vec::new();
    let count = scene["fingers"].as_array().map_or(0, Vec::len);
    for i in 0..count {
        match place_finger(&mut scene["fingers"][i], i, &shape, plane.as_ref()) {
            Ok(Some(d)) => fingers.push(d),
            Ok(None) => {}
            Err(p) => problems.push(p),
        }
    }
    if !problems.is_empty() {
        return Err(SceneError::Invalid(problems));
    }
    let tips = crate::scene::tip_shapes::resolve_tip_shapes(scene, load_mesh)?;
    let mut warnings: Vec<String> = open
        .iter()
        .map(|d| open_mesh_warning(d, volume_m3))
        .collect();
    // With exact gaps the elements past an edge face no surface and carry nothing: only the
    // thesis's quadratic gap, blind to the edge, needs the warning.
    warnings.extend(
        (0..count)
            .filter(|&i| quadratic_gap(scene, i))
            .filter_map(|i| overhang_warning(&scene["fingers"][i], &shape)),
    );
    warnings.extend(overlap_warnings(&scene["fingers"]));
    let report = ShapeReport {
        volume_m3,
        centroid_m: arr(&centroid),
        mass_kg,
        fingers,
        warnings,
    };
    Ok(Some(shape_geometry(report, shape, tips)))
}

/// What the shape gave the scene: its report, the posed object shape and its triangles, the
/// posed tips (no height maps: the reader reads them).
fn shape_geometry(
    report: ShapeReport,
    shape: Shape,
    tips: Vec<Option<SharedShape>>,
) -> SceneGeometry {
    let surface = crate::geometry::tessellation::tessellate(&shape);
    SceneGeometry {
        report: Some(report),
        surface: Some(std::sync::Arc::new(surface)),
        shape: Some(SharedShape::new(shape)),
        tips,
        height_maps: Vec::new(),
    }
}

/// True when finger `i` of the parsed scene uses the thesis's quadratic gap (its own `gap`, else
/// the scene's; with a shape the default is exact).
fn quadratic_gap(scene: &Value, i: usize) -> bool {
    let gap = scene["fingers"][i]
        .get("gap")
        .filter(|g| !g.is_null())
        .or_else(|| scene.get("gap").filter(|g| !g.is_null()));
    gap.and_then(Value::as_str) == Some("quadratic")
}

/// Without a shape, `place` and `density` cannot be used.
fn no_shape(scene: &Value) -> Result<(), SceneError> {
    let mut problems = Vec::new();
    if scene.pointer("/object/density").is_some() {
        problems.push(problem(
            "object.density",
            "needs object.shape (the volume comes from the shape)".into(),
            "give object.shape, or object.weight and object.center_of_mass instead",
        ));
    }
    for (i, f) in scene["fingers"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        if f.get("place").is_some() {
            problems.push(problem(
                &format!("fingers[{i}].place"),
                "needs object.shape to place the finger on".into(),
                "give object.shape, or the finger's contact_point and normal instead",
            ));
        }
    }
    match problems.is_empty() {
        true => Ok(()),
        false => Err(SceneError::Invalid(problems)),
    }
}

/// The warning for a mesh that is not closed: its volume is not the object's.
fn open_mesh_warning(d: &MeshDefects, volume_m3: f64) -> String {
    format!(
        "object.shape.mesh: the mesh is not closed ({}): the volume its triangles give \
         ({volume_m3:.6e} m^3) and its centroid are not the object's, and whether a point is \
         inside or outside is uncertain near the gaps (close the mesh: every edge shared by \
         two triangles)",
        d.describe()
    )
}

/// Weight and centre of mass from `object.density` (kg/m^3): `W = rho V g0`, at the centroid.
/// Refused on a mesh that is not closed (`open`): the volume its triangles give then depends
/// on where the origin is, and is not the object's.
fn apply_density(
    scene: &mut Value,
    volume_m3: f64,
    centroid: &Vector3<f64>,
    open: Option<MeshDefects>,
) -> Result<Option<f64>, SceneError> {
    let Some(rho) = scene.pointer("/object/density").cloned() else {
        return Ok(None);
    };
    if let Some(d) = open {
        return Err(SceneError::Invalid(vec![problem(
            "object.density",
            format!(
                "needs a closed mesh, and object.shape.mesh is not closed ({}): its volume is not the object's",
                d.describe()
            ),
            "give object.weight (N) and object.center_of_mass (m) instead, or close the mesh (every edge shared by two triangles)",
        )]));
    }
    let fix = "give the density in kg/m^3, in [1e-3, 1e5] (aluminium: 2700)";
    let rho = match rho.as_f64() {
        Some(r) if (1e-3..=1e5).contains(&r) => r,
        _ => {
            return Err(SceneError::Invalid(vec![problem(
                "object.density",
                format!("is {rho}"),
                fix,
            )]))
        }
    };
    let Some(object) = scene["object"].as_object_mut() else {
        return Err(SceneError::Invalid(vec![problem(
            "object",
            "is not an object".into(),
            "give the object as {\"density\": ..., \"shape\": ...}",
        )]));
    };
    for key in ["weight", "center_of_mass"] {
        if object.contains_key(key) {
            return Err(SceneError::Invalid(vec![problem(
                &format!("object.{key}"),
                "is given together with object.density".into(),
                "give either the density (weight and centre of mass follow from the shape) or the weight and centre of mass",
            )]));
        }
    }
    let mass_kg = rho * volume_m3;
    object.insert("weight".into(), json!(mass_kg * STANDARD_GRAVITY));
    object.insert("center_of_mass".into(), json!(arr(centroid)));
    Ok(Some(mass_kg))
}

/// Places finger `i` (its JSON object `f`) when it has `place`, or checks its explicit frame
/// against the shape.
fn place_finger(
    f: &mut Value,
    i: usize,
    shape: &Shape,
    plane: Option<&Vector3<f64>>,
) -> Result<Option<DerivedFrame>, InputProblem> {
    let name = f
        .get("name")
        .and_then(Value::as_str)
        .unwrap_or("?")
        .to_string();
    let Some(place) = f.get("place").cloned() else {
        return check_explicit(f, i, &name, shape);
    };
    let path = format!("fingers[{i}].place");
    // A cylindrical tip's axis is the preferred t1 (the curvatures must share directions).
    let tip_axis = f.pointer("/tip/cylinder/axis").and_then(vec3_at);
    let spec: PlaceSpec = serde_json::from_value(place).map_err(|e| {
        problem(
            &path,
            e.to_string(),
            "give {\"point\": [x, y, z]} or {\"ray\": {\"origin\": [...], \"direction\": [...]}}",
        )
    })?;
    let obj = without_frame(f, i)?;
    if spec.tangent.is_some_and(|t| Vector3::from(t).norm() == 0.0) {
        return Err(problem(
            &format!("{path}.tangent"),
            "has zero length".into(),
            "give the preferred first tangent, or omit it",
        ));
    }
    let (s, source) = face_point(&spec, &path, shape)?;
    let hint = spec.tangent.map(Vector3::from).or(tip_axis);
    let frame = tangent_frame(&s, hint, plane).map_err(|m| {
        problem(
            &path,
            m,
            "in a planar scene, place fingers where the shape is a prism along the plane normal",
        )
    })?;
    let (radius, notes) = radii(frame.curvatures);
    write_frame(obj, &s, &frame, plane.is_none(), radius);
    Ok(Some(DerivedFrame {
        finger: name,
        source: source.into(),
        contact_point_m: arr(&s.point_m),
        normal: arr(&-s.outward_normal),
        tangent: Some(arr(&frame.t1)),
        curvature_per_m: frame.curvatures,
        object_radius_m: radius,
        distance_m: s.distance_m,
        notes,
    }))
}

/// Finger `i`'s JSON object `f` as a map, refused when it is not an object or gives a part of
/// the frame that `place` derives.
fn without_frame(f: &mut Value, i: usize) -> Result<&mut Map<String, Value>, InputProblem> {
    let Some(obj) = f.as_object_mut() else {
        return Err(problem(
            &format!("fingers[{i}]"),
            "is not an object".into(),
            "give each finger as {\"name\": ..., ...}",
        ));
    };
    for key in ["contact_point", "normal", "tangent", "object_radius"] {
        if obj.get(key).is_some_and(|v| !v.is_null()) {
            return Err(problem(
                &format!("fingers[{i}].{key}"),
                "is given together with place (which derives it from the shape)".into(),
                "remove it, or remove place and give the frame by hand",
            ));
        }
    }
    Ok(obj)
}

/// The surface point of a place spec and which kind it was, refused off the faces (on an
/// edge or a corner the normal is not defined).
fn face_point(
    spec: &PlaceSpec,
    path: &str,
    shape: &Shape,
) -> Result<(SurfacePoint, &'static str), InputProblem> {
    let (s, source) = surface_point(spec, path, shape)?;
    if s.feature != SurfaceFeature::Face {
        return Err(problem(
            path,
            format!(
                "lands on {} of the shape at {:?}, where the normal is not defined",
                if s.feature == SurfaceFeature::Edge {
                    "an edge"
                } else {
                    "a corner"
                },
                arr(&s.point_m)
            ),
            "move the finger onto a face",
        ));
    }
    Ok((s, source))
}

/// The surface point of a place spec, and which kind it was.
fn surface_point(
    spec: &PlaceSpec,
    path: &str,
    shape: &Shape,
) -> Result<(SurfacePoint, &'static str), InputProblem> {
    match (&spec.point, &spec.ray) {
        (Some(p), None) => {
            let p = Vector3::from(*p);
            let s = shape.closest(&p).map_err(|m| {
                problem(&format!("{path}.point"), m, "give a point near the surface")
            })?;
            if !(spec.tolerance.is_finite() && spec.tolerance >= 0.0) {
                return Err(problem(
                    &format!("{path}.tolerance"),
                    format!("is {}", crate::number_text::readable(spec.tolerance)),
                    "give a distance in metres >= 0",
                ));
            }
            if s.distance_m.abs() > spec.tolerance {
                return Err(problem(
                    &format!("{path}.point"),
                    format!("is {:.3} mm {} the surface (tolerance {:.3} mm); the nearest surface point is {:?}", 1e3 * s.distance_m.abs(), if s.distance_m < 0.0 { "inside" } else { "off" }, 1e3 * spec.tolerance, arr(&s.point_m)),
                    "give a point on the surface, or raise place.tolerance",
                ));
            }
            Ok((s, "point"))
        }
        (None, Some(r)) => {
            let d = Vector3::from(r.direction);
            if !(d.norm() > 0.0 && d.iter().all(|x| x.is_finite())) {
                return Err(problem(
                    &format!("{path}.ray.direction"),
                    "has zero length".into(),
                    "give the approach direction",
                ));
            }
            let o = Vector3::from(r.origin);
            match shape.ray_hit(&o, &d) {
                Err(m) => Err(problem(
                    &format!("{path}.ray.origin"),
                    m,
                    "start the ray outside the object",
                )),
                Ok(None) => Err(problem(
                    &format!("{path}.ray"),
                    format!(
                        "from {:?} along {:?} misses the object",
                        r.origin, r.direction
                    ),
                    "aim the ray at the object",
                )),
                // Only a mesh that is not closed lets a ray from outside meet the back of
                // a triangle; the finger would push the surface from the wrong side.
                Ok(Some(s)) if shape.open_mesh().is_some() && s.outward_normal.dot(&d) > 0.0 => {
                    Err(problem(
                        &format!("{path}.ray"),
                        format!(
                            "from {:?} along {:?} meets the back of the mesh at {:?} (the mesh is not closed, and its triangles face away from the ray there)",
                            r.origin, r.direction, arr(&s.point_m)
                        ),
                        "approach from the side the triangles face (counter-clockwise seen from outside), or close the mesh",
                    ))
                }
                Ok(Some(s)) => Ok((s, "ray")),
            }
        }
        _ => Err(problem(
            path,
            "needs exactly one of point and ray".into(),
            "give {\"point\": [x, y, z]} or {\"ray\": {...}}",
        )),
    }
}

/// A finger frame on the surface: `t1` and the curvatures along `t1`, `t2`.
struct TangentFrame {
    t1: Vector3<f64>,
    curvatures: [f64; 2],
}

/// `t1` among the principal directions: along the hint where the point is umbilic (equal
/// curvatures), else the principal direction closest to it; in a planar scene the direction
/// in the plane (`t2` is the plane normal).
fn tangent_frame(
    s: &SurfacePoint,
    hint: Option<Vector3<f64>>,
    plane: Option<&Vector3<f64>>,
) -> Result<TangentFrame, String> {
    let [d1, d2] = s.directions;
    let [k1, k2] = s.curvatures_per_m;
    let n = -s.outward_normal;
    let umbilic =
        (k1 - k2).abs() <= UMBILIC_FRACTION * k1.abs().max(k2.abs()).max(f64::MIN_POSITIVE);
    if let Some(p) = plane {
        let t1 = p.cross(&n).normalize();
        if umbilic {
            return Ok(TangentFrame {
                t1,
                curvatures: [k1, k2],
            });
        }
        let along_d1 = d1.dot(p).abs() > 1.0 - ALIGNED_COSINE_GAP;
        let along_d2 = d2.dot(p).abs() > 1.0 - ALIGNED_COSINE_GAP;
        return match (along_d1, along_d2) {
            (_, true) => Ok(TangentFrame {
                t1,
                curvatures: [k1, k2],
            }),
            (true, false) => Ok(TangentFrame {
                t1,
                curvatures: [k2, k1],
            }),
            _ => {
                Err("lands where no principal direction of the surface is the plane normal".into())
            }
        };
    }
    let hint = hint
        .map(|h| h - n * n.dot(&h))
        .filter(|h| h.norm() > NORMAL_HINT_FRACTION * (1.0 + h.norm()));
    Ok(match (umbilic, hint) {
        (true, Some(h)) => TangentFrame {
            t1: h.normalize(),
            curvatures: [k1, k2],
        },
        (false, Some(h)) if h.dot(&d2).abs() > h.dot(&d1).abs() => TangentFrame {
            t1: d2,
            curvatures: [k2, k1],
        },
        _ => TangentFrame {
            t1: d1,
            curvatures: [k1, k2],
        },
    })
}

/// Object radii along `t1`, `t2` from the curvatures: flat below [`FLAT_CURVATURE_PER_M`];
/// concave directions are treated as flat, with a note.
fn radii(k: [f64; 2]) -> ([Option<f64>; 2], Vec<String>) {
    let mut notes = Vec::new();
    let r = [0, 1].map(|a| {
        if k[a] > FLAT_CURVATURE_PER_M {
            Some(1.0 / k[a])
        } else {
            if k[a] < -FLAT_CURVATURE_PER_M {
                notes.push(format!(
                    "concave along t{} (radius {:.4} m): treated as flat, as the contact model takes convex or flat surfaces",
                    a + 1,
                    -1.0 / k[a]
                ));
            }
            None
        }
    });
    (r, notes)
}

/// Writes the derived frame into the finger's JSON.
fn write_frame(
    obj: &mut Map<String, Value>,
    s: &SurfacePoint,
    frame: &TangentFrame,
    with_tangent: bool,
    radius: [Option<f64>; 2],
) {
    obj.insert("contact_point".into(), json!(arr(&s.point_m)));
    obj.insert("normal".into(), json!(arr(&-s.outward_normal)));
    if with_tangent {
        obj.insert("tangent".into(), json!(arr(&frame.t1)));
    }
    let r = match radius {
        [None, None] => Value::Null,
        [Some(a), Some(b)] if a == b => json!(a),
        [a, b] => json!([a, b]),
    };
    obj.insert("object_radius".into(), r);
}

/// Checks an explicit frame on a shaped object: the point near the surface, the normal
/// pointing in.
fn check_explicit(
    f: &Value,
    i: usize,
    name: &str,
    shape: &Shape,
) -> Result<Option<DerivedFrame>, InputProblem> {
    let (Some(p), Some(n)) = (
        f.get("contact_point").and_then(vec3_at),
        f.get("normal").and_then(vec3_at),
    ) else {
        return Ok(None); // missing or malformed: the typed parse reports it
    };
    let s = shape.closest(&p).map_err(|m| {
        problem(
            &format!("fingers[{i}].contact_point"),
            m,
            "give a point on the surface",
        )
    })?;
    if s.distance_m.abs() > DEFAULT_SURFACE_TOLERANCE_M {
        return Err(problem(
            &format!("fingers[{i}].contact_point"),
            format!(
                "is {:.3} mm {} the object's surface; the nearest surface point is {:?}",
                1e3 * s.distance_m.abs(),
                if s.distance_m < 0.0 { "inside" } else { "off" },
                arr(&s.point_m)
            ),
            "put the contact point on the surface (or use place: {\"point\": ...} to project it)",
        ));
    }
    let inward = -s.outward_normal;
    let mut notes = Vec::new();
    if n.norm() > 0.0 {
        let c = n.normalize().dot(&inward);
        if c < 0.0 {
            return Err(problem(
                &format!("fingers[{i}].normal"),
                format!(
                    "points out of the object (the surface's inward normal there is {:?})",
                    arr(&inward)
                ),
                "give the normal pointing into the object (the direction the finger pushes)",
            ));
        }
        if s.feature == SurfaceFeature::Face && c < 10f64.to_radians().cos() {
            notes.push(format!(
                "normal is {:.1} deg off the surface normal",
                c.clamp(-1.0, 1.0).acos().to_degrees()
            ));
        }
    }
    Ok(Some(DerivedFrame {
        finger: name.into(),
        source: "explicit".into(),
        contact_point_m: arr(&s.point_m),
        normal: arr(&inward),
        tangent: None,
        curvature_per_m: s.curvatures_per_m,
        object_radius_m: [None, None],
        distance_m: s.distance_m,
        notes,
    }))
}
