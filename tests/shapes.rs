//! Object shapes: fingers placed on boxes, spheres, cylinders, capsules and meshes
//! get the frames and radii computed here by hand; a refined sphere mesh converges to the
//! sphere; mass properties match closed forms; every shape check is an error or warning that
//! names the finger; and a scene written with a shape solves exactly like the same grasp
//! written with explicit frames.

mod support;

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use grasp_model::icosphere;
use grasp_model::TriangleMesh;
use grasp_model::{DerivedFrame, STANDARD_GRAVITY};
use grasp_model::{GraspModel, LoadedScene, SceneError};
use serde_json::{json, Value};
use support::*;

/// A one-finger scene on `shape` with the finger placed by `place` (flat rubber pad,
/// 2 mm patch; the object's weight is irrelevant to the frame).
fn placed(shape: Value, place: Value) -> Value {
    json!({
        "object": {"weight": 1.0, "center_of_mass": [0, 0, 0], "material": "rigid", "shape": shape},
        "fingers": [{
            "name": "f", "place": place,
            "material": {"youngs_modulus": 2e6, "poisson_ratio": 0.45},
            "patch": {"size": [0.002, 0.002], "grid": [3, 3]}, "friction": {"mu": 0.5}
        }]
    })
}

fn load(v: &Value) -> Result<LoadedScene, SceneError> {
    LoadedScene::from_json_str(&v.to_string())
}

fn frame(v: &Value) -> (LoadedScene, DerivedFrame) {
    let s = load(v).unwrap_or_else(|e| panic!("{e}"));
    let d = s.shape_report().expect("shape report").fingers[0].clone();
    (s, d)
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() <= tol)
}

fn problem_paths(e: SceneError) -> Vec<String> {
    e.problems().into_iter().map(|p| p.path).collect()
}

// Exact to round-off: the primitives' geometry is closed-form (1e-12 m on 0.1 m shapes).
const EXACT: f64 = 1e-12;

#[test]
fn a_point_near_a_box_face_lands_on_the_face_with_its_inward_normal() {
    let shape = json!({"box": {"size": [0.1, 0.2, 0.3]}, "position": [1, 2, 3]});
    let (s, d) = frame(&placed(shape, json!({"point": [1.01, 2.1004, 3.02]})));
    assert!(
        close(d.contact_point_m, [1.01, 2.1, 3.02], EXACT),
        "{:?}",
        d.contact_point_m
    );
    assert!(close(d.normal, [0.0, -1.0, 0.0], EXACT));
    assert!((d.distance_m - 4e-4).abs() < EXACT);
    assert_eq!(d.object_radius_m, [None, None]);
    assert_eq!(s.fingers[0].normal, [0.0, -1.0, 0.0]);
    assert_eq!(s.fingers[0].object_radius, None);
}

#[test]
fn a_sphere_gives_its_radius_in_every_direction() {
    let r = 0.04;
    let shape = json!({"sphere": {"radius": r}, "position": [0.1, 0, 0]});
    let p = [0.1 + 0.02, 0.03, -0.01];
    let (s, d) = frame(&placed(shape, json!({"point": p, "tolerance": 0.01})));
    let dir = nalgebra::Vector3::new(0.02, 0.03, -0.01).normalize();
    let want = [0.1 + r * dir.x, r * dir.y, r * dir.z];
    assert!(close(d.contact_point_m, want, EXACT));
    assert!(close(d.normal, [-dir.x, -dir.y, -dir.z], EXACT));
    assert_eq!(d.object_radius_m, [Some(r), Some(r)]);
    assert!(
        matches!(s.fingers[0].object_radius, Some(grasp_model::RadiusSpec::Isotropic(x)) if (x - r).abs() < EXACT)
    );
}

#[test]
fn a_cylinder_side_is_curved_around_and_straight_along_its_axis() {
    // Axis along world x (z rotated onto x: 90 degrees about y).
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let shape = json!({"cylinder": {"radius": 0.02, "length": 0.2}, "quaternion": [h, 0, h, 0]});
    let (_, d) = frame(&placed(
        shape.clone(),
        json!({"ray": {"origin": [0.05, 0, -1], "direction": [0, 0, 1]}}),
    ));
    assert!(close(d.contact_point_m, [0.05, 0.0, -0.02], EXACT));
    assert!(close(d.normal, [0.0, 0.0, 1.0], EXACT));
    // t1 is the principal direction around the axis (curvature 1/R), t2 along it (flat).
    let t1 = d.tangent.unwrap();
    assert!(
        t1[0].abs() < EXACT && (t1[1].abs() - 1.0).abs() < EXACT,
        "{t1:?}"
    );
    assert_eq!(d.object_radius_m[1], None);
    assert!((d.object_radius_m[0].unwrap() - 0.02).abs() < EXACT);
    // The flat end cap (world +x face).
    let (_, d) = frame(&placed(shape, json!({"point": [0.1005, 0.003, 0.004]})));
    assert!(close(d.contact_point_m, [0.1, 0.003, 0.004], EXACT));
    assert!(close(d.normal, [-1.0, 0.0, 0.0], EXACT));
    assert_eq!(d.object_radius_m, [None, None]);
}

#[test]
fn a_capsule_is_cylindrical_between_its_caps_and_spherical_on_them() {
    let shape = json!({"capsule": {"radius": 0.01, "length": 0.05}});
    let (_, d) = frame(&placed(shape.clone(), json!({"point": [0.0105, 0, 0.01]})));
    assert!(close(d.contact_point_m, [0.01, 0.0, 0.01], EXACT));
    assert!(close(d.normal, [-1.0, 0.0, 0.0], EXACT));
    assert_eq!(d.object_radius_m[1], None);
    let (_, d) = frame(&placed(
        shape,
        json!({"ray": {"origin": [0, 0, 1], "direction": [0, 0, -1]}}),
    ));
    assert!(close(d.contact_point_m, [0.0, 0.0, 0.035], EXACT));
    assert_eq!(d.object_radius_m, [Some(0.01), Some(0.01)]);
}

#[test]
fn shape_checks_name_the_finger_and_the_fix() {
    let cube = json!({"box": {"size": [0.1, 0.1, 0.1]}});
    let off = load(&placed(cube.clone(), json!({"point": [0.0, 0.0, 0.052]}))).unwrap_err();
    assert_eq!(problem_paths(off), ["fingers[0].place.point"]);
    let edge = load(&placed(cube.clone(), json!({"point": [0.05, 0.05, 0.0]}))).unwrap_err();
    assert!(edge.to_string().contains("edge"), "{edge}");
    let miss = load(&placed(
        cube.clone(),
        json!({"ray": {"origin": [1, 1, 1], "direction": [1, 0, 0]}}),
    ))
    .unwrap_err();
    assert_eq!(problem_paths(miss), ["fingers[0].place.ray"]);
    let zero_hint = load(&placed(
        cube.clone(),
        json!({"point": [0, 0, 0.05], "tangent": [0, 0, 0]}),
    ))
    .unwrap_err();
    assert_eq!(problem_paths(zero_hint), ["fingers[0].place.tangent"]);
    let inside = load(&placed(
        cube.clone(),
        json!({"ray": {"origin": [0, 0, 0], "direction": [1, 0, 0]}}),
    ))
    .unwrap_err();
    assert!(inside.to_string().contains("inside"));
    // An explicit frame on a shaped object: the normal pointing out, the point off the face.
    let mut v = placed(cube.clone(), json!(null));
    let f = v["fingers"][0].as_object_mut().unwrap();
    f.remove("place");
    f.insert("contact_point".into(), json!([0.0, 0.0, 0.05]));
    f.insert("normal".into(), json!([0, 0, 1]));
    assert_eq!(problem_paths(load(&v).unwrap_err()), ["fingers[0].normal"]);
    v["fingers"][0]["normal"] = json!([0, 0, -1]);
    v["fingers"][0]["contact_point"] = json!([0.0, 0.0, 0.053]);
    assert_eq!(
        problem_paths(load(&v).unwrap_err()),
        ["fingers[0].contact_point"]
    );
    v["fingers"][0]["contact_point"] = json!([0.0, 0.0, 0.05]);
    assert!(load(&v).is_ok());
    // place and an explicit frame together; place or density without a shape.
    let mut both = placed(cube, json!({"point": [0, 0, 0.05]}));
    both["fingers"][0]["normal"] = json!([0, 0, -1]);
    assert_eq!(
        problem_paths(load(&both).unwrap_err()),
        ["fingers[0].normal"]
    );
    let mut no_shape = placed(json!(null), json!({"point": [0, 0, 0.05]}));
    no_shape["object"].as_object_mut().unwrap().remove("shape");
    assert_eq!(
        problem_paths(load(&no_shape).unwrap_err()),
        ["fingers[0].place"]
    );
}

#[test]
fn a_patch_over_a_box_edge_and_overlapping_patches_are_warnings() {
    let mut v = placed(
        json!({"box": {"size": [0.1, 0.1, 0.1]}}),
        json!({"point": [0.0495, 0.0, 0.05]}),
    );
    // With the exact gaps (the default with a shape) the elements past the edge face no
    // surface and carry nothing: no warning. The thesis's quadratic gap is blind to the edge.
    let s = load(&v).unwrap();
    assert!(s.shape_report().unwrap().warnings.is_empty());
    v["gap"] = json!("quadratic");
    let s = load(&v).unwrap();
    let w = &s.shape_report().unwrap().warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("finger f") && w[0].contains("0.500 mm over the edge"),
        "{w:?}"
    );
    v["fingers"][0]["place"] = json!({"point": [0.0, 0.0, 0.05]});
    let mut g = v["fingers"][0].clone();
    g["name"] = json!("g");
    g["place"] = json!({"point": [0.0015, 0.0, 0.05]});
    v["fingers"].as_array_mut().unwrap().push(g);
    let s = load(&v).unwrap();
    let w = &s.shape_report().unwrap().warnings;
    assert!(w.len() == 1 && w[0].contains("fingers f and g"), "{w:?}");
    v["fingers"][1]["place"] = json!({"point": [0.0025, 0.0, 0.05]});
    assert!(load(&v)
        .unwrap()
        .shape_report()
        .unwrap()
        .warnings
        .is_empty());
}

#[test]
fn density_gives_the_closed_form_weight_and_centroid() {
    let rho = 2700.0;
    let cases = [
        (json!({"box": {"size": [0.1, 0.2, 0.3]}}), 0.1 * 0.2 * 0.3),
        (
            json!({"sphere": {"radius": 0.05}}),
            4.0 / 3.0 * PI * 0.05f64.powi(3),
        ),
        (
            json!({"cylinder": {"radius": 0.02, "length": 0.1}}),
            PI * 0.02f64.powi(2) * 0.1,
        ),
        (
            json!({"capsule": {"radius": 0.02, "length": 0.1}}),
            PI * 0.0004 * 0.1 + 4.0 / 3.0 * PI * 0.02f64.powi(3),
        ),
    ];
    for (mut shape, volume) in cases {
        shape["position"] = json!([0.3, -0.2, 0.1]);
        let mut v = placed(
            shape,
            json!({"ray": {"origin": [0.3, -0.2, 2.0], "direction": [0, 0, -1]}}),
        );
        let o = v["object"].as_object_mut().unwrap();
        o.remove("weight");
        o.remove("center_of_mass");
        o.insert("density".into(), json!(rho));
        let s = load(&v).unwrap();
        let w = rho * volume * STANDARD_GRAVITY;
        assert!(
            (s.object.weight - w).abs() <= 1e-12 * w,
            "{} vs {w}",
            s.object.weight
        );
        assert!(close(s.object.center_of_mass, [0.3, -0.2, 0.1], EXACT));
    }
    let mut both = placed(
        json!({"sphere": {"radius": 0.05}}),
        json!({"point": [0, 0, 0.05]}),
    );
    both["object"]["density"] = json!(1000.0);
    assert_eq!(problem_paths(load(&both).unwrap_err()), ["object.weight"]);
}

fn write_obj(dir: &Path, name: &str, mesh: &TriangleMesh) -> PathBuf {
    let mut text = String::new();
    for p in &mesh.vertices_m {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in &mesh.triangles {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-shapes-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_refined_sphere_mesh_converges_to_the_sphere() {
    let (r, dir) = (0.05, temp_dir("sphere"));
    // A ray that hits inside a facet, off every vertex.
    let ray = json!({"ray": {"origin": [0.31, 0.17, 1.0], "direction": [-0.3, -0.15, -1.0]}});
    let mut errors = Vec::new();
    for k in 1..=3 {
        let file = write_obj(&dir, &format!("sphere{k}.obj"), &icosphere(r * 1000.0, k));
        let shape =
            json!({"mesh": {"file": file.file_name().unwrap().to_str().unwrap(), "unit": "mm"}});
        let v = placed(shape, ray.clone());
        let s =
            grasp_io::scene_from_json_str(&v.to_string(), &dir).unwrap_or_else(|e| panic!("{e}"));
        let d = &s.shape_report().unwrap().fingers[0];
        let p = nalgebra::Vector3::from(d.contact_point_m);
        let exact_normal = -p.normalize();
        let normal_error = (nalgebra::Vector3::from(d.normal) - exact_normal).norm();
        let radius_error = d
            .object_radius_m
            .map(|x| (x.expect("curved") - r).abs() / r)
            .iter()
            .fold(0.0_f64, |m, x| m.max(*x));
        let (vol, _) = s.shape_report().map(|r| (r.volume_m3, ())).unwrap();
        let volume_error = (vol - 4.0 / 3.0 * PI * r.powi(3)).abs() / (4.0 / 3.0 * PI * r.powi(3));
        println!("refinement {k}: radius error {radius_error:.2e}, normal error {normal_error:.2e}, volume error {volume_error:.2e}");
        errors.push((radius_error, normal_error, volume_error));
    }
    for w in errors.windows(2) {
        assert!(
            w[1].0 < w[0].0 && w[1].1 < w[0].1 && w[1].2 < w[0].2,
            "{errors:?}"
        );
    }
    // Finest mesh (1,280 triangles): radius within 2 %, normal within 0.01 rad (facets of
    // about 0.08 R; the quadric fit's error falls with the mesh size).
    assert!(errors[2].0 < 0.02 && errors[2].1 < 0.01, "{errors:?}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A cylinder as CAD programs export it: each of 64 facets one full-height strip of two long
/// triangles, so the only vertices are on the two rims, 50 mm above and below a contact at
/// mid-height, and the nearest ones reach far round the circumference. Hand-computed: radius
/// 30 mm around, flat along the axis. The fit's first estimate over the whole neighbourhood
/// is pulled low (the quadric bends to follow a half circle: about 15 mm, which the one-pass
/// fit reported); the second pass keeps the vertices within about 30 degrees of arc (here the
/// rim vertices within 17 degrees) and is within 3 % (the quadric's error over that arc), and
/// the unobservable curvature across the two rims stays zero rather than an alias of the
/// constant.
#[test]
fn a_cad_cylinder_of_long_strips_gives_its_radius() {
    let (r, h, n) = (0.03, 0.1, 64);
    let mut mesh = TriangleMesh {
        vertices_m: Vec::new(),
        triangles: Vec::new(),
    };
    for i in 0..n {
        let a = 2.0 * PI * i as f64 / n as f64;
        mesh.vertices_m.push([r * a.cos(), r * a.sin(), -h / 2.0]);
        mesh.vertices_m.push([r * a.cos(), r * a.sin(), h / 2.0]);
    }
    mesh.vertices_m.push([0.0, 0.0, -h / 2.0]);
    mesh.vertices_m.push([0.0, 0.0, h / 2.0]);
    let (bottom, top) = (2 * n as u32, 2 * n as u32 + 1);
    for i in 0..n as u32 {
        let j = (i + 1) % n as u32;
        let (b0, t0, b1, t1) = (2 * i, 2 * i + 1, 2 * j, 2 * j + 1);
        mesh.triangles
            .extend([[b0, b1, t1], [b0, t1, t0], [bottom, b1, b0], [top, t0, t1]]);
    }
    let dir = temp_dir("cad-cylinder");
    let file = write_obj(&dir, "cylinder.obj", &mesh);
    // Onto a rim column (the worst case: the nearest vertices 50 mm away) and mid-facet.
    for y in [0.0, 0.0014] {
        let shape =
            json!({"mesh": {"file": file.file_name().unwrap().to_str().unwrap(), "unit": "m"}});
        let ray = json!({"ray": {"origin": [0.2, y, 0.0], "direction": [-1, 0, 0]}});
        let s = grasp_io::scene_from_json_str(&placed(shape, ray).to_string(), &dir)
            .unwrap_or_else(|e| panic!("{e}"));
        let d = &s.shape_report().unwrap().fingers[0];
        let radii = d.object_radius_m;
        let curved: Vec<f64> = radii.iter().flatten().copied().collect();
        println!("CAD cylinder at y = {y}: radii {radii:?}");
        assert_eq!(curved.len(), 1, "one curved direction: {radii:?}");
        assert!(
            (curved[0] - r).abs() < 0.03 * r,
            "radius {:?} at y = {y}",
            radii
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_cube_mesh_has_the_exact_volume_and_centroid_and_an_stl_reads_the_same() {
    let dir = temp_dir("cube");
    // The unit cube [0, 1]^3: the library's box mesh, moved.
    let mut cube = grasp_model::box_mesh([0.5; 3]);
    for c in &mut cube.vertices_m {
        *c = c.map(|x| x + 0.5);
    }
    let v = cube.vertices_m.clone();
    let obj = write_obj(&dir, "cube.obj", &cube);
    let spec = grasp_model::MeshSpec {
        file: "cube.obj".into(),
        scale: 0.1,
        unit: Default::default(),
    };
    let mesh = grasp_io::read_mesh(&obj, &spec).unwrap();
    let (vol, c) = mesh.volume_and_centroid();
    assert!(
        (vol - 1e-3).abs() < 1e-15 && (c - nalgebra::Vector3::repeat(0.05)).norm() < 1e-15,
        "{vol} {c}"
    );
    // The same cube as binary STL (stl_io writes it; our reader reads it back).
    let tris: Vec<stl_io::Triangle> = cube
        .triangles
        .iter()
        .map(|t| stl_io::Triangle {
            normal: stl_io::Normal::new([0.0; 3]),
            vertices: t.map(|i| stl_io::Vertex::new(v[i as usize].map(|x| x as f32))),
        })
        .collect();
    let stl = dir.join("cube.stl");
    stl_io::write_stl(&mut std::fs::File::create(&stl).unwrap(), tris.iter()).unwrap();
    let from_stl = grasp_io::read_mesh(&stl, &spec).unwrap();
    assert!((from_stl.volume_and_centroid().0 - 1e-3).abs() < 1e-15);
    std::fs::remove_dir_all(&dir).ok();
}

/// `example` rewritten with `shape` and each finger placed at its own contact point (nudged
/// 0.3 mm into the object, to be projected back) with its explicit frame's tangent as hint.
fn with_shape(example: &str, shape: Value) -> (Value, Value) {
    let explicit = example_json(example);
    let mut v = explicit.clone();
    v["object"]["shape"] = shape;
    let planar = v.get("planar").is_some_and(|p| !p.is_null());
    for f in v["fingers"].as_array_mut().unwrap() {
        let f = f.as_object_mut().unwrap();
        let p: [f64; 3] = serde_json::from_value(f.remove("contact_point").unwrap()).unwrap();
        let n: [f64; 3] = serde_json::from_value(f.remove("normal").unwrap()).unwrap();
        f.remove("object_radius");
        let scene = grasp_model::ContactFrame::new(p.into(), n.into(), None, None);
        let nudged = [0, 1, 2].map(|i| p[i] + 3e-4 * n[i]);
        let mut place = json!({"point": nudged});
        if !planar {
            place["tangent"] = json!([scene.t1.x, scene.t1.y, scene.t1.z]);
        }
        f.insert("place".into(), place);
    }
    (explicit, v)
}

fn same_forces(explicit: &Value, shaped: &Value) {
    let a = solved(explicit);
    // The frames and radii the shape derives, in the thesis's quadratic gap that the explicit
    // frames use (the exact gaps are checked in tests/exact_gaps.rs).
    let mut shaped = shaped.clone();
    shaped["gap"] = json!("quadratic");
    let model = GraspModel::from_loaded(&load(&shaped).unwrap()).unwrap();
    let b = grasp_model::solve(&model).unwrap();
    assert_eq!(a.status, b.status);
    let d = element_force_difference_n(&a, &b);
    // The derived frames equal the written ones to round-off: forces to 1e-9 of the load.
    assert!(d <= 1e-9 * a.load_scale_n, "{d:e}");
}

#[test]
fn a_scene_written_with_a_shape_solves_like_its_explicit_frames() {
    // Cube A on a box; the pipe (planar, curved across its axis) on a cylinder along x.
    let (explicit, shaped) = with_shape(
        "cube_a.json",
        json!({"box": {"size": [0.1, 0.1, 0.1]}, "position": [0.05, 0.05, 0.05]}),
    );
    same_forces(&explicit, &shaped);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let pipe = json!({"cylinder": {"radius": 0.01, "length": 0.4}, "position": [0.1, 0, 0], "quaternion": [h, 0, h, 0]});
    let (explicit, shaped) = with_shape("pipe_three_fingers.json", pipe);
    let s = load(&shaped).unwrap();
    for f in &s.shape_report().unwrap().fingers {
        assert_eq!(f.object_radius_m[0], None, "{f:?}");
        assert!(
            (f.object_radius_m[1].unwrap() - 0.01).abs() < EXACT,
            "{f:?}"
        );
    }
    same_forces(&explicit, &shaped);
}

// ---------------------------------------------------------------------------------------
// Mesh geometry: flat faces give their exact normal, the curvature fit
// does not blur across sharp edges, contacts on sharp edges are refused and patches over
// them warned of as on the primitives, open meshes refuse a density and are warned of.

#[path = "shapes/meshes.rs"]
mod meshes;
use meshes::*;

/// `v` loaded with its mesh given in memory (metres; the file name is not read).
fn load_with_mesh(v: &Value, mesh: &TriangleMesh) -> Result<LoadedScene, SceneError> {
    LoadedScene::from_json_str_with_meshes(&v.to_string(), &|_| Ok(mesh.clone()))
}

/// The pose used for the box comparisons: off the origin and turned about a skew axis, so
/// no face normal is a world axis.
fn pose() -> (Value, Value) {
    (json!([0.1, -0.2, 0.3]), json!([0.9, 0.1, -0.3, 0.2]))
}

fn posed(mut shape: Value) -> Value {
    let (p, q) = pose();
    shape["position"] = p;
    shape["quaternion"] = q;
    shape
}

/// World point of the local point `x` under [`pose`].
fn world(x: [f64; 3]) -> [f64; 3] {
    let q =
        nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(0.9, 0.1, -0.3, 0.2));
    let w = nalgebra::Vector3::new(0.1, -0.2, 0.3) + q.transform_vector(&x.into());
    [w.x, w.y, w.z]
}

/// World direction of the local direction `d` under [`pose`].
fn world_dir(d: [f64; 3]) -> [f64; 3] {
    let (o, w) = (world([0.0; 3]), world(d));
    [0, 1, 2].map(|k| w[k] - o[k])
}

const HALF: [f64; 3] = [0.03, 0.02, 0.05];

fn box_meshes() -> Vec<(&'static str, TriangleMesh)> {
    vec![
        ("12 triangles", uniform_box(HALF, 1, BoxCut::Grid)),
        ("1,200 triangles", uniform_box(HALF, 10, BoxCut::Grid)),
        ("fans", uniform_box(HALF, 3, BoxCut::Fan)),
        ("slivers", sliver_box(HALF)),
    ]
}

/// Local points on the face `+-e_k` of the box [`HALF`] (`s` the sign): its centre, 0.4 mm
/// from an edge, 0.4 mm from a corner, and an off-centre point.
fn face_points(k: usize, s: f64) -> Vec<[f64; 3]> {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    [
        (0.0, 0.0),
        (HALF[i] - 4e-4, 0.0),
        (HALF[i] - 4e-4, -(HALF[j] - 4e-4)),
        (0.37 * HALF[i], 0.61 * HALF[j]),
    ]
    .iter()
    .map(|&(u, v)| {
        let mut p = [0.0; 3];
        p[k] = s * HALF[k];
        p[i] = u;
        p[j] = v;
        p
    })
    .collect()
}

/// On every face of boxes tessellated as grids (12 and 1,200 triangles), fans and slivers,
/// posed off the origin: a finger placed 0.2 mm off the face at its centre, near an edge,
/// near a corner and off-centre gets the primitive box's frame to round-off (1e-12; the
/// primitive's is closed form: the face normal, checked against `R e_k` here too), flat in
/// both directions, and the same patch-over-the-edge warnings. Before, the quadric fit over
/// the nearest vertices gave up to 74 degrees off near an edge or corner of the 12-triangle
/// box, 51 degrees with 1,200 triangles, 85 with fans and 90 with slivers.
#[test]
fn mesh_boxes_give_the_exact_face_normal_at_centres_near_edges_and_corners() {
    let primitive = posed(json!({"box": {"size": HALF.map(|h| 2.0 * h)}}));
    let mesh_shape = posed(json!({"mesh": {"file": "box.obj"}}));
    for (name, mesh) in box_meshes() {
        for k in 0..3 {
            for s in [-1.0, 1.0] {
                let mut n = [0.0; 3];
                n[k] = s;
                let (o, w) = (world([0.0; 3]), world(n));
                let inward = [0, 1, 2].map(|c| o[c] - w[c]);
                for p in face_points(k, s) {
                    let off = world([0, 1, 2].map(|c| p[c] + 2e-4 * n[c]));
                    let place = json!({"point": off, "tangent": [0.3, -0.5, 0.8]});
                    let exact = load(&placed(primitive.clone(), place.clone())).unwrap();
                    let exact_report = exact.shape_report().unwrap();
                    let e = &exact_report.fingers[0];
                    let s_mesh = load_with_mesh(&placed(mesh_shape.clone(), place), &mesh)
                        .unwrap_or_else(|e| panic!("{name}: {e}"));
                    let report = s_mesh.shape_report().unwrap();
                    let d = &report.fingers[0];
                    assert!(close(e.normal, inward, EXACT), "{:?}", e.normal);
                    assert!(
                        close(d.normal, e.normal, EXACT),
                        "{name} at {p:?}: {:?}",
                        d.normal
                    );
                    assert!(
                        close(d.contact_point_m, e.contact_point_m, EXACT),
                        "{name} at {p:?}"
                    );
                    assert!(
                        close(d.tangent.unwrap(), e.tangent.unwrap(), EXACT),
                        "{name}"
                    );
                    assert_eq!(d.curvature_per_m, [0.0, 0.0], "{name} at {p:?}");
                    assert_eq!(d.object_radius_m, [None, None], "{name} at {p:?}");
                    assert_eq!(report.warnings, exact_report.warnings, "{name} at {p:?}");
                }
            }
        }
    }
}

/// Each box mesh and the primitive box, posed, refuse the same contacts (`fingers[0].place`,
/// "an edge" or "a corner"): a point on a sharp edge, one off the box in the wedge beside an
/// edge (it projects onto the edge), one on a tessellation vertex in the middle of an edge,
/// a corner and a point beyond it, and a ray aimed straight at an edge.
#[test]
fn contacts_on_a_sharp_mesh_edge_or_corner_are_refused_as_on_the_box() {
    let primitive = posed(json!({"box": {"size": HALF.map(|h| 2.0 * h)}}));
    let mesh_shape = posed(json!({"mesh": {"file": "box.obj"}}));
    let [a, b, c] = HALF;
    let dir = world_dir;
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let cases = [
        ("an edge", json!({"point": world([a, b, 0.013])})),
        (
            "an edge",
            json!({"point": world([a + 3e-4, b + 2e-4, -0.021])}),
        ),
        ("an edge", json!({"point": world([a, -b, 0.0])})),
        ("a corner", json!({"point": world([-a, b, -c])})),
        (
            "a corner",
            json!({"point": world([a + 1e-4, -b - 1e-4, c + 1e-4])}),
        ),
        (
            "an edge",
            json!({"ray": {"origin": world([a + 0.05 * s2, b + 0.05 * s2, 0.007]), "direction": dir([-1.0, -1.0, 0.0])}}),
        ),
    ];
    for (what, place) in cases {
        let e = load(&placed(primitive.clone(), place.clone())).unwrap_err();
        assert!(e.to_string().contains(&format!("lands on {what}")), "{e}");
        assert_eq!(problem_paths(e), ["fingers[0].place"]);
        for (name, mesh) in box_meshes() {
            let e = load_with_mesh(&placed(mesh_shape.clone(), place.clone()), &mesh).unwrap_err();
            assert!(
                e.to_string().contains(&format!("lands on {what}")),
                "{name}, {place}: {e}"
            );
            assert_eq!(problem_paths(e), ["fingers[0].place"], "{name}");
        }
    }
}

/// A pinch of the box near its top edge (each 10 mm pad 3 mm from the edge, hanging 2 mm
/// over it) solves on every mesh box exactly as on the primitive box: element forces within
/// 1e-9 of the load (the exact gaps' rays meet the mesh's faces as the box's, and miss past
/// the edge alike), the same warnings. Before, the normals 20-90 degrees off made the
/// friction needed to hold 31 % to 5.5 times too high.
#[test]
fn a_pinch_near_the_edge_of_a_mesh_box_solves_as_on_the_primitive_box() {
    let pinch = |shape: Value| {
        let mut v = example_json("box_pinch.json");
        v["object"]["shape"] = shape;
        for (f, side) in v["fingers"]
            .as_array_mut()
            .unwrap()
            .iter_mut()
            .zip([1.0, -1.0])
        {
            let origin = world([0.0, 0.2 * side, HALF[2] - 3e-3]);
            let direction = world_dir([0.0, -side, 0.0]);
            f["place"] = json!({"ray": {"origin": origin, "direction": direction}, "tangent": world_dir([1.0, 0.0, 0.0])});
        }
        v
    };
    let primitive = pinch(posed(json!({"box": {"size": HALF.map(|h| 2.0 * h)}})));
    let exact = solved(&primitive);
    // Exact gaps: the elements past the edge face no surface, on the mesh as on the box.
    assert!(exact.warnings.is_empty(), "{:?}", exact.warnings);
    assert!(exact.fingers.iter().all(|f| f.off_surface_count > 0));
    for (name, mesh) in box_meshes() {
        let scene = load_with_mesh(&pinch(posed(json!({"mesh": {"file": "box.obj"}}))), &mesh)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let sol = grasp_model::solve(&GraspModel::from_loaded(&scene).unwrap()).unwrap();
        assert_eq!(sol.status, exact.status, "{name}");
        let d = element_force_difference_n(&exact, &sol);
        assert!(d <= 1e-9 * exact.load_scale_n, "{name}: {d:e}");
        assert_eq!(sol.warnings, exact.warnings, "{name}");
    }
}

/// The angle between two unit vectors, rad.
fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (a, b) = (nalgebra::Vector3::from(a), nalgebra::Vector3::from(b));
    a.cross(&b).norm().atan2(a.dot(&b))
}

/// Tessellated cylinders (radius 20 mm, 60 mm long; 48 segments with 12 rings and fan caps,
/// 24 with 6, and the CAD cut: 64 full-height strips with caps fanned from one rim vertex):
/// on the caps, at the centre and 0.5 mm inside the rim, the exact normal to round-off and
/// no curvature; on the side, at mid-height and 1 mm and 0.3 mm from a rim, the normal
/// within a twentieth of the facet angle of the cylinder's (the radial direction through the
/// point; the facet's own normal errs by up to half the facet angle), the radius around
/// within the facet angle (relative) and flat along the axis: the fit takes no vertex of the
/// caps; a patch reaching over the rim is warned of (with the quadratic gap). On the rim, or beyond it, the contact is
/// refused as on the primitive cylinder.
#[test]
fn tessellated_cylinders_have_flat_caps_and_a_side_fitted_apart_from_its_rims() {
    let (r, h) = (0.02, 0.03);
    let meshes = [
        (
            "48 segments",
            48,
            cylinder_mesh(r, h, 48, 12, CapCut::Centre),
        ),
        (
            "24 segments",
            24,
            cylinder_mesh(r, h, 24, 6, CapCut::Centre),
        ),
        ("64 strips", 64, cylinder_mesh(r, h, 64, 1, CapCut::Rim)),
    ];
    let shape = posed(json!({"mesh": {"file": "cylinder.obj"}}));
    let primitive = posed(json!({"cylinder": {"radius": r, "length": 2.0 * h}}));
    let o = world([0.0; 3]);
    let axis = world_dir([0.0, 0.0, 1.0]);
    for (name, n, mesh) in meshes {
        let facet = 2.0 * PI / n as f64;
        let frame_at = |local: [f64; 3]| {
            let mut v = placed(
                shape.clone(),
                json!({"point": world(local), "tolerance": 0.003}),
            );
            // The quadratic gap: the over-the-rim warning is the thesis gap's.
            v["gap"] = json!("quadratic");
            let s =
                load_with_mesh(&v, &mesh).unwrap_or_else(|e| panic!("{name} at {local:?}: {e}"));
            s.shape_report().unwrap().clone()
        };
        for (x, y, z) in [
            (0.0, 0.0, h + 2e-4),
            (0.0195 * 0.8, 0.0195 * 0.6, -h - 2e-4),
        ] {
            let report = frame_at([x, y, z]);
            let d = &report.fingers[0];
            let inward = axis.map(|c| -z.signum() * c);
            assert!(close(d.normal, inward, EXACT), "{name} cap: {:?}", d.normal);
            assert_eq!(d.curvature_per_m, [0.0, 0.0], "{name}");
            if x != 0.0 {
                assert!(
                    report.warnings.iter().any(|w| w.contains("over the edge")),
                    "{name}"
                );
            }
        }
        for (a, z) in [
            (0.37, 0.0),
            (1.0, h - 1e-3),
            (2.0, h - 3e-4),
            (4.0, 3e-4 - h),
        ] {
            let report = frame_at([1.01 * r * f64::cos(a), 1.01 * r * f64::sin(a), z]);
            let d = &report.fingers[0];
            let p = d.contact_point_m;
            let radial_world = [0, 1, 2].map(|k| p[k] - o[k]);
            let along = radial_world
                .iter()
                .zip(&axis)
                .map(|(p, a)| p * a)
                .sum::<f64>();
            let exact = [0, 1, 2].map(|k| -(radial_world[k] - along * axis[k]));
            let err = angle(d.normal, exact);
            assert!(
                err <= facet / 20.0,
                "{name} at a = {a}, z = {z}: {err:.2e} rad"
            );
            // The 2 mm patch 0.3 mm from a rim hangs over it; at mid-height it does not.
            let over = report.warnings.iter().any(|w| w.contains("over the edge"));
            assert!(
                over == (h - z.abs() < 5e-4) || z.abs() == h - 1e-3,
                "{name} at z = {z}"
            );
            let curved: Vec<f64> = d.object_radius_m.iter().flatten().copied().collect();
            assert_eq!(
                curved.len(),
                1,
                "{name} at z = {z}: {:?}",
                d.object_radius_m
            );
            assert!(
                (curved[0] - r).abs() <= facet * r,
                "{name} at z = {z}: {curved:?}"
            );
            // Flat along the axis: no curvature from the caps' vertices (0.01 / R: a radius
            // of 100 R, treated as flat).
            assert!(
                d.curvature_per_m[1].abs() <= 0.01 / r,
                "{name}: {:?}",
                d.curvature_per_m
            );
        }
        for place in [
            json!({"point": world([r, 0.0, h])}),
            json!({"point": world([0.0, -r - 2e-4, -h - 2e-4])}),
        ] {
            let e = load(&placed(primitive.clone(), place.clone())).unwrap_err();
            assert!(e.to_string().contains("lands on an edge"), "{e}");
            let e = load_with_mesh(&placed(shape.clone(), place), &mesh).unwrap_err();
            assert!(e.to_string().contains("lands on an edge"), "{name}: {e}");
        }
    }
}

/// Spheres of radius 40 mm as a latitude-longitude mesh (48 x 24) and an icosphere (1,280
/// triangles): one smooth region without edges; at points all round, the normal within a
/// twentieth of the facet angle of the radial direction (closed form) and both radii within
/// the facet angle (relative); no warnings.
#[test]
fn sphere_meshes_give_the_radial_normal_and_their_radius() {
    let r = 0.04;
    let meshes = [
        ("48 x 24", 2.0 * PI / 48.0, uv_sphere(r, 48, 24)),
        ("icosphere", 0.06, icosphere(r, 3)),
    ];
    for (name, facet, mesh) in meshes {
        for dir in [
            [0.3, -0.2, 0.9],
            [1.0, 0.01, 0.02],
            [-0.5, 0.5, -0.7],
            [0.0, 0.001, -1.0],
        ] {
            let u = nalgebra::Vector3::from(dir).normalize();
            let p = u * 1.02 * r;
            let v = placed(
                json!({"mesh": {"file": "sphere.obj"}}),
                json!({"point": [p.x, p.y, p.z], "tolerance": 0.002}),
            );
            let s = load_with_mesh(&v, &mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
            let report = s.shape_report().unwrap();
            let d = &report.fingers[0];
            let c = nalgebra::Vector3::from(d.contact_point_m).normalize();
            let err = angle(d.normal, [-c.x, -c.y, -c.z]);
            assert!(err <= facet / 20.0, "{name} along {dir:?}: {err:.2e} rad");
            for radius in d.object_radius_m {
                let radius = radius.expect("curved");
                assert!((radius - r).abs() <= facet * r, "{name}: {radius}");
            }
            assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        }
    }
}

/// Meshes that do not bound a solid: a box without its top, one triangle, a box whose top is
/// 1 um off its sides (a crack), and a tube without caps. A density is refused
/// (`object.density`, naming the open edges and the fix); with a weight the scene loads,
/// warns that the mesh is not closed, and every solve carries the warning. The frame on a
/// face of such a mesh is still its face's, exactly; a ray that meets the back of a face
/// (into the box through its missing top, up onto the triangle, from inside the cracked box,
/// out from the tube's axis) is refused.
#[test]
fn open_meshes_refuse_a_density_and_are_warned_of() {
    let boxed = uniform_box(HALF, 1, BoxCut::Grid);
    let up = (
        json!({"ray": {"origin": [0.001, 0.002, -1.0], "direction": [0, 0, 1]}}),
        1.0,
    );
    let down = (
        json!({"ray": {"origin": [0.001, 0.002, 1.0], "direction": [0, 0, -1]}}),
        -1.0,
    );
    let cases = [
        (
            "a box without its top",
            without(&boxed, |c| c.iter().all(|p| p[2] == HALF[2])),
            4,
            &up,
            &down,
        ),
        ("one triangle", single_triangle(), 3, &down, &up),
        // From inside (it has no inside to refuse a start in) up to the top.
        (
            "a cracked box",
            cracked_box(HALF, 1e-6),
            8,
            &up,
            &(
                json!({"ray": {"origin": [0.001, 0.002, 0.0], "direction": [0, 0, 1]}}),
                0.0,
            ),
        ),
        (
            "a tube",
            without(&cylinder_mesh(0.02, 0.03, 24, 2, CapCut::Centre), |c| {
                c.iter().all(|p| p[2] == c[0][2])
            }),
            48,
            &(
                json!({"ray": {"origin": [1.0, 0.0, 0.001], "direction": [-1, 0, 0]}}),
                0.0,
            ),
            &(
                json!({"ray": {"origin": [0.0, 0.0, 0.001], "direction": [-1, 0, 0]}}),
                0.0,
            ),
        ),
    ];
    for (name, mesh, open_edges, (front, nz), (back, _)) in cases {
        let mut v = placed(json!({"mesh": {"file": "open.obj"}}), front.clone());
        let o = v["object"].as_object_mut().unwrap();
        o.remove("weight");
        o.remove("center_of_mass");
        o.insert("density".into(), json!(1000.0));
        let e = load_with_mesh(&v, &mesh).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("needs a closed mesh")
                && text.contains(&format!("{open_edges} edges with one triangle only"))
                && text.contains("give object.weight"),
            "{name}: {text}"
        );
        assert_eq!(problem_paths(e), ["object.density"], "{name}");
        let o = v["object"].as_object_mut().unwrap();
        o.remove("density");
        o.insert("weight".into(), json!(1.0));
        o.insert("center_of_mass".into(), json!([0, 0, 0]));
        let s = load_with_mesh(&v, &mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
        let report = s.shape_report().unwrap();
        assert_eq!(report.warnings.len(), 1, "{name}: {:?}", report.warnings);
        assert!(
            report.warnings[0].contains("the mesh is not closed"),
            "{name}"
        );
        if *nz != 0.0 {
            let n = report.fingers[0].normal;
            assert!(close(n, [0.0, 0.0, *nz], EXACT), "{name}: {n:?}");
        }
        let sol = grasp_model::solve(&GraspModel::from_loaded(&s).unwrap()).unwrap();
        assert_eq!(sol.warnings[0], report.warnings[0], "{name}");
        v["fingers"][0]["place"] = back.clone();
        let e = load_with_mesh(&v, &mesh).unwrap_err();
        assert!(
            e.to_string().contains("meets the back of the mesh"),
            "{name}: {e}"
        );
        assert_eq!(problem_paths(e), ["fingers[0].place.ray"], "{name}");
    }
}

/// A box written inside out, or with every other triangle turned over, is the same box:
/// closed, the density gives the exact weight, and the frames are the box's.
#[test]
fn a_mesh_wound_inward_or_inconsistently_is_wound_outward() {
    let boxed = uniform_box(HALF, 3, BoxCut::Grid);
    for (name, mesh) in [
        ("turned over", turned_over(&boxed)),
        ("scrambled", scrambled(&boxed)),
    ] {
        let place = json!({"point": [0.01, -0.005, HALF[2] + 1e-4]});
        let mut v = placed(json!({"mesh": {"file": "box.obj"}}), place);
        let o = v["object"].as_object_mut().unwrap();
        o.remove("weight");
        o.remove("center_of_mass");
        o.insert("density".into(), json!(1000.0));
        let s = load_with_mesh(&v, &mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
        let volume = 8.0 * HALF[0] * HALF[1] * HALF[2];
        let w = 1000.0 * volume * STANDARD_GRAVITY;
        assert!(
            (s.object.weight - w).abs() <= 1e-12 * w,
            "{name}: {}",
            s.object.weight
        );
        let report = s.shape_report().unwrap();
        assert!(report.warnings.is_empty(), "{name}: {:?}", report.warnings);
        assert!(
            close(report.fingers[0].normal, [0.0, 0.0, -1.0], EXACT),
            "{name}"
        );
    }
}

/// The scene's warnings reach the solution (`Solution.warnings`, the CLI's JSON, Python,
/// batch lines): a patch over a box's edge and two overlapping patches, first, whatever the
/// outcome; the solve's own follow.
#[test]
fn a_solution_carries_the_scenes_warnings() {
    let mut v = placed(
        json!({"box": {"size": [0.1, 0.1, 0.1]}}),
        json!({"point": [0.0495, 0.0, 0.05]}),
    );
    let mut g = v["fingers"][0].clone();
    g["name"] = json!("g");
    g["place"] = json!({"point": [0.0492, 0.0005, 0.05]});
    v["fingers"].as_array_mut().unwrap().push(g);
    // The quadratic gap, to keep the over-the-edge warnings.
    v["gap"] = json!("quadratic");
    let scene = load(&v).unwrap();
    let expected = scene.shape_report().unwrap().warnings.clone();
    assert_eq!(expected.len(), 3, "{expected:?}");
    // One side only: the fingers cannot hold the 1 N weight (no equilibrium), and the
    // warnings are still there.
    let sol = grasp_model::solve(&GraspModel::from_loaded(&scene).unwrap()).unwrap();
    assert!(!sol.status.has_forces(), "{:?}", sol.status);
    assert_eq!(sol.warnings[..3], expected[..], "{:?}", sol.warnings);
}

/// A plain scene (the file format alone: a scene read, its geometry dropped, or one built in
/// code) is loaded from its own data: its shapes posed from their specs, its warnings found
/// again, so its model and solution are the read scene's, bit for bit; the model draws the
/// same triangles.
#[test]
fn a_plain_scene_solves_as_the_scene_read() {
    for name in [
        "box_pinch.json",
        "sphere_three_fingers.json",
        "edge_pinch.json",
    ] {
        let read = example_scene(name);
        let plain = LoadedScene::of_plain(read.scene.clone()).unwrap();
        let a = GraspModel::from_loaded(&read).unwrap();
        let b = GraspModel::from_scene(&read.scene).unwrap();
        assert_eq!(a.object_surface(), b.object_surface(), "{name}");
        assert_eq!(
            a.object_surface(),
            read.geometry.surface.as_deref(),
            "{name}"
        );
        assert_eq!(
            plain.geometry.warnings(),
            read.geometry.warnings(),
            "{name}"
        );
        let (sa, sb) = (
            grasp_model::solve(&a).unwrap(),
            grasp_model::solve(&b).unwrap(),
        );
        assert_eq!(sa.warnings, sb.warnings, "{name}");
        assert_eq!(
            element_force_components(&sa),
            element_force_components(&sb),
            "{name}"
        );
    }
}

/// A box as an STL file stores it: turned about a skew axis, then every coordinate rounded
/// to single precision (6e-8 relative). Its faces are still flat regions (within 1e-6 of
/// their size of a plane): each contact gets the face's normal to within 1e-6 rad of the
/// turned box's exact one (the file's own precision), no curvature, and no edge in a face.
#[test]
fn a_box_stored_in_single_precision_still_has_flat_faces() {
    let exact = uniform_box(HALF, 4, BoxCut::Grid);
    let rounded = TriangleMesh {
        vertices_m: exact
            .vertices_m
            .iter()
            .map(|&p| world(p).map(|x| f64::from(x as f32)))
            .collect(),
        triangles: exact.triangles.clone(),
    };
    for k in 0..3 {
        for s in [-1.0, 1.0] {
            let mut n = [0.0; 3];
            n[k] = s;
            let inward = world_dir(n).map(|x| -x);
            for p in face_points(k, s) {
                let off = world([0, 1, 2].map(|c| p[c] + 2e-4 * n[c]));
                let v = placed(json!({"mesh": {"file": "box.stl"}}), json!({"point": off}));
                let scene = load_with_mesh(&v, &rounded).unwrap_or_else(|e| panic!("{p:?}: {e}"));
                let d = &scene.shape_report().unwrap().fingers[0];
                assert!(angle(d.normal, inward) <= 1e-6, "{p:?}: {:?}", d.normal);
                assert_eq!(d.curvature_per_m, [0.0, 0.0], "{p:?}");
            }
        }
    }
}

/// A ray aimed at an edge or a corner of the box (posed off the origin) is refused alike by
/// the primitive and by every tessellation of it: "lands on an edge" / "a corner", where
/// the normal is not defined (the mesh box once accepted the ray with a warning).
#[test]
fn rays_onto_a_mesh_boxs_edge_or_corner_are_refused_as_on_the_primitive() {
    let primitive = posed(json!({"box": {"size": HALF.map(|h| 2.0 * h)}}));
    let mesh_shape = posed(json!({"mesh": {"file": "box.obj"}}));
    let targets = [
        ([HALF[0], HALF[1], 0.013], [-1.0, -1.0, 0.0], "an edge"),
        ([-HALF[0], 0.007, HALF[2]], [1.0, 0.0, -1.0], "an edge"),
        (HALF, [-1.0, -1.0, -1.0], "a corner"),
    ];
    for (target, dir, what) in targets {
        let origin = world([0, 1, 2].map(|k| target[k] - 0.01 * dir[k]));
        let place = json!({"ray": {"origin": origin, "direction": world_dir(dir)}});
        let expected = format!("lands on {what}");
        let e = load(&placed(primitive.clone(), place.clone())).unwrap_err();
        assert!(e.to_string().contains(&expected), "primitive: {e}");
        for (name, mesh) in box_meshes() {
            let e =
                load_with_mesh(&placed(mesh_shape.clone(), place.clone()), &mesh).expect_err(name);
            assert!(e.to_string().contains(&expected), "{name}: {e}");
        }
    }
}
