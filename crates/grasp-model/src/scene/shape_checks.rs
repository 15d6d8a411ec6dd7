//! Checks of a shape as written (`object.shape`, a finger's `tip.shape`): exactly one geometry,
//! sizes in range, a usable pose; each problem named under the path given.

use std::ops::RangeInclusive;

use crate::error::{InputProblem, SceneError};
use crate::geometry::mesh_surface::TriangleMesh;
use crate::number_text::readable;
use crate::scene::limits::{MAX_COORDINATE_M, MAX_MESH_TRIANGLES};
use crate::scene::mesh_budget::{check_mesh_room, MESH_BYTES_PER_TRIANGLE};
use crate::scene::shape_spec::ShapeSpec;

/// A quaternion shorter than this has no direction to normalise to.
const MIN_QUATERNION_NORM: f64 = 1e-9;

/// Smallest and largest size of a shape dimension, m.
pub const SHAPE_SIZE_RANGE_M: RangeInclusive<f64> = 1e-6..=1e3;

/// The first problem of a mesh as read (vertices in metres after `unit` and `scale`): more
/// triangles than [`MAX_MESH_TRIANGLES`] or than the memory left can prepare, a vertex that is
/// not finite or lies beyond [`MAX_COORDINATE_M`] (a garbage file, or a unit or scale too
/// large), or a triangle naming a vertex the mesh does not have.
pub fn check_mesh(path: &str, mesh: &TriangleMesh) -> Result<(), InputProblem> {
    let file = format!("{path}.mesh.file");
    let triangles = mesh.triangles.len();
    if triangles > MAX_MESH_TRIANGLES {
        return Err(problem(
            &file,
            too_many_triangles(triangles),
            MESH_TOO_FINE_FIX,
        ));
    }
    if let Err(e) = check_mesh_room(triangles) {
        return Err(problem(
            &file,
            e.message(),
            &format!("{MESH_TOO_FINE_FIX}; or free memory or raise the memory limit"),
        ));
    }
    let bad = |v: &[f64; 3]| {
        !v.iter()
            .all(|x| x.is_finite() && x.abs() <= MAX_COORDINATE_M)
    };
    if let Some((i, v)) = mesh.vertices_m.iter().enumerate().find(|(_, v)| bad(v)) {
        return Err(problem(
            &file,
            format!(
                "vertex {i} of the mesh is [{}, {}, {}] m (after unit and scale): not finite or \
                 beyond {MAX_COORDINATE_M:e} m",
                readable(v[0]),
                readable(v[1]),
                readable(v[2])
            ),
            "correct the file's vertices, or its unit or scale, so that every coordinate is a \
             finite number of metres within 1e3",
        ));
    }
    let n = mesh.vertices_m.len();
    if let Some((t, tri)) =
        (mesh.triangles.iter().enumerate()).find(|(_, tri)| tri.iter().any(|&k| k as usize >= n))
    {
        return Err(problem(
            &file,
            format!("triangle {t} names vertex {tri:?}, but the mesh has {n} vertices"),
            "correct the file's faces",
        ));
    }
    Ok(())
}

/// What to do with a mesh too fine to prepare.
pub const MESH_TOO_FINE_FIX: &str =
    "decimate the mesh (MeshLab's Quadric Edge Collapse Decimation, \
                            Blender's Decimate modifier): the contact model needs the surface \
                            near the fingers no finer than their patches' elements";

/// The message of a mesh of `triangles` triangles, more than [`MAX_MESH_TRIANGLES`].
pub fn too_many_triangles(triangles: usize) -> String {
    format!(
        "holds {triangles} triangles, more than the {MAX_MESH_TRIANGLES} a mesh may have \
         (preparing it would take about {:.1} GB)",
        triangles as f64 * MESH_BYTES_PER_TRIANGLE as f64 / 1e9
    )
}

/// Every problem of `spec`.
pub fn check_shape_spec(path: &str, spec: &ShapeSpec) -> Result<(), SceneError> {
    let mut p = Vec::new();
    let kinds = [
        spec.box_shape.is_some(),
        spec.sphere.is_some(),
        spec.cylinder.is_some(),
        spec.capsule.is_some(),
        spec.mesh.is_some(),
    ];
    if kinds.iter().filter(|k| **k).count() != 1 {
        p.push(problem(
            path,
            "needs exactly one of box, sphere, cylinder, capsule, mesh".into(),
            "give one geometry, e.g. {\"box\": {\"size\": [0.1, 0.1, 0.1]}}",
        ));
    }
    let mut size = |path: &str, v: f64, zero_ok: bool| {
        if !(v.is_finite() && (SHAPE_SIZE_RANGE_M.contains(&v) || (zero_ok && v == 0.0))) {
            p.push(problem(
                path,
                format!("is {}", readable(v)),
                &format!(
                    "give a length in metres in [{:e}, {:e}]",
                    SHAPE_SIZE_RANGE_M.start(),
                    SHAPE_SIZE_RANGE_M.end()
                ),
            ));
        }
    };
    if let Some(b) = &spec.box_shape {
        for (k, v) in b.size.iter().enumerate() {
            size(&format!("{path}.box.size[{k}]"), *v, false);
        }
    }
    if let Some(s) = &spec.sphere {
        size(&format!("{path}.sphere.radius"), s.radius, false);
    }
    for (name, c, zero_ok) in [
        ("cylinder", &spec.cylinder, false),
        ("capsule", &spec.capsule, true),
    ] {
        if let Some(c) = c {
            size(&format!("{path}.{name}.radius"), c.radius, false);
            size(&format!("{path}.{name}.length"), c.length, zero_ok);
        }
    }
    if let Some(m) = &spec.mesh {
        if !(m.scale.is_finite() && m.scale > 0.0) {
            p.push(problem(
                &format!("{path}.mesh.scale"),
                format!("is {}", readable(m.scale)),
                "give a positive factor, e.g. 1",
            ));
        }
    }
    for (k, v) in spec.position.iter().enumerate() {
        if !(v.is_finite() && v.abs() <= 1e3) {
            p.push(problem(
                &format!("{path}.position[{k}]"),
                format!("is {}", readable(*v)),
                "give a coordinate in metres in [-1e3, 1e3]",
            ));
        }
    }
    let q = spec.quaternion;
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(len.is_finite() && len > MIN_QUATERNION_NORM) {
        p.push(problem(
            &format!("{path}.quaternion"),
            format!("is {q:?}"),
            "give a rotation [w, x, y, z], e.g. [1, 0, 0, 0]",
        ));
    }
    match p.is_empty() {
        true => Ok(()),
        false => Err(SceneError::Invalid(p)),
    }
}

fn problem(path: &str, message: String, fix: &str) -> InputProblem {
    InputProblem {
        path: path.into(),
        message,
        fix: fix.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh finer than a contact model needs (a million triangles took 76 s and 632 MB for a
    /// 16 x 16 pinch; the limit admitted six times that) is refused above
    /// [`MAX_MESH_TRIANGLES`], naming the count, the memory it would take and the fix.
    #[test]
    fn a_mesh_with_more_triangles_than_the_limit_is_refused_with_the_fix() {
        let mesh = |n: usize| TriangleMesh {
            vertices_m: vec![[0.0; 3], [1e-3, 0.0, 0.0], [0.0, 1e-3, 0.0]],
            triangles: vec![[0, 1, 2]; n],
        };
        let p = check_mesh("object.shape", &mesh(MAX_MESH_TRIANGLES + 1)).unwrap_err();
        assert_eq!(p.path, "object.shape.mesh.file");
        assert!(
            p.message
                .contains("holds 2000001 triangles, more than the 2000000"),
            "{}",
            p.message
        );
        assert!(p.message.contains("GB"), "{}", p.message);
        assert!(p.fix.contains("decimate"), "{}", p.fix);
        assert!(check_mesh("object.shape", &mesh(1000)).is_ok());
    }
}
