//! Gel images read from solved grasps: the height map against the indenter's profile inside
//! the contact (compatibility) and Boussinesq's closed form outside it (Johnson eq. 3.42),
//! converging under refinement; the FFT (lattice) and dense read-outs against each other;
//! the normals and colours against the sphere's own normals under Lambert's law; a lookup
//! table against the lights it tabulates; and the refusals.

mod support;
use support::*;

use grasp_model::closed_form::HertzSphere;
use grasp_model::{
    default_lights, sensor_readings, solve, GelImage, GraspModel, HeightPath, Solution,
};
use serde_json::{json, Value};

const E_GEL: f64 = 1e6;
const NU_GEL: f64 = 0.45;
const R_SPHERE: f64 = 0.01;
const LOAD: f64 = 0.1;

/// The gel's Hertz contact with a rigid sphere (`E* = E / (1 - nu^2)`, the gel alone).
fn gel_hertz() -> HertzSphere {
    HertzSphere::new(LOAD, R_SPHERE, E_GEL / (1.0 - NU_GEL * NU_GEL))
}

/// A rigid sphere (radius 10 mm, 0.1 N) pressed on a flat frictionless gel pad (E 1 MPa, nu
/// 0.45: examples/hertz_markers.json) of `n x n` elements over 2.45 a, with the gel image
/// `gel`.
fn sphere_on_gel(n: usize, gel: Value) -> Value {
    let side = 2.45 * gel_hertz().contact_radius_m;
    json!({
        "object": {"weight": LOAD, "center_of_mass": [0, 0, 0.02], "gravity": [0, 0, -1],
                   "material": "rigid"},
        "fingers": [{
            "name": "pad", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
            "material": {"youngs_modulus": E_GEL, "poisson_ratio": NU_GEL},
            "tip_radius": null, "object_radius": R_SPHERE,
            "patch": {"size": [side, side], "grid": [n, n]},
            "friction": {"mu": 0.0}, "control": "held",
            "sensor": {"gel": gel}
        }],
        "model": "energy"
    })
}

/// An image on the element lattice of an `n x n` patch of side `side`: `m x m` pixels of
/// the elements' size (`m - n` even, so that the pixels fall on element centres).
fn lattice_gel(n: usize, m: usize, side: f64) -> Value {
    let h = side / n as f64;
    json!({"image_px": [m, m], "field_of_view_m": [m as f64 * h, m as f64 * h]})
}

/// Solves `v` and reads its first finger's gel image.
fn read(v: &Value) -> (GraspModel, Solution, GelImage) {
    let loaded = scene(v);
    let model = GraspModel::from_loaded(&loaded).expect("model");
    let solution = solve(&model).expect("solve");
    assert!(solution.status.has_forces(), "{:?}", solution.reason);
    let mut r = sensor_readings(&loaded.scene, &model, &solution).expect("readings");
    let gel = r.remove(0).gel.expect("a gel image");
    (model, solution, gel)
}

/// The sphere on an `n x n` gel with an image of `n + 20` pixels a side on its lattice.
fn hertz_image(n: usize) -> (GraspModel, Solution, GelImage) {
    let side = 2.45 * gel_hertz().contact_radius_m;
    read(&sphere_on_gel(n, lattice_gel(n, n + 20, side)))
}

#[test]
fn inside_the_contact_the_height_is_the_profile_less_the_approach() {
    // Compatibility (thesis eq. 7 with the gap closed): at an element in contact the pad's
    // surface meets the rigid sphere, so its height (into the pad) is the approach less the
    // initial gap `c_k`. The image's pixel on that element reads it to the solver's
    // tolerance (measured: 2e-15 of the approach, the solved gap there being round-off), the
    // read-out's own error is round-off; 1e-7 of the approach is stated. The approach itself
    // is Hertz's `a^2 / R` within 2 % (the discretisation's).
    let n = 41;
    let (model, solution, gel) = hertz_image(n);
    assert_eq!(gel.path, HeightPath::Lattice);
    // The finger is held: the sphere approaches it, by the object's sinking along -n = -z
    // (no rotation: the load is on the axis).
    let moved = solution
        .rigid_displacement
        .expect("the object's displacement");
    let approach = -moved.translation_m[2];
    let hertz = gel_hertz().approach_m;
    assert!(
        (approach - hertz).abs() < 0.02 * hertz,
        "{approach:e} vs Hertz {hertz:e}"
    );
    let gap0 = &model.fingers()[0].patch().gap_m;
    let m = n + 20;
    let mut worst = 0.0f64;
    let mut contact = 0;
    for e in &solution.fingers[0].elements {
        if e.normal_force_n <= 0.0 {
            continue;
        }
        contact += 1;
        let k = e.index[0] * n + e.index[1];
        let pixel = (e.index[0] + 10) * m + e.index[1] + 10;
        worst = worst.max((gel.height_m[pixel] - (approach - gap0[k])).abs());
    }
    println!(
        "{contact} elements in contact, largest |height - (approach - c)| {:.3e} of the approach",
        worst / approach
    );
    assert!(contact > 100, "{contact}");
    assert!(worst < 1e-7 * approach, "{worst:e} vs {approach:e}");
}

/// The largest error of the image's height map against Boussinesq's under the Hertz pressure
/// (Johnson eqs. 3.41-3.42), over the central `u_z` (the approach), on an `n x n` patch.
fn hertz_height_error(n: usize) -> f64 {
    let (_, _, gel) = hertz_image(n);
    let h = gel_hertz();
    let scale = h.surface_displacement_m(0.0, E_GEL, NU_GEL).0;
    gel.positions_m()
        .iter()
        .zip(&gel.height_m)
        .map(|(p, z)| {
            let want = h.surface_displacement_m(p[0].hypot(p[1]), E_GEL, NU_GEL).0;
            (z - want).abs() / scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_height_map_converges_to_boussinesq_under_the_hertz_pressure() {
    // The error is the discretisation's (element pressures uniform, the contact's edge within
    // an element); the read-out is exact. Inside the contact it is the profile's (the test
    // above), outside Johnson eq. 3.42. Doubling the grid must take it to 0.6 of itself or
    // less (the markers' own rule, tests/marker_readings.rs).
    let e21 = hertz_height_error(21);
    let e41 = hertz_height_error(41);
    let e81 = hertz_height_error(81);
    println!(
        "gel height vs Boussinesq, over the approach: 21 {e21:.3e}, 41 {e41:.3e}, 81 {e81:.3e}"
    );
    assert!(e21 < 1e-2, "{e21:e}");
    assert!(e41 <= 0.6 * e21, "{e41:e} vs {e21:e}");
    assert!(e81 <= 0.6 * e41, "{e81:e} vs {e41:e}");
}

#[test]
fn the_normals_and_colours_are_the_spheres_under_lamberts_law() {
    // Inside the contact the surface is the sphere's (the test above), `h = approach - c`,
    // whose unit normal toward the camera is `(-h_u, -h_v, 1) / |.|` with `h_u = -dc/du`.
    // The model's gap is the paraboloid `r^2 / (2 R)` (model/patch.rs), whose central
    // differences are exact: the normals equal `(u/R, v/R, 1)/|.|` to round-off (the heights'
    // 2e-15 of the approach over the pixel, 1e-14 here; 1e-9 stated), and each default light
    // (one colour each, 30 degrees above the plane) gives its channel `N . L` to the same
    // (|L| = 1).
    let n = 41;
    let (_, solution, gel) = hertz_image(n);
    let m = n + 20;
    let a = gel_hertz().contact_radius_m;
    let lights = default_lights();
    let positions = gel.positions_m();
    let mut checked = 0;
    for i in 1..m - 1 {
        for j in 1..m - 1 {
            let k = i * m + j;
            let [u, v] = positions[k];
            if u.hypot(v) > 0.8 * a {
                continue;
            }
            let n_want = {
                let (su, sv) = (u / R_SPHERE, v / R_SPHERE);
                let norm = (1.0 + su * su + sv * sv).sqrt();
                [su / norm, sv / norm, 1.0 / norm]
            };
            for c in 0..3 {
                let off = (gel.normal[k][c] - n_want[c]).abs();
                assert!(off < 1e-9, "{k} {:?} {n_want:?}", gel.normal[k]);
                let l = lights[c].direction;
                let lit: f64 = (0..3).map(|x| n_want[x] * l[x]).sum();
                assert!(
                    (gel.rgb[k][c] - lit).abs() < 5e-4,
                    "{k} {:?} {lit}",
                    gel.rgb[k]
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
    assert!(solution.fingers[0].contact_area_m2 > 0.0);
}

/// The sphere on a gel of `grid` elements over `size` (m), with the image `gel`.
fn sphere_on_patch(grid: [usize; 2], size: [f64; 2], gel: Value) -> Value {
    let mut v = sphere_on_gel(grid[0], gel);
    v["fingers"][0]["patch"] = json!({"size": size, "grid": grid});
    v
}

#[test]
fn the_lattice_and_dense_read_outs_agree() {
    // The same pixels read by one FFT product on the lattice and densely (the image turned
    // by 2 pi, which moves no pixel by more than 1e-19 m but is not on the lattice): the
    // same rectangle integrals, so equal to round-off; 1e-8 of the largest height stated
    // (the tolerance for the two paths). Cases: an image larger than the patch,
    // frictionless; with friction and an elastic object (the finger's share of the shear
    // terms); an oblong patch of oblong elements with an oblong image inside it, shifted; an
    // image reaching past the patch's side.
    let side = 2.45 * gel_hertz().contact_radius_m;
    let mut cases = vec![sphere_on_gel(21, lattice_gel(21, 31, side))];
    let mut pushed = example_json("hertz_sphere_on_flat.json");
    pushed["fingers"][0]["material"] = json!({"youngs_modulus": 70e9, "poisson_ratio": 0.33});
    pushed["fingers"][0]["friction"] = json!({"mu": 0.5});
    pushed["object"]["external_forces"] =
        json!([{"force": [2.0, 1.0, 0.0], "at": [0.0, 0.0, 0.0]}]);
    let size = pushed["fingers"][0]["patch"]["size"][0].as_f64().unwrap();
    let grid = pushed["fingers"][0]["patch"]["grid"][0].as_u64().unwrap() as usize;
    pushed["fingers"][0]["sensor"] = json!({"gel": lattice_gel(grid, grid + 10, size)});
    cases.push(pushed);
    let (hx, hy) = (side / 21.0, 0.8 * side / 15.0);
    cases.push(sphere_on_patch(
        [21, 15],
        [side, 0.8 * side],
        json!({"image_px": [17, 11], "field_of_view_m": [17.0 * hx, 11.0 * hy],
               "offset_m": [2.0 * hx, -hy]}),
    ));
    let h = side / 21.0;
    cases.push(sphere_on_gel(
        21,
        json!({"image_px": [9, 5], "field_of_view_m": [9.0 * h, 5.0 * h],
               "offset_m": [12.0 * h, -3.0 * h]}),
    ));
    for v in cases {
        let (_, solution, on_lattice) = read(&v);
        assert_eq!(on_lattice.path, HeightPath::Lattice);
        let mut turned = v.clone();
        turned["fingers"][0]["sensor"]["gel"]["rotation_rad"] = json!(std::f64::consts::TAU);
        let (_, _, dense) = read(&turned);
        assert_eq!(dense.path, HeightPath::Dense);
        let largest = dense.height_m.iter().fold(0.0f64, |m, h| m.max(h.abs()));
        let worst = on_lattice
            .height_m
            .iter()
            .zip(&dense.height_m)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!(
            "lattice vs dense, {:?} pixels: {:.3e} of the largest {largest:.3e} m",
            on_lattice.count,
            worst / largest
        );
        assert!(
            largest > 0.0 && worst <= 1e-8 * largest,
            "{worst:e} vs {largest:e}"
        );
        assert!(solution.fingers[0].normal_force_n > 0.0);
    }
}

#[test]
fn a_small_image_far_from_the_patch_is_read_densely() {
    // On the lattice, but the lattice's kernel table (from the patch to the image, 60
    // elements away) is more work than 4 pixels x 441 elements: the dense read-out is taken.
    let h = 2.45 * gel_hertz().contact_radius_m / 21.0;
    let v = sphere_on_gel(
        21,
        json!({"image_px": [2, 2], "field_of_view_m": [2.0 * h, 2.0 * h],
               "offset_m": [60.5 * h, 0.5 * h]}),
    );
    let (_, _, gel) = read(&v);
    assert_eq!(gel.path, HeightPath::Dense);
    assert!(gel.height_m.iter().all(|z| *z > 0.0), "{:?}", gel.height_m);
}

#[test]
fn a_lookup_table_of_the_lights_gives_their_image() {
    // A calibrated table tabulating Lambert's law under the default lights (129 x 129 over
    // slopes of +-0.2, beyond the largest slope here, about 0.09) reads the lights' image to
    // the bilinear interpolation's error, (step^2 / 8) max |f''| with step 3.1e-3 and
    // |f''| <= 2: 2.4e-6; 1e-5 stated.
    let (na, range) = (129usize, 0.2);
    let lights = default_lights();
    let rgb: Vec<Vec<[f64; 3]>> = (0..na)
        .map(|a| {
            (0..na)
                .map(|b| {
                    let su = -range + 2.0 * range * a as f64 / (na - 1) as f64;
                    let sv = -range + 2.0 * range * b as f64 / (na - 1) as f64;
                    let norm = (1.0 + su * su + sv * sv).sqrt();
                    let n = [su / norm, sv / norm, 1.0 / norm];
                    let mut c = [0.0; 3];
                    for (ch, l) in lights.iter().enumerate() {
                        let d = l.direction;
                        c[ch] = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).max(0.0);
                    }
                    c
                })
                .collect()
        })
        .collect();
    let side = 2.45 * gel_hertz().contact_radius_m;
    let lit = read(&sphere_on_gel(21, lattice_gel(21, 31, side))).2;
    let mut gel = lattice_gel(21, 31, side);
    gel["lookup"] = json!({"slope_range": range, "rgb": rgb});
    let looked = read(&sphere_on_gel(21, gel)).2;
    assert_eq!(lit.height_m, looked.height_m);
    let worst = largest_difference(&lit.rgb, &looked.rgb);
    println!("lookup vs lights: {worst:.3e}");
    assert!(worst < 1e-5, "{worst:e}");
}

#[test]
fn a_rigid_finger_reads_a_flat_image() {
    let side = 2.45 * gel_hertz().contact_radius_m;
    let mut v = sphere_on_gel(11, lattice_gel(11, 11, side));
    v["fingers"][0]["material"] = json!("rigid");
    v["object"]["material"] = json!({"youngs_modulus": E_GEL, "poisson_ratio": NU_GEL});
    let (_, _, gel) = read(&v);
    assert_eq!(gel.path, HeightPath::Flat);
    assert!(gel.height_m.iter().all(|h| *h == 0.0));
    assert!(gel.rgb.iter().flatten().all(|c| (c - 0.5).abs() < 1e-12));
    assert_eq!(gel.rgb8().len(), 3 * 11 * 11);
}

// ---- Refusals ----

fn with_gel(gel: Value) -> Value {
    let side = 2.45 * gel_hertz().contact_radius_m;
    let mut v = sphere_on_gel(11, lattice_gel(11, 11, side));
    v["fingers"][0]["sensor"]["gel"] = gel;
    v
}

fn good_gel() -> Value {
    json!({"image_px": [8, 8], "field_of_view_m": [2e-3, 2e-3]})
}

#[test]
fn a_layered_or_viscoelastic_pad_is_refused_for_a_gel_image() {
    let mut v = with_gel(good_gel());
    v["fingers"][0]["material"]["layer_thickness_m"] = json!(1e-3);
    assert_refused(
        &v,
        "fingers[0].sensor",
        "gel images need a half-space pad; fingers[0].material has a bonded layer",
    );
    let mut v = with_gel(good_gel());
    v["fingers"][0]["material"]["relaxation"] = json!({"long_term_modulus": 3e5, "time_s": 1.0});
    assert_refused(
        &v,
        "fingers[0].sensor",
        "gel images need an elastic half-space pad; fingers[0].material is viscoelastic",
    );
}

#[test]
fn bad_gel_numbers_are_named_with_their_path() {
    let p = "fingers[0].sensor.gel";
    let edit = |key: &str, value: Value| {
        let mut g = good_gel();
        g[key] = value;
        with_gel(g)
    };
    assert_refused(
        &edit("image_px", json!([0, 8])),
        &format!("{p}.image_px[0]"),
        "outside [1, 1024]",
    );
    assert_refused(
        &edit("field_of_view_m", json!([2e-3, -1.0])),
        &format!("{p}.field_of_view_m[1]"),
        "outside",
    );
    assert_refused(
        &edit("rotation_rad", json!(10.0)),
        &format!("{p}.rotation_rad"),
        "outside",
    );
    assert_refused(
        &edit("lights", json!([])),
        &format!("{p}.lights"),
        "has 0 lights",
    );
    assert_refused(
        &edit(
            "lights",
            json!([{"direction": [1, 0, -1], "rgb": [1, 1, 1]}]),
        ),
        &format!("{p}.lights[0].direction"),
        "w > 0",
    );
    assert_refused(
        &edit(
            "lights",
            json!([{"direction": [0, 0, 1], "rgb": [1, 11, 1]}]),
        ),
        &format!("{p}.lights[0].rgb[1]"),
        "outside",
    );
    assert_refused(
        &edit("ambient_rgb", json!([0, 2, 0])),
        &format!("{p}.ambient_rgb[1]"),
        "outside",
    );
    let table =
        json!({"slope_range": 0.1, "rgb": [[[0, 0, 0], [1, 1, 1]], [[0, 0, 0], [1, 1, 1]]]});
    let mut both = good_gel();
    both["lookup"] = table.clone();
    both["ambient_rgb"] = json!([0.1, 0.1, 0.1]);
    assert_refused(&with_gel(both), p, "both `lookup` and");
    let ragged = json!({"slope_range": 0.1, "rgb": [[[0, 0, 0], [1, 1, 1]], [[0, 0, 0]]]});
    assert_refused(
        &edit("lookup", ragged),
        &format!("{p}.lookup.rgb[1]"),
        "has 1 colours",
    );
    let dim = json!({"slope_range": 0.1, "rgb": [[[0, 0, 0], [1, 1, 2]], [[0, 0, 0], [1, 1, 1]]]});
    assert_refused(
        &edit("lookup", dim),
        &format!("{p}.lookup.rgb[0]"),
        "outside [0, 1]",
    );
    let tiny = json!({"slope_range": 0.1, "rgb": [[[0, 0, 0]]]});
    assert_refused(
        &edit("lookup", tiny),
        &format!("{p}.lookup.rgb"),
        "is 1 x 1",
    );
    assert_refused(
        &edit("lookup", json!({"slope_range": 0.0, "rgb": table["rgb"]})),
        &format!("{p}.lookup.slope_range"),
        "outside",
    );
}

#[test]
fn a_dense_gel_read_out_of_too_much_work_is_refused() {
    // 1024 x 1024 pixels turned off the lattice over a 256 x 256 patch: 6.9e10 evaluations,
    // far above the limit; the refusal says how to reach the FFT read-out.
    let mut v = with_gel(
        json!({"image_px": [1024, 1024], "field_of_view_m": [2e-3, 2e-3],
                                "rotation_rad": 0.1}),
    );
    v["fingers"][0]["patch"]["grid"] = json!([256, 256]);
    assert_refused(&v, "fingers[0].sensor", "kernel evaluations");
    let p = problems(&v);
    assert!(p.iter().any(|m| m.contains("element lattice")), "{p:#?}");
}
