//! The `grasp` binary: exit codes, messages, and never overwriting a user's file without
//! `--force`.

use std::path::{Path, PathBuf};

mod common;
use common::{example, grasp, text};

fn tmp(tag: &str) -> PathBuf {
    common::tmp("cli", tag)
}

#[test]
fn solve_prints_a_table_and_writes_json() {
    let dir = tmp("solve");
    let out = dir.join("cube_a.solution.json");
    let o = grasp(&[
        "solve",
        &example("cube_a.json"),
        "--json",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("P [N]") && t.contains("status: solved") && t.contains("error: equilibrium"),
        "{t}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["status"], "solved");
    for key in ["name", "normal_force_n", "tangential_force_n", "elements"] {
        assert!(!v["fingers"][0][key].is_null(), "missing fingers[0].{key}");
    }
    assert!(v["residuals"]["equilibrium_relative"].as_f64().unwrap() < 1e-9);
    assert!(v["solve_time_s"].as_f64().unwrap() > 0.0);
}

#[test]
fn existing_output_is_not_overwritten_without_force() {
    let dir = tmp("force");
    let out = dir.join("mine.json");
    std::fs::write(&out, "precious").unwrap();
    let o = grasp(&[
        "solve",
        &example("cube_a.json"),
        "--json",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("already exists") && text(&o).contains("--force"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "precious");
    let mcap = dir.join("mine.mcap");
    std::fs::write(&mcap, "precious").unwrap();
    let o = grasp(&[
        "transfer",
        &example("plate_transfer.json"),
        "--schedule",
        &example("plate_transfer.schedule.json"),
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&mcap).unwrap(), "precious");
    let o = grasp(&[
        "solve",
        &example("cube_a.json"),
        "--json",
        out.to_str().unwrap(),
        "--force",
    ]);
    assert!(o.status.success());
    assert_ne!(std::fs::read_to_string(&out).unwrap(), "precious");
}

#[test]
fn infeasible_grasp_is_a_reported_outcome_with_exit_code_2() {
    let dir = tmp("infeasible");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("cube_b.json")).unwrap()).unwrap();
    for f in v["fingers"].as_array_mut().unwrap() {
        f["friction"]["mu"] = 0.3.into();
    }
    let scene = dir.join("cube_b_mu03.json");
    std::fs::write(&scene, v.to_string()).unwrap();
    let o = grasp(&["solve", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("no equilibrium"), "{}", text(&o));
    assert!(!text(&o).contains("panicked"));
}

#[test]
fn bad_scene_and_bad_schedule_name_the_field() {
    let dir = tmp("bad");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("cube_a.json")).unwrap()).unwrap();
    v["fingers"][2]["normal"] = serde_json::json!([0, 0, 0]);
    let scene = dir.join("bad.json");
    std::fs::write(&scene, v.to_string()).unwrap();
    let o = grasp(&["solve", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o).contains("fingers[2].normal: has zero length"),
        "{}",
        text(&o)
    );
    let sched = dir.join("bad.schedule.json");
    std::fs::write(
        &sched,
        r#"{"time": {"start": 0, "end": 1, "step": 0.5}, "fingers": {"f7": [{"held": {}}]}}"#,
    )
    .unwrap();
    let o = grasp(&[
        "transfer",
        &example("plate_transfer.json"),
        "--schedule",
        sched.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o).contains("fingers.f7: no finger named `f7`"),
        "{}",
        text(&o)
    );
}

#[test]
fn schema_commands_print_json_schemas() {
    for args in [vec!["schema"], vec!["schema", "--schedule"]] {
        let o = grasp(&args);
        assert!(o.status.success());
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["type"], "object");
        assert!(v["properties"]["fingers"].is_object());
    }
}

#[test]
fn transfer_writes_every_output_and_summarises() {
    let dir = tmp("transfer");
    let (m, r, c, p) = (
        dir.join("d.mcap"),
        dir.join("d.rrd"),
        dir.join("d.csv"),
        dir.join("d.svg"),
    );
    let o = grasp(&[
        "transfer",
        &example("disc_transfer.json"),
        "--schedule",
        &example("disc_transfer.schedule.json"),
        "--mcap",
        m.to_str().unwrap(),
        "--rrd",
        r.to_str().unwrap(),
        "--csv",
        c.to_str().unwrap(),
        "--plot",
        p.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    for want in [
        "receiving fingers carry half the load: t =",
        "carry all the load:  t =",
        "peak squeeze",
        "smallest slip margin",
        "failed steps: none",
    ] {
        assert!(t.contains(want), "missing `{want}` in\n{t}");
    }
    for f in [&m, &r, &c, &p] {
        assert!(
            std::fs::metadata(f).unwrap().len() > 0,
            "{} empty",
            f.display()
        );
    }
    assert!(std::fs::read_to_string(&p).unwrap().starts_with("<svg"));
}

/// The schemas published in docs/ are the ones the code generates (regenerate with
/// `grasp schema > docs/scene.schema.json` and `grasp schema --schedule > docs/schedule.schema.json`).
#[test]
fn published_schemas_match_the_code() {
    for (args, file) in [
        (vec!["schema"], "scene.schema.json"),
        (vec!["schema", "--schedule"], "schedule.schema.json"),
    ] {
        let o = grasp(&args);
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../docs")
            .join(file);
        let published = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            String::from_utf8_lossy(&o.stdout),
            published,
            "docs/{file} is stale"
        );
    }
}

/// A step without equilibrium stops the run; `--keep-going` records it and goes on.
#[test]
fn keep_going_continues_past_a_failed_step() {
    let dir = tmp("keep-going");
    // Release the first pair before the second engages: the middle steps have no fingers.
    let sched = dir.join("gap.schedule.json");
    std::fs::write(
        &sched,
        r#"{"time": {"times": [0, 1, 2, 3]},
            "fingers": {"f1": [{"held": {"until": 0}}, {"ramp": {"keyframes": [[1, 0]]}}],
                        "f2": [{"held": {"until": 0}}, {"ramp": {"keyframes": [[1, 0]]}}],
                        "f3": [{"ramp": {"keyframes": [[2, 0]]}}, {"held": {}}],
                        "f4": [{"ramp": {"keyframes": [[2, 0]]}}, {"held": {}}]}}"#,
    )
    .unwrap();
    let csv = dir.join("gap.csv");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "transfer",
            &*Box::leak(example("plate_transfer.json").into_boxed_str()),
            "--schedule",
            sched.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
            "--force",
        ];
        args.extend_from_slice(extra);
        grasp(&args)
    };
    let o = run(&[]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("steps: 2 of 4") && text(&o).contains("nothing holds the object"),
        "{}",
        text(&o)
    );
    let o = run(&["--keep-going"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("steps: 4 of 4") && text(&o).contains("failed steps: 2"),
        "{}",
        text(&o)
    );
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
    assert_eq!(rows, 5, "header and four steps");
}

#[test]
fn missing_output_folders_are_created() {
    let dir = tmp("mkdir").join("new").join("deeper");
    let out = dir.join("cube_a.json");
    let o = grasp(&[
        "solve",
        &example("cube_a.json"),
        "--json",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.is_file());
}

/// The shape's warnings reach `solve --json` and are printed once: a box pinch on an OBJ
/// box without its bottom face (open: a warning), with both 10 mm pads 3 mm below the top
/// edge (each hangs 2 mm over it: a warning per finger).
#[test]
fn solve_json_carries_the_shape_warnings() {
    let dir = tmp("warnings");
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                (i & 1) as f64 * 60.0 - 30.0,
                ((i >> 1) & 1) as f64 * 40.0 - 20.0,
                ((i >> 2) & 1) as f64 * 100.0,
            ]
        })
        .collect();
    // The box's faces but its bottom (z = 0), counter-clockwise seen from outside.
    let faces = [
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    let mut obj = String::new();
    for c in &corners {
        obj += &format!("v {} {} {}\n", c[0], c[1], c[2]);
    }
    for f in faces {
        obj += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    std::fs::write(dir.join("open_box.obj"), obj).unwrap();
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("box_pinch.json")).unwrap()).unwrap();
    let object = scene["object"].as_object_mut().unwrap();
    object.remove("density");
    object.insert("weight".into(), serde_json::json!(1.6));
    object.insert("center_of_mass".into(), serde_json::json!([0, 0, 0.05]));
    object.insert(
        "shape".into(),
        serde_json::json!({"mesh": {"file": "open_box.obj", "unit": "mm"}}),
    );
    for f in scene["fingers"].as_array_mut().unwrap() {
        f["place"]["ray"]["origin"][2] = serde_json::json!(0.097);
    }
    let path = dir.join("scene.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.join("solution.json");
    let o = grasp(&[
        "solve",
        path.to_str().unwrap(),
        "--json",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let warnings: Vec<&str> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert!(
        warnings[0].contains("the mesh is not closed (4 edges with one triangle only)"),
        "{warnings:?}"
    );
    for (w, name) in warnings[1..].iter().zip(["left", "right"]) {
        assert!(
            w.starts_with(&format!(
                "finger {name}: the patch hangs 2.000 mm over the edge"
            )),
            "{w}"
        );
    }
    let printed = String::from_utf8_lossy(&o.stdout);
    for w in &warnings {
        assert_eq!(
            printed.matches(&format!("warning: {w}")).count(),
            1,
            "{printed}"
        );
    }
}
