//! Messages as a user reads them: numbers in exponent form when extreme
//! (1e308 is not written as 309 digits), a nested shape error at its full path
//! (`object.shape.mesh.unit: unknown variant`, not `mesh.unitunknown`), a mesh vertex that is
//! not finite refused at the mesh file (not reported as a ray starting inside the object), and
//! a bad external-load CSV column as one problem (no second "has no keyframe").

mod common;

use common::{example, grasp, text, tmp};
use serde_json::{json, Value};

fn load(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(example(name)).unwrap()).unwrap()
}

/// The longest run of digits in `text`.
fn longest_digit_run(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// The problem lines (`  - path: message; fix: ...`) of an error.
fn problems(all: &str) -> Vec<&str> {
    all.lines().filter(|l| l.starts_with("  - ")).collect()
}

#[test]
fn extreme_numbers_in_scenes_are_quoted_in_exponent_form() {
    let d = tmp("messages", "numbers");
    type Set = fn(&mut Value, f64);
    let cases: [(&str, Set); 4] = [
        ("weight", |s, x| s["object"]["weight"] = json!(x)),
        ("modulus", |s, x| {
            s["fingers"][0]["material"]["youngs_modulus"] = json!(x)
        }),
        ("patch", |s, x| {
            s["fingers"][0]["patch"]["size"][0] = json!(x)
        }),
        ("radius", |s, x| s["fingers"][0]["tip_radius"] = json!(x)),
    ];
    for (name, set) in cases {
        for x in [1e308, -1e308] {
            let mut s = load("cube_a.json");
            set(&mut s, x);
            let path = d.join(format!("{name}.json"));
            std::fs::write(&path, s.to_string()).unwrap();
            let o = grasp(&["solve", path.to_str().unwrap()]);
            let all = text(&o);
            assert_eq!(o.status.code(), Some(1), "{name} {x:e}: {all}");
            assert!(all.contains("e308"), "{name} {x:e}: {all}");
            assert!(longest_digit_run(&all) <= 20, "{name} {x:e}: {all}");
        }
    }
}

/// The mug scene and its mesh copied into a scratch folder, changed by `scene` and with the
/// first vertex line replaced by `vertex`.
fn mug(tag: &str, scene: impl Fn(&mut Value), vertex: Option<&str>) -> String {
    let d = tmp("messages", tag);
    std::fs::create_dir_all(d.join("meshes")).unwrap();
    let obj = std::fs::read_to_string(example("meshes/mug.obj")).unwrap();
    let mut lines: Vec<&str> = obj.lines().collect();
    if let Some(v) = vertex {
        let first = lines.iter().position(|l| l.starts_with("v ")).unwrap();
        lines[first] = v;
    }
    std::fs::write(d.join("meshes/mug.obj"), lines.join("\n")).unwrap();
    let mut s = load("mug_power_grasp.json");
    scene(&mut s);
    let path = d.join("mug.json");
    std::fs::write(&path, s.to_string()).unwrap();
    path.display().to_string()
}

#[test]
fn an_unknown_mesh_unit_is_named_by_its_full_path() {
    let path = mug(
        "unit",
        |s| s["object"]["shape"]["mesh"]["unit"] = json!("furlong"),
        None,
    );
    let o = grasp(&["solve", &path]);
    let all = text(&o);
    assert_eq!(o.status.code(), Some(1), "{all}");
    assert!(
        all.contains("object.shape.mesh.unit: unknown variant `furlong`"),
        "{all}"
    );
    assert!(!all.contains('\u{1f}'), "{all:?}");
}

#[test]
fn a_mesh_vertex_that_is_not_finite_is_refused_at_the_mesh_file() {
    for vertex in ["v nan 0 0", "v 0 0 inf", "v 1e30 0 0"] {
        let path = mug("vertex", |_| {}, Some(vertex));
        let o = grasp(&["solve", &path]);
        let all = text(&o);
        assert_eq!(o.status.code(), Some(1), "{vertex}: {all}");
        let p = problems(&all);
        assert_eq!(p.len(), 1, "{vertex}: {all}");
        assert!(
            p[0].starts_with("  - object.shape.mesh.file: vertex 0 of the mesh is"),
            "{vertex}: {all}"
        );
        assert!(!all.contains("start the ray outside"), "{vertex}: {all}");
    }
}

#[test]
fn a_bad_external_load_column_is_one_problem() {
    let d = tmp("messages", "wrench");
    std::fs::copy(example("plate_bump.csv"), d.join("plate_bump.csv")).unwrap();
    let mut s = load("plate_bump.schedule.json");
    s["external"]["csv"]["force_columns"] = json!([null, null, "fz_newtons"]);
    let schedule = d.join("s.json");
    std::fs::write(&schedule, s.to_string()).unwrap();
    let o = grasp(&[
        "transfer",
        &example("plate_handoff_coulomb.json"),
        "--schedule",
        schedule.to_str().unwrap(),
    ]);
    let all = text(&o);
    assert_eq!(o.status.code(), Some(1), "{all}");
    let p = problems(&all);
    assert_eq!(p.len(), 1, "{all}");
    assert!(
        p[0].starts_with("  - external.csv.columns: column `fz_newtons` is not in"),
        "{all}"
    );
    assert!(p[0].contains("(columns: `t_s`, `fz_n`, `ty_nm`)"), "{all}");
}

/// The help shows the solve tolerance's default as it is written everywhere else, `1e-10`
/// (not `0.0000000001`, ten digits to count).
#[test]
fn the_tolerance_default_is_shown_in_exponent_form() {
    let o = grasp(&["solve", "--help"]);
    assert!(o.status.success(), "{}", text(&o));
    let help = text(&o);
    assert!(help.contains("[default: 1e-10]"), "{help}");
    assert!(!help.contains("0.0000000001"), "{help}");
}

/// A frictionless finger's elements in contact neither stick nor slip: the table counts them
/// apart (they were counted as slipping), and one finger is "1 finger".
#[test]
fn a_frictionless_finger_is_counted_neither_stick_nor_slip() {
    let o = grasp(&["solve", &example("hertz_sphere_on_flat.json")]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    assert!(out.contains(": 1 finger, 3-D scene"), "{out}");
    let row = out
        .lines()
        .find(|l| l.starts_with("tip ") || l.split_whitespace().next() == Some("tip"))
        .unwrap_or_else(|| panic!("no row of finger tip:\n{out}"));
    assert!(row.contains("-/-/"), "{row}");
    assert!(row.contains(" frictionless"), "{row}");
}
