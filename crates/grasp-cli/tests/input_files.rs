//! Every file the CLI reads is a regular file within a size limit: scenes,
//! schedules, CSV profiles, direction files, meshes, batch inputs and their folder entries,
//! shard outputs to merge. Each reader is given a device (`/dev/zero`, directly and through a
//! link), a FIFO (which would block a reader that opens it), a folder and, where it applies, a
//! file over the limit; each must refuse quickly with exit 1, naming the file and what it is.
//! An OBJ's `mtllib` naming such a file is never read: the mesh loads.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{example, text, tmp};

/// Runs grasp, failing the test if it has not ended after 60 s (a blocked or runaway read).
fn grasp_within(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_grasp"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run grasp");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("grasp {args:?} did not end within 60 s (blocked on a file?)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Special files in `dir`: (path, words the refusal must contain).
fn specials(dir: &Path, ext: &str) -> Vec<(PathBuf, &'static str)> {
    let link = dir.join(format!("zero-link.{ext}"));
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let folder = dir.join(format!("folder.{ext}"));
    std::fs::create_dir_all(&folder).unwrap();
    let mut out = vec![
        (PathBuf::from("/dev/zero"), "a device, not a regular file"),
        (link, "a device, not a regular file"),
        (folder, "a folder, not a regular file"),
    ];
    let fifo = dir.join(format!("pipe.{ext}"));
    common::fifo(&fifo);
    out.push((fifo, "a FIFO (named pipe), not a regular file"));
    out
}

/// A sparse file one byte over 64 MiB.
fn oversized(dir: &Path, name: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::File::create(&p)
        .unwrap()
        .set_len(64 * 1024 * 1024 + 1)
        .unwrap();
    p
}

fn refused(args: &[&str], words: &str) {
    let o = grasp_within(args);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
    assert!(
        text(&o).contains(words),
        "{args:?}: want `{words}` in {}",
        text(&o)
    );
}

#[test]
fn scene_schedule_and_directions_files_are_regular_and_bounded() {
    let d = tmp("inputs", "json");
    let mut cases = specials(&d, "json");
    cases.push((oversized(&d, "big.json"), "more than the 64 MiB"));
    let plate = example("plate_transfer.json");
    let cube = example("cube_a.json");
    let out = d.join("out.jsonl");
    let out = out.to_str().unwrap();
    for (path, words) in &cases {
        let p = path.to_str().unwrap();
        refused(&["solve", p], words);
        refused(&["transfer", &plate, "--schedule", p], words);
        refused(&["margin", &cube, "--directions", p], words);
        refused(
            &["sweep", p, "--vary", "object.weight=1,2", "--out", out],
            words,
        );
    }
}

#[test]
fn csv_profiles_of_a_schedule_are_regular_and_bounded() {
    let d = tmp("inputs", "csv");
    let mut cases = specials(&d, "csv");
    cases.push((oversized(&d, "big.csv"), "more than the 64 MiB"));
    for (path, words) in &cases {
        let sched = d.join("s.schedule.json");
        let spec = serde_json::json!({
            "time": {"start": 0, "end": 1, "step": 0.5},
            "fingers": {"f1": [{"csv": {"path": path, "time_column": "t", "load_column": "p"}}]}
        });
        std::fs::write(&sched, spec.to_string()).unwrap();
        refused(
            &[
                "transfer",
                &example("plate_transfer.json"),
                "--schedule",
                sched.to_str().unwrap(),
            ],
            words,
        );
    }
}

/// A copy of the mug scene whose mesh is `mesh` (a path relative to `dir`).
fn mug_scene(dir: &Path, mesh: &str) -> PathBuf {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("mug_power_grasp.json")).unwrap())
            .unwrap();
    v["object"]["shape"]["mesh"]["file"] = serde_json::json!(mesh);
    let scene = dir.join(format!("mug-{}.json", mesh.replace('/', "_")));
    std::fs::write(&scene, v.to_string()).unwrap();
    scene
}

#[test]
fn mesh_files_are_regular_and_bounded_and_materials_are_never_read() {
    let d = tmp("inputs", "mesh");
    for ext in ["obj", "stl"] {
        let mut cases = specials(&d, ext);
        let big = format!("big.{ext}");
        cases.push((oversized(&d, &big), "more than the 256 MiB"));
        std::fs::File::create(d.join(&big))
            .unwrap()
            .set_len(256 * 1024 * 1024 + 1)
            .unwrap();
        // (A mesh is named with its extension: /dev/zero itself is an unknown format.)
        for (path, words) in cases.iter().filter(|c| c.0.extension().is_some()) {
            let scene = mug_scene(&d, path.to_str().unwrap());
            refused(&["solve", scene.to_str().unwrap()], words);
        }
    }
    // `mtllib` naming a device, a FIFO, a folder or nothing: the geometry is read, the scene
    // solves as the mug does.
    let mug = std::fs::read_to_string(example("meshes/mug.obj")).unwrap();
    let reference = grasp_within(&["solve", &example("mug_power_grasp.json")]);
    assert_eq!(reference.status.code(), Some(0), "{}", text(&reference));
    for (lib, _) in specials(&d, "mtl") {
        let obj = d.join("mug-with-materials.obj");
        std::fs::write(&obj, format!("mtllib {}\n{mug}", lib.display())).unwrap();
        let scene = mug_scene(&d, "mug-with-materials.obj");
        let o = grasp_within(&["solve", scene.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "mtllib {lib:?}: {}", text(&o));
    }
}

#[test]
fn batch_inputs_folder_entries_and_shards_are_regular_files() {
    let d = tmp("inputs", "batch");
    let cases = specials(&d, "jsonl");
    for (path, words) in &cases {
        let p = path.to_str().unwrap();
        let out = d.join("out.jsonl");
        if path.is_dir() {
            continue; // a folder is a folder of scenes: see below
        }
        refused(&["batch", p, "--out", out.to_str().unwrap()], words);
        refused(
            &["batch", "--merge", p, "--out", out.to_str().unwrap()],
            words,
        );
        assert!(!out.exists());
    }
    // A folder whose *.json entries include a device link and a FIFO: each is an invalid line
    // saying what it is; the real scene is solved.
    let folder = d.join("scenes");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::copy(example("cube_a.json"), folder.join("a.json")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", folder.join("b.json")).unwrap();
    common::fifo(&folder.join("c.json"));
    let out = d.join("from-folder.jsonl");
    let o = grasp_within(&[
        "batch",
        folder.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines[0]["status"], "solved");
    assert_eq!(lines[1]["status"], "invalid");
    assert!(
        lines[1]["reason"].as_str().unwrap().contains("a device"),
        "{}",
        lines[1]
    );
    assert!(
        lines[2]["reason"].as_str().unwrap().contains("a FIFO"),
        "{}",
        lines[2]
    );
}
