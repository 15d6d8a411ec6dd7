//! # grasp-mesh-io: the files a scene names
//!
//! The contact model does no I/O; a scene whose `object.shape` is a mesh names an OBJ or STL
//! file, read here (OBJ with `tobj`, triangulated; STL, binary or ASCII, with `stl_io`) and
//! scaled to metres. [`scene_from_json_str`] loads a scene with its mesh paths resolved
//! against a folder (the scene file's own).

use std::path::{Path, PathBuf};

use grasp_model::geometry::mesh_surface::TriangleMesh;
use grasp_model::geometry::shape::MeshSpec;
use grasp_model::{Scene, SceneError};

/// Largest mesh file read, bytes.
pub const MAX_MESH_BYTES: u64 = 256 << 20;

/// A scene from JSON text, its mesh files read relative to `base_dir`.
pub fn scene_from_json_str(text: &str, base_dir: &Path) -> Result<Scene, SceneError> {
    Scene::from_json_str_with_meshes(text, &|m: &MeshSpec| read_mesh(&base_dir.join(&m.file), m))
}

/// The mesh of `spec` from the file at `path`, in metres (`unit`, then `scale`).
pub fn read_mesh(path: &Path, spec: &MeshSpec) -> Result<TriangleMesh, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if !meta.is_file() {
        return Err(format!("{} is not a file", path.display()));
    }
    if meta.len() > MAX_MESH_BYTES {
        return Err(format!(
            "{} has {} MiB, over the limit of {} MiB",
            path.display(),
            meta.len() >> 20,
            MAX_MESH_BYTES >> 20
        ));
    }
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let mut mesh = match ext.as_str() {
        "obj" => read_obj(path)?,
        "stl" => read_stl(path)?,
        other => {
            return Err(format!(
                "{}: unknown mesh format `.{other}`; give an .obj or .stl file",
                path.display()
            ))
        }
    };
    let factor = spec.unit.metres() * spec.scale;
    for v in &mut mesh.vertices_m {
        *v = v.map(|x| x * factor);
    }
    if mesh.triangles.is_empty() {
        return Err(format!("{} holds no triangles", path.display()));
    }
    Ok(mesh)
}

fn read_obj(path: &Path) -> Result<TriangleMesh, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) =
        tobj::load_obj(path, &options).map_err(|e| format!("{}: {e}", path.display()))?;
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

fn read_stl(path: &Path) -> Result<TriangleMesh, String> {
    let mut file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let stl = stl_io::read_stl(&mut file)
        .map_err(|e| format!("{}: not a readable STL file: {e}", path.display()))?;
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

/// The folder a scene file's relative mesh paths start from.
pub fn base_dir_of(scene_path: &Path) -> PathBuf {
    scene_path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}
