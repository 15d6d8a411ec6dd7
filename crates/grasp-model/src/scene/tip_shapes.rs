//! Fingertips given as solids (scene format `fingers[i].tip.shape`: a mesh, or any primitive
//! the object can be), read and posed while the object's shape is resolved, and checked where
//! they meet the object: the tip's surface passes through the finger's contact point and
//! faces the object there. Runs on the parsed JSON after the fingers are placed, so a placed
//! finger's derived frame is what the tip is checked against.

use nalgebra::Vector3;
use serde_json::Value;

use crate::error::{InputProblem, SceneError};
use crate::geometry::mesh_surface::TriangleMesh;
use crate::geometry::shape::Shape;
use crate::scene::scene_geometry::SharedShape;
use crate::scene::shape_checks::{check_mesh, check_shape_spec};
use crate::scene::shape_spec::{MeshSpec, ShapeSpec};

/// Largest distance of the contact point from the tip's surface, as a fraction of the patch's
/// half diagonal: the tip's heights are measured from its height at the contact point, so a
/// small offset (a simulator's penetration, say) changes nothing, but a tip farther away is
/// posed for another contact.
const CONTACT_DISTANCE_FRACTION: f64 = 0.05;

/// Largest angle between the tip's outward normal at the contact point and the contact's
/// normal, rad (the half-space's small-slope limit, `atan 0.3`).
const MAX_FACING_ANGLE_RAD: f64 = 0.2915;

/// The posed tip shape of every finger (`None` where the tip is not a `shape`), read with
/// `load_mesh`; each problem named under `fingers[i].tip.shape`.
pub fn resolve_tip_shapes(
    scene: &Value,
    load_mesh: &dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>,
) -> Result<Vec<Option<SharedShape>>, SceneError> {
    let fingers = scene["fingers"].as_array().map_or(&[][..], Vec::as_slice);
    let mut problems = Vec::new();
    let mut tips = Vec::with_capacity(fingers.len());
    for (i, f) in fingers.iter().enumerate() {
        match f.pointer("/tip/shape") {
            None => tips.push(None),
            Some(spec) => match tip_shape(i, f, spec, load_mesh) {
                Ok(shape) => tips.push(Some(SharedShape::new(shape))),
                Err(mut p) => {
                    problems.append(&mut p);
                    tips.push(None);
                }
            },
        }
    }
    match problems.is_empty() {
        true => Ok(tips),
        false => Err(SceneError::Invalid(problems)),
    }
}

/// Finger `i`'s tip shape: its spec checked, its mesh read, posed, and met at the contact.
fn tip_shape(
    i: usize,
    finger: &Value,
    spec: &Value,
    load_mesh: &dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>,
) -> Result<Shape, Vec<InputProblem>> {
    let path = format!("fingers[{i}].tip.shape");
    let spec: ShapeSpec = crate::scene::strict_json::variant::<ShapeSpec, serde_json::Error>(
        spec.clone(),
    )
    .map_err(|e| {
        let (path, message) = crate::scene::strict_json::join_path(&path, &e.to_string());
        vec![InputProblem::new(
            &path,
            message,
            "see the scene schema's ShapeSpec",
        )]
    })?;
    check_shape_spec(&path, &spec).map_err(|e| e.problems())?;
    let mesh = match &spec.mesh {
        Some(m) => {
            let mesh = load_mesh(m).map_err(|e| {
                vec![InputProblem::new(
                    format!("{path}.mesh.file"),
                    e,
                    "give the path of an OBJ or STL file, relative to the scene file",
                )]
            })?;
            check_mesh(&path, &mesh).map_err(|p| vec![p])?;
            Some(mesh)
        }
        None => None,
    };
    let shape = spec.posed(mesh).map_err(|e| {
        vec![InputProblem::new(
            &path,
            e,
            "give a closed mesh or a primitive",
        )]
    })?;
    meets_the_contact(&path, finger, &shape).map_err(|p| vec![p])?;
    Ok(shape)
}

/// The tip's surface passes within [`CONTACT_DISTANCE_FRACTION`] of the patch's half diagonal
/// of the contact point, its outward normal there within [`MAX_FACING_ANGLE_RAD`] of the
/// contact's inward normal (the tip pushes into the object).
fn meets_the_contact(path: &str, finger: &Value, shape: &Shape) -> Result<(), InputProblem> {
    let (Some(point), Some(normal)) = (
        vec3_at(&finger["contact_point"]),
        vec3_at(&finger["normal"]).and_then(|n| n.try_normalize(0.0)),
    ) else {
        // Without a usable frame validation names the finger's own fields.
        return Ok(());
    };
    let size = &finger["patch"]["size"];
    let half_diagonal = 0.5
        * size[0]
            .as_f64()
            .unwrap_or(0.0)
            .hypot(size[1].as_f64().unwrap_or(0.0));
    let s = shape.closest(&point).map_err(|e| {
        InputProblem::new(
            path,
            e,
            "pose the tip so that its surface passes through the contact point",
        )
    })?;
    let tolerance = CONTACT_DISTANCE_FRACTION * half_diagonal;
    // Negated on purpose: a NaN distance fails the check.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let far = !(s.distance_m.abs() <= tolerance);
    if far {
        return Err(InputProblem::new(
            path,
            format!(
                "lies {:.3e} m from the contact point (more than {tolerance:.3e} m, 5 % of the \
                 patch's half diagonal)",
                s.distance_m.abs()
            ),
            "pose the tip (its position and quaternion) so that its surface passes through the \
             finger's contact point",
        ));
    }
    let angle = s.outward_normal.dot(&normal).clamp(-1.0, 1.0).acos();
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let turned = !(angle <= MAX_FACING_ANGLE_RAD);
    if turned {
        return Err(InputProblem::new(
            path,
            format!(
                "faces {:.1} degrees away from the contact's normal at the contact point (at \
                 most {:.1})",
                angle.to_degrees(),
                MAX_FACING_ANGLE_RAD.to_degrees()
            ),
            "turn the tip so that its surface at the contact point faces the object along the \
             finger's normal",
        ));
    }
    Ok(())
}

fn vec3_at(v: &Value) -> Option<Vector3<f64>> {
    let a: [f64; 3] = serde_json::from_value(v.clone()).ok()?;
    a.iter().all(|x| x.is_finite()).then(|| Vector3::from(a))
}
