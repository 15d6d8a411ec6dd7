//! Mesh files of `object.shape.mesh`: OBJ (with `tobj`, triangulated) and STL (binary or
//! ASCII, with `stl_io`), read through [`crate::input_file`] (a regular file of at most
//! [`MESH_FILE`]'s 256 MiB) and parsed from memory. An OBJ's materials are never read: its
//! `mtllib` lines name files the geometry does not need (and could name `/dev/zero`), so the
//! material loader loads nothing.

use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

use grasp_model::limits::MAX_MESH_TRIANGLES;
use grasp_model::MeshSpec;
use grasp_model::{too_many_triangles, TriangleMesh, MESH_TOO_FINE_FIX};

use crate::input_file::{read_bytes, FileIdentity, MESH_FILE};

/// The mesh of `spec` from the file at `path`, in metres (`unit`, then `scale`).
pub fn read_mesh(path: &Path, spec: &MeshSpec) -> Result<TriangleMesh, String> {
    read_mesh_file(path, spec).map(|(mesh, _)| mesh)
}

/// As [`read_mesh`], with the identity of the file read.
pub fn read_mesh_file(
    path: &Path,
    spec: &MeshSpec,
) -> Result<(TriangleMesh, FileIdentity), String> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if ext != "obj" && ext != "stl" {
        return Err(format!(
            "{}: unknown mesh format `.{ext}`; give an .obj or .stl file",
            path.display()
        ));
    }
    let (bytes, identity) = read_bytes(path, MESH_FILE).map_err(|e| e.to_string())?;
    if let Some(n) = binary_stl_triangles(&bytes).filter(|&n| n > MAX_MESH_TRIANGLES) {
        return Err(format!(
            "{} {}; {MESH_TOO_FINE_FIX}",
            path.display(),
            too_many_triangles(n)
        ));
    }
    let mut mesh = if ext == "obj" {
        parse_obj(&bytes).map_err(|e| format!("{}: {e}", path.display()))?
    } else {
        parse_stl(&bytes)
            .map_err(|e| format!("{}: not a readable STL file: {e}", path.display()))?
    };
    let factor = spec.unit.metres() * spec.scale;
    for v in &mut mesh.vertices_m {
        *v = v.map(|x| x * factor);
    }
    if mesh.triangles.is_empty() {
        return Err(format!("{} holds no triangles", path.display()));
    }
    Ok((mesh, identity))
}

/// The triangle count a binary STL's header gives, when `bytes` is one (80 bytes of header,
/// the count, then 50 bytes a triangle, exactly): read before parsing, so that a mesh too
/// fine to prepare is refused before its vertices are built.
fn binary_stl_triangles(bytes: &[u8]) -> Option<usize> {
    let count = bytes.get(80..84)?;
    let n = u32::from_le_bytes(count.try_into().ok()?) as usize;
    (n.checked_mul(50)?.checked_add(84)? == bytes.len()).then_some(n)
}

/// An OBJ file's triangles (faces triangulated, one index per vertex); materials not read.
fn parse_obj(bytes: &[u8]) -> Result<TriangleMesh, tobj::LoadError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let no_materials = |_: &Path| -> tobj::MTLLoadResult { Ok((Vec::new(), HashMap::new())) };
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(bytes), &options, no_materials)?;
    let mut mesh = TriangleMesh {
        vertices_m: Vec::new(),
        triangles: Vec::new(),
    };
    for m in models {
        let base = mesh.vertices_m.len() as u32;
        let p = &m.mesh.positions;
        mesh.vertices_m.extend(
            p.chunks_exact(3)
                .map(|c| [f64::from(c[0]), f64::from(c[1]), f64::from(c[2])]),
        );
        mesh.triangles.extend(
            m.mesh
                .indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    Ok(mesh)
}

/// An STL file's triangles (binary or ASCII).
fn parse_stl(bytes: &[u8]) -> std::io::Result<TriangleMesh> {
    let stl = stl_io::read_stl(&mut Cursor::new(bytes))?;
    Ok(TriangleMesh {
        vertices_m: stl
            .vertices
            .iter()
            .map(|v| [f64::from(v[0]), f64::from(v[1]), f64::from(v[2])])
            .collect(),
        triangles: stl
            .faces
            .iter()
            .map(|f| f.vertices.map(|i| i as u32))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TETRA: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    fn spec(file: &str) -> MeshSpec {
        serde_json::from_value(serde_json::json!({"file": file, "unit": "mm"})).unwrap()
    }

    #[test]
    fn materials_are_never_read() {
        let d = std::env::temp_dir().join(format!("grasp-io-mtl-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        // Each names a material library that would hang (a FIFO), run away (/dev/zero), or
        // fail (missing, a folder): the geometry is read all the same.
        let fifo = d.join("pipe.mtl");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.as_ref().is_ok_and(|s| s.success()), "mkfifo: {made:?}");
        for lib in [
            "/dev/zero".to_string(),
            fifo.display().to_string(),
            "missing.mtl".into(),
            d.display().to_string(),
        ] {
            let obj = d.join("t.obj");
            std::fs::write(&obj, format!("mtllib {lib}\nusemtl steel\n{TETRA}")).unwrap();
            let mesh = read_mesh(&obj, &spec("t.obj")).unwrap();
            assert_eq!(mesh.triangles.len(), 4, "{lib}");
            // unit mm: the vertex at x = 1 mm is at 1e-3 m.
            let x_max = mesh.vertices_m.iter().fold(0.0_f64, |m, v| m.max(v[0]));
            assert_eq!(x_max, 1e-3, "{lib}");
        }
    }

    /// A binary STL of more triangles than a mesh may have is refused from its header, with
    /// the count and the fix, before its triangles are parsed.
    #[test]
    fn a_binary_stl_too_fine_to_prepare_is_refused_from_its_header() {
        let d = std::env::temp_dir().join(format!("grasp-io-fine-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let n = MAX_MESH_TRIANGLES + 1;
        let mut bytes = vec![0u8; 84 + 50 * n];
        bytes[80..84].copy_from_slice(&(n as u32).to_le_bytes());
        let stl = d.join("fine.stl");
        std::fs::write(&stl, &bytes).unwrap();
        let e = read_mesh(&stl, &spec("fine.stl")).unwrap_err();
        assert!(
            e.contains(&format!("holds {n} triangles, more than the")),
            "{e}"
        );
        assert!(e.contains("decimate"), "{e}");
        assert_eq!(binary_stl_triangles(&bytes[..84 + 50]), None);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn special_files_and_unknown_formats_are_refused() {
        let e = read_mesh(Path::new("/dev/zero.obj"), &spec("x")).unwrap_err();
        assert!(e.contains("cannot read mesh file"), "{e}");
        let d = std::env::temp_dir().join(format!("grasp-io-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let link = d.join("zero.stl");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let e = read_mesh(&link, &spec("zero.stl")).unwrap_err();
        assert!(e.contains("a device, not a regular file"), "{e}");
        let e = read_mesh(&d.join("m.ply"), &spec("m.ply")).unwrap_err();
        assert!(e.contains("unknown mesh format `.ply`"), "{e}");
    }
}
