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
        t.contains("P [N]") && t.contains("status: solved") && t.contains("residuals: equilibrium"),
        "{t}"
    );
    // `error:` is kept for errors: a successful run prints none.
    assert!(!t.lines().any(|l| l.starts_with("error")), "{t}");
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
        "residuals: worst equilibrium residual",
        "time: stepping ",
    ] {
        assert!(t.contains(want), "missing `{want}` in\n{t}");
    }
    assert!(!t.lines().any(|l| l.starts_with("error")), "{t}");
    // Each output says how to open it.
    let opens: Vec<&str> = t.lines().filter(|l| l.starts_with("  open: ")).collect();
    assert_eq!(opens.len(), 4, "{t}");
    assert!(
        t.contains(&format!("  open: rerun {}", r.display())),
        "the recording's line names the command: {t}"
    );
    assert!(t.contains("  open: Foxglove"), "{t}");
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
    // The thesis's quadratic gap, blind to the edge, is what the over-the-edge warning is about.
    scene["gap"] = serde_json::json!("quadratic");
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
/// A slip margin within round-off of 0 (the plate's releasing fingers start at the friction
/// limit: `1 - |Q|/(mu P)` came out -6.66e-16) is printed as 0 and explained.
#[test]
fn a_round_off_slip_margin_reads_zero() {
    let o = grasp(&[
        "transfer",
        &example("plate_transfer.json"),
        "--schedule",
        &example("plate_transfer.schedule.json"),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    let line = t
        .lines()
        .find(|l| l.starts_with("smallest slip margin"))
        .unwrap_or_else(|| panic!("no slip margin line in\n{t}"));
    assert!(
        line.starts_with("smallest slip margin 1 - |Q|/(mu P): 0 (")
            && line.contains("friction limit"),
        "{line}"
    );
}

/// With `--margins` the summary's time line gives the stepping and the margins apart.
#[test]
fn transfer_with_margins_reports_both_times() {
    let dir = tmp("margins-time");
    let sched = dir.join("three.schedule.json");
    std::fs::write(
        &sched,
        r#"{"time": {"times": [0, 10, 19.9]},
            "fingers": {"f1": [{"held": {"until": 0}}, {"ramp": {"keyframes": [[0, "current"], [19.9, 0]]}}],
                        "f2": [{"held": {"until": 0}}, {"ramp": {"keyframes": [[0, "current"], [19.9, 0]]}}],
                        "f3": [{"held": {}}], "f4": [{"held": {}}]}}"#,
    )
    .unwrap();
    let o = grasp(&[
        "transfer",
        &example("plate_transfer.json"),
        "--schedule",
        sched.to_str().unwrap(),
        "--margins",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    let line = t.lines().find(|l| l.starts_with("time: ")).unwrap_or("");
    assert!(
        line.starts_with("time: stepping ")
            && line.contains("; margins ")
            && line.contains(" solves)")
            && line.contains("the whole run "),
        "{t}"
    );
}

/// A coulomb hand-off's margins are probed for second equilibria only when asked, and the
/// report says when they were not; an energy hand-off has nothing to probe and says nothing.
#[test]
fn transfer_says_whether_its_coulomb_margins_were_probed() {
    let dir = tmp("probe-said");
    let sched = dir.join("three.schedule.json");
    std::fs::write(
        &sched,
        r#"{"time": {"times": [0, 6, 12]},
            "fingers": {"f1": [{"ramp": {"keyframes": [[0, 8], [4, 8], [12, 0]]}}],
                        "f2": [{"ramp": {"keyframes": [[0, 8], [4, 8], [12, 0]]}}],
                        "f3": [{"ramp": {"keyframes": [[0, 0], [8, 8]]}}],
                        "f4": [{"ramp": {"keyframes": [[0, 0], [8, 8]]}}]}}"#,
    )
    .unwrap();
    let run = |scene: &str, extra: &[&str]| {
        let scene = example(scene);
        let mut args = vec!["transfer", &scene, "--schedule", sched.to_str().unwrap()];
        args.push("--margins");
        args.extend_from_slice(extra);
        let o = grasp(&args);
        assert!(o.status.success(), "{}", text(&o));
        text(&o)
    };
    let not_probed = "second coulomb equilibria at the margins' failing ends: not probed";
    let t = run("plate_handoff_coulomb.json", &[]);
    assert!(t.contains(not_probed), "{t}");
    let t = run("plate_handoff_coulomb.json", &["--probe-equilibria"]);
    assert!(!t.contains(not_probed), "{t}");
    assert!(!t.contains("another coulomb equilibrium"), "{t}");
    let t = run("plate_transfer.json", &[]);
    assert!(!t.contains("coulomb equilibri"), "{t}");
}

/// The same run writes the same `.rrd` bytes up to Rerun's footer (two processes, so nothing
/// is shared but the inputs). The footer, an index Rerun 0.36 appends, lists its entries in
/// hash-map order; `tests/transfer_outputs.rs` checks that its content is the same.
#[test]
fn recordings_are_byte_identical_from_run_to_run_up_to_the_footer() {
    let dir = tmp("rrd-twice");
    let run = |name: &str| {
        let out = dir.join(name);
        let o = grasp(&[
            "transfer",
            &example("plate_transfer.json"),
            "--schedule",
            &example("plate_transfer.schedule.json"),
            "--rrd",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        let bytes = std::fs::read(out).unwrap();
        // The stream footer (the last 32 bytes) starts with the footer payload's offset; a
        // 16-byte frame header precedes the payload.
        let tail = bytes.len() - 32;
        assert_eq!(&bytes[tail + 20..tail + 28], b"RRF2FOOT");
        let start = u64::from_le_bytes(bytes[tail..tail + 8].try_into().unwrap()) as usize;
        bytes[..start - 16].to_vec()
    };
    let (a, b) = (run("a.rrd"), run("b.rrd"));
    assert!(a.len() > 100_000, "{} bytes before the footer", a.len());
    let first_difference = a.iter().zip(&b).position(|(x, y)| x != y);
    assert!(
        a.len() == b.len() && first_difference.is_none(),
        "{} and {} bytes, first difference at byte {first_difference:?}",
        a.len(),
        b.len()
    );
}

/// Runs `grasp args` with its standard output a pipe whose reader is already closed: every
/// write fails with a broken pipe.
fn with_closed_stdout(args: &[&str]) -> std::process::Output {
    use std::os::fd::FromRawFd;
    let mut fds = [0 as libc::c_int; 2];
    // SAFETY: `fds` has room for the two descriptors pipe(2) writes.
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
    // SAFETY: fds[0] is the read end just made and owned here; closing it leaves no reader.
    unsafe { libc::close(fds[0]) };
    // SAFETY: fds[1] is the write end just made, owned by nothing else.
    let write_end = unsafe { std::os::fd::OwnedFd::from_raw_fd(fds[1]) };
    std::process::Command::new(env!("CARGO_BIN_EXE_grasp"))
        .args(args)
        .stdout(std::process::Stdio::from(write_end))
        .output()
        .expect("run grasp")
}

/// Every command meets a closed standard output quietly: exit 0 or 141 (what a shell reports
/// for a program stopped by a closed pipe), never a panic (101), and an interrupted run leaves
/// no temporary file behind.
#[test]
fn a_closed_stdout_ends_every_command_quietly() {
    let dir = tmp("closed-stdout");
    let file = |name: &str| dir.join(name).display().to_string();
    let scenes = dir.join("scenes.jsonl");
    let cube = std::fs::read_to_string(example("cube_a.json")).unwrap();
    let cube: serde_json::Value = serde_json::from_str(&cube).unwrap();
    std::fs::write(
        &scenes,
        format!("{}\n", serde_json::json!({"id": "a", "scene": cube})),
    )
    .unwrap();
    let (cube_a, hertz) = (example("cube_a.json"), example("hertz_sphere_on_flat.json"));
    let (plate, plate_schedule) = (
        example("plate_transfer.json"),
        example("plate_transfer.schedule.json"),
    );
    let coulomb = example("plate_handoff_coulomb.json");
    let runs: Vec<Vec<String>> = vec![
        vec!["schema".into()],
        vec!["schema".into(), "--schedule".into()],
        vec!["--help".into()],
        vec!["solve".into(), cube_a.clone()],
        vec![
            "solve".into(),
            cube_a.clone(),
            "--json".into(),
            file("cube.json"),
        ],
        vec![
            "transfer".into(),
            plate.clone(),
            "--schedule".into(),
            plate_schedule.clone(),
            "--csv".into(),
            file("plate.csv"),
        ],
        vec![
            "plot".into(),
            cube_a.clone(),
            "--out".into(),
            file("cube.svg"),
        ],
        vec!["study".into(), hertz, "--grids".into(), "3,5".into()],
        vec!["margin".into(), coulomb],
        vec![
            "sweep".into(),
            cube_a.clone(),
            "--vary".into(),
            "object.weight=1,2".into(),
            "--out".into(),
            file("variants.jsonl"),
        ],
        vec![
            "batch".into(),
            scenes.display().to_string(),
            "--out".into(),
            file("results.jsonl"),
        ],
        vec![
            "bench".into(),
            "--quick".into(),
            "--case".into(),
            "cube_a_5x5".into(),
            "--solver".into(),
            "native".into(),
            "--min-time".into(),
            "0".into(),
        ],
    ];
    for args in &runs {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = with_closed_stdout(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            matches!(o.status.code(), Some(0) | Some(141)) && !stderr.contains("panicked"),
            "grasp {}: {:?}\n{stderr}",
            args.join(" "),
            o.status
        );
    }
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".grasp-tmp-"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
    // The transfer stopped at its first line: its CSV was never moved into place.
    assert!(!dir.join("plate.csv").exists());
}

/// `grasp study` takes the closed form as its reference where the scene has one, and says
/// why the reference matters where it has none.
#[test]
fn study_picks_the_closed_form_where_the_scene_has_one() {
    let o = grasp(&[
        "study",
        &example("hertz_sphere_on_flat.json"),
        "--grids",
        "5,9",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("reference: the Hertz closed form") && t.contains("chosen automatically"),
        "{t}"
    );
    assert!(t.contains("| p0 error |"), "{t}");
    let o = grasp(&["study", &example("cube_a.json"), "--grids", "3,5"]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("reference: the finest grid")
            && t.contains("understated")
            && t.contains("no closed form applies"),
        "{t}"
    );
}

/// A scene with several structural mistakes lists them all, each with a fix.
#[test]
fn a_scene_lists_every_structural_problem_with_a_fix() {
    let dir = tmp("structure");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("cube_a.json")).unwrap()).unwrap();
    v["fingers"][0].as_object_mut().unwrap().remove("normal");
    v["fingers"][1].as_object_mut().unwrap().remove("material");
    v["fingers"][2]["nromal"] = serde_json::json!([0, 1, 0]);
    v["object"]["weight"] = serde_json::json!("heavy");
    let scene = dir.join("bad.json");
    std::fs::write(&scene, v.to_string()).unwrap();
    let o = grasp(&["solve", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    for path in [
        "fingers[0].normal: is missing; fix: give the contact normal pointing into the object, \
         or `place`",
        "fingers[1].material: is missing; fix: add `material`",
        "fingers[2].nromal: is not a field here; fix: did you mean `normal`?",
        "object.weight: is the string \"heavy\", expected a number; fix: write a number",
    ] {
        assert!(t.contains(path), "missing `{path}` in\n{t}");
    }
    let problems = t.lines().filter(|l| l.starts_with("  - ")).count();
    assert_eq!(problems, 4, "{t}");
    assert!(
        t.lines()
            .filter(|l| l.starts_with("  - "))
            .all(|l| l.contains("; fix: ")),
        "{t}"
    );
}

/// The guide's commented scene (docs/guide/scenes.md) pasted as is: the error says JSON has no
/// comments.
#[test]
fn a_commented_scene_is_told_json_has_no_comments() {
    let dir = tmp("comments");
    let guide = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/guide/scenes.md"),
    )
    .unwrap();
    let start = guide.find("## Scenes (SI units)").unwrap();
    let block = &guide[start..];
    let body = &block[block.find("```json\n").unwrap() + 8..];
    let body = &body[..body.find("```").unwrap()];
    assert!(body.contains("//"), "the guide's example has comments");
    let scene = dir.join("pasted.json");
    std::fs::write(&scene, body).unwrap();
    let o = grasp(&["solve", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("line 1, column 52: JSON has no comments"),
        "{}",
        text(&o)
    );
}

/// Hand-off plots show every finger: the plate's pairs have identical curves (f1 = f2,
/// f3 = f4), so each finger needs markers that no other finger's marker covers, and the note
/// names the pairs. Read from the SVG: markers are circles of radius 4 in the finger's colour
/// (the plot's palette: f1 red, f2 blue, f3 green, f4 orange), drawn after every line.
#[test]
fn hand_off_plots_show_every_finger() {
    let dir = tmp("hand-off-plot");
    for (scene, pairs) in [
        ("plate_transfer", ["f1 = f2", "f3 = f4"]),
        ("disc_transfer", ["", ""]),
    ] {
        let svg = dir.join(format!("{scene}.svg"));
        let o = grasp(&[
            "transfer",
            &example(&format!("{scene}.json")),
            "--schedule",
            &example(&format!("{scene}.schedule.json")),
            "--plot",
            svg.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        let text = std::fs::read_to_string(&svg).unwrap();
        for p in pairs.iter().filter(|p| !p.is_empty()) {
            assert!(text.contains(p), "{scene}: no note `{p}`");
        }
        let circles = svg_circles(&text);
        for (i, colour) in ["#D62728", "#1F77B4", "#2CA02C", "#FF7F0E"]
            .iter()
            .enumerate()
        {
            for filled in [true, false] {
                let visible = circles
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.colour == *colour && c.filled == filled && c.r == 4.0)
                    .filter(|(k, c)| {
                        circles[k + 1..].iter().all(|d| {
                            d.colour == c.colour || (d.x - c.x).hypot(d.y - c.y) >= c.r + d.r
                        })
                    })
                    .count();
                assert!(
                    visible >= 3,
                    "{scene}: f{} has {visible} uncovered {} markers",
                    i + 1,
                    if filled { "filled (P)" } else { "hollow (|Q|)" }
                );
            }
        }
    }
}

/// A hand-off plot's legend sits beside the curves, not over them: its box (the one rectangle
/// drawn with a black border) lies right of every line that is not inside it.
#[test]
fn hand_off_plot_legend_sits_beside_the_curves() {
    let dir = tmp("hand-off-legend");
    let svg = dir.join("plate.svg");
    let o = grasp(&[
        "transfer",
        &example("plate_transfer.json"),
        "--schedule",
        &example("plate_transfer.schedule.json"),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    let attr = |line: &str, name: &str| -> f64 {
        let key = format!(" {name}=\"");
        let start = line.find(&key).unwrap() + key.len();
        line[start..].split('"').next().unwrap().parse().unwrap()
    };
    let boxes: Vec<[f64; 4]> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("<rect") && l.contains("stroke=\"#000000\""))
        .map(|l| {
            [
                attr(l, "x"),
                attr(l, "y"),
                attr(l, "width"),
                attr(l, "height"),
            ]
        })
        .collect();
    assert_eq!(boxes.len(), 1, "one legend box: {boxes:?}");
    let [x, y, w, h] = boxes[0];
    let inside = |p: (f64, f64)| p.0 >= x && p.0 <= x + w && p.1 >= y && p.1 <= y + h;
    let lines = text
        .lines()
        .filter(|l| l.trim_start().starts_with("<polyline"));
    let mut curves = 0;
    for l in lines {
        let start = l.find(" points=\"").unwrap() + 9;
        let points: Vec<(f64, f64)> = l[start..]
            .split('"')
            .next()
            .unwrap()
            .split_whitespace()
            .map(|p| {
                let (a, b) = p.split_once(',').unwrap();
                (a.parse().unwrap(), b.parse().unwrap())
            })
            .collect();
        if points.iter().all(|&p| inside(p)) {
            continue; // a legend entry's sample line
        }
        curves += 1;
        assert!(
            points.iter().all(|p| p.0 < x),
            "a line reaches under the legend: {l}"
        );
    }
    assert!(curves >= 8, "{curves} lines outside the legend");
}

/// A scene whose gravity lies along an axis is drawn with the weight pointing down the page:
/// both views are onto a plane that holds gravity's axis as the vertical (the cylinder
/// hand-off, gravity -z, was drawn onto z-x, its weight pointing left).
#[test]
fn force_diagrams_draw_gravity_down_the_page() {
    let dir = tmp("gravity-down");
    let svg = dir.join("cylinder.svg");
    let o = grasp(&[
        "plot",
        &example("cylinder_handoff.json"),
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    let views: Vec<&str> = text
        .match_indices("view onto ")
        .map(|(i, _)| text[i..].split('<').next().unwrap().trim())
        .collect();
    assert_eq!(views.len(), 2, "{views:?}");
    assert!(views.iter().all(|v| v.ends_with("-z [m]")), "{views:?}");
}

struct SvgCircle {
    x: f64,
    y: f64,
    r: f64,
    colour: String,
    filled: bool,
}

/// The circles of an SVG written by plotters, in drawing order.
fn svg_circles(svg: &str) -> Vec<SvgCircle> {
    let attr = |line: &str, name: &str| -> String {
        let key = format!(" {name}=\"");
        let start = line.find(&key).map(|i| i + key.len()).unwrap_or(line.len());
        line[start..].split('"').next().unwrap_or("").to_string()
    };
    svg.lines()
        .filter(|l| l.trim_start().starts_with("<circle"))
        .map(|l| {
            let fill = attr(l, "fill");
            let filled = fill != "none";
            SvgCircle {
                x: attr(l, "cx").parse().unwrap(),
                y: attr(l, "cy").parse().unwrap(),
                r: attr(l, "r").parse().unwrap(),
                colour: if filled { fill } else { attr(l, "stroke") },
                filled,
            }
        })
        .collect()
}

/// Bad times and thresholds of the viscoelastic flags are refused naming the flag and the fix,
/// before anything runs.
#[test]
fn bad_viscoelastic_flags_name_the_flag() {
    let scene = example("plate_hold_viscoelastic.json");
    let schedule = example("plate_hold_viscoelastic.schedule.json");
    for (args, flag) in [
        (vec!["solve", &scene, "--at-time", "0"], "--at-time 0"),
        (
            vec!["solve", &scene, "--at-time", "2e9"],
            "--at-time 2000000000",
        ),
        (
            vec![
                "transfer",
                &scene,
                "--schedule",
                &schedule,
                "--margins",
                "--margin-threshold=-1",
            ],
            "--margin-threshold -1",
        ),
    ] {
        let o = grasp(&args);
        let t = text(&o);
        assert!(
            !o.status.success() && t.contains(flag) && t.contains("give"),
            "{t}"
        );
    }
}

/// The long runs' progress bars (hand-offs, batches, margins, a viscoelastic history,
/// studies, a fine patch's solve) are drawn on a terminal's standard error only: piped, as
/// here, standard error carries no bar, with or without `--quiet`, and the run's answer is
/// the same.
#[test]
fn progress_bars_stay_off_a_pipe_and_quiet_changes_nothing_else() {
    // 272 x 272 frictionless: 73,984 unknowns, above the 65,536 of a long solve's display.
    let fine = std::env::temp_dir().join(format!("grasp-cli-fine-{}.json", std::process::id()));
    let hertz = std::fs::read_to_string(example("hertz_sphere_on_flat.json")).unwrap();
    std::fs::write(&fine, hertz.replace("[21, 21]", "[272, 272]")).unwrap();
    let runs: [Vec<String>; 5] = [
        vec!["solve".into(), fine.display().to_string()],
        vec!["margin".into(), example("cube_a.json")],
        vec![
            "study".into(),
            example("hertz_sphere_on_flat.json"),
            "--grids".into(),
            "5,9".into(),
        ],
        vec![
            "solve".into(),
            example("plate_hold_viscoelastic.json"),
            "--at-time".into(),
            "3".into(),
        ],
        vec![
            "transfer".into(),
            example("plate_transfer.json"),
            "--schedule".into(),
            example("plate_transfer.schedule.json"),
        ],
    ];
    for args in runs {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let plain = grasp(&args);
        assert_eq!(plain.status.code(), Some(0), "{args:?}: {}", text(&plain));
        let stderr = String::from_utf8_lossy(&plain.stderr);
        assert!(
            !stderr.contains('\r') && !stderr.contains("eta") && !stderr.contains("in all"),
            "{args:?}: {stderr}"
        );
        let quiet = grasp(&[args.as_slice(), &["--quiet"]].concat());
        assert_eq!(quiet.status.code(), Some(0), "{args:?}: {}", text(&quiet));
        // The answer without what varies between runs: times, and a study row's peak memory
        // (its last columns).
        let table = |o: &std::process::Output| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .filter(|l| !l.contains("time") && !l.contains(" ms") && !l.contains("solves in"))
                .map(|l| match l.starts_with("| ") {
                    true => l.split('|').take(5).collect::<Vec<_>>().join("|"),
                    false => l.to_string(),
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(table(&plain), table(&quiet), "{args:?}");
    }
}

/// What `grasp solve` wrote for an example with `--json` and `--npz` into `dir` (`extra`
/// flags after them): its output, the JSON, and the `.npz`'s bytes.
fn solve_with_files(
    scene: &str,
    dir: &Path,
    extra: &[&str],
) -> (std::process::Output, serde_json::Value, Vec<u8>) {
    let (json, npz) = (dir.join("solution.json"), dir.join("solution.npz"));
    let mut args = vec![
        "solve",
        scene,
        "--json",
        json.to_str().unwrap(),
        "--npz",
        npz.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = grasp(&args);
    assert!(o.status.success(), "{}", text(&o));
    let v = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    (o, v, std::fs::read(&npz).unwrap())
}

#[test]
fn solve_reads_markers_for_a_scene_with_markers() {
    let (o, v, bytes) = solve_with_files(&example("hertz_markers.json"), &tmp("markers"), &[]);
    assert!(
        text(&o).contains("markers (pad surface displacement") && !text(&o).contains("taxels ("),
        "{}",
        text(&o)
    );
    let s = &v["sensors"][0];
    assert_eq!(s["finger"], "pad");
    assert!(s.get("force_n").is_none());
    let moved = s["markers"]["displacement_m"].as_array().unwrap();
    assert_eq!(moved.len(), 81);
    // The central marker sinks by the approach a^2/R = 71.0 um, into the pad.
    let centre = moved[40][0].as_f64().unwrap();
    assert!((centre - 71.0e-6).abs() < 0.2e-6, "{centre}");
    let has = |name: &str| bytes.windows(name.len()).any(|w| w == name.as_bytes());
    assert!(has("pad/markers/displacement_m.npy") && has("pad/markers/position_m.npy"));
    assert!(!has("taxels/"));
}

#[test]
fn solve_reads_taxels_only_for_a_scene_with_a_sensor() {
    let dir = tmp("taxels");
    let (o, v, bytes) = solve_with_files(&example("hertz_taxels.json"), &dir, &[]);
    assert!(
        text(&o).contains("taxels (force crossing each taxel"),
        "{}",
        text(&o)
    );
    let s = &v["sensors"][0];
    assert_eq!(s["finger"], "tip");
    assert_eq!(s["force_n"].as_array().unwrap().len(), 25);
    // The npz's entries are named in the zip's plain text.
    let has = |name: &str| bytes.windows(name.len()).any(|w| w == name.as_bytes());
    assert!(has("tip/taxels/force_n.npy") && has("tip/taxels/centre_m.npy"));
    // Without a sensor: no table, no key, no arrays.
    let (o, v, bytes) = solve_with_files(&example("hertz_sphere_on_flat.json"), &dir, &["--force"]);
    assert!(!text(&o).contains("taxels (force crossing"));
    assert!(v.get("sensors").is_none());
    assert!(!bytes.windows(7).any(|w| w == b"taxels/"));
}
