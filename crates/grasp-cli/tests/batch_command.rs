//! `grasp batch` and `grasp sweep` (issue 12): bad lines become `invalid` lines and the batch
//! goes on; a resumed run (after an interruption that left half a line) ends equal to one
//! uninterrupted run; shards merged equal one unsharded run and a missing shard is named; the
//! output does not depend on the number of threads; `sweep --run` equals `sweep` then `batch`;
//! a folder of scene files works like a JSONL file. Results are compared without `time_s`
//! (wall time, the one field that differs between runs).

mod common;

use std::path::Path;

use common::{example, grasp, text, tmp};
use serde_json::Value;

/// The result lines of a file, each without its time.
fn results(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| {
            let mut v: Value = serde_json::from_str(l).unwrap();
            v.as_object_mut().unwrap().remove("time_s");
            v
        })
        .collect()
}

/// A small sweep of cube A (12 variants) as JSONL, plus a bare scene and three bad lines.
fn input(dir: &Path) -> std::path::PathBuf {
    let variants = dir.join("variants.jsonl");
    let o = grasp(&[
        "sweep",
        &example("cube_a.json"),
        "--vary",
        "fingers[*].friction.mu=0.4:1.0:4",
        "--vary",
        "object.weight=2,4,6",
        "--out",
        variants.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let mut body = std::fs::read_to_string(&variants).unwrap();
    let bare = std::fs::read_to_string(example("disc_three_fingers.json")).unwrap();
    body.push_str(&serde_json::to_string(&serde_json::from_str::<Value>(&bare).unwrap()).unwrap());
    body.push('\n');
    body.push_str("{not json\n");
    body.push_str("{\"id\": \"zero-normal\", \"scene\": {\"object\": {}}}\n");
    body.push_str("{\"id\": \"extra\", \"scene\": {}, \"colour\": 1}\n");
    let all = dir.join("all.jsonl");
    std::fs::write(&all, body).unwrap();
    all
}

fn batch(args: &[&str]) -> String {
    let o = grasp(args);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    text(&o)
}

#[test]
fn bad_lines_are_lines_and_threads_do_not_change_the_output() {
    let d = tmp("batch", "lines");
    let all = input(&d);
    let (one, two) = (d.join("one.jsonl"), d.join("two.jsonl"));
    let log = batch(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        one.to_str().unwrap(),
        "--jobs",
        "1",
    ]);
    assert!(
        log.contains("solved 13") && log.contains("invalid 3"),
        "{log}"
    );
    batch(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        two.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    let r = results(&one);
    assert_eq!(r, results(&two));
    assert_eq!(r.len(), 16);
    let ids: Vec<&str> = r.iter().map(|v| v["id"].as_str().unwrap()).collect();
    assert_eq!(ids[0], "cube_a-00");
    assert_eq!(ids[12], "line-13", "a bare scene is named by its line");
    assert_eq!(r[13]["status"], "invalid");
    assert_eq!(r[14]["id"], "zero-normal");
    assert!(r[14]["problems"][0]["path"]
        .as_str()
        .unwrap()
        .starts_with("scene."));
    assert!(r[15]["reason"].as_str().unwrap().contains("colour"));
    // The sweep's parameters ride along.
    assert_eq!(r[1]["vary"]["object.weight"], 4.0);
    // Output exists: refused without --force or --resume.
    let again = grasp(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        one.to_str().unwrap(),
    ]);
    assert_eq!(again.status.code(), Some(1));
}

#[test]
fn a_resumed_run_equals_one_run() {
    let d = tmp("batch", "resume");
    let all = input(&d);
    let (full, part) = (d.join("full.jsonl"), d.join("part.jsonl"));
    batch(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        full.to_str().unwrap(),
    ]);
    // An interrupted run: the first 5 lines and half of the 6th.
    let text = std::fs::read_to_string(&full).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let cut = format!(
        "{}\n{}",
        lines[..5].join("\n"),
        &lines[5][..lines[5].len() / 2]
    );
    std::fs::write(&part, cut).unwrap();
    let log = batch(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        part.to_str().unwrap(),
        "--resume",
    ]);
    assert!(log.contains("5 already in the output"), "{log}");
    assert_eq!(results(&part), results(&full));
}

#[test]
fn shards_merge_into_the_unsharded_run() {
    let d = tmp("batch", "shards");
    let all = input(&d);
    let full = d.join("full.jsonl");
    batch(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        full.to_str().unwrap(),
    ]);
    let mut shards = Vec::new();
    for i in 0..3 {
        let s = d.join(format!("s{i}.jsonl"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_grasp"))
            .args(["batch", all.to_str().unwrap(), "--out", s.to_str().unwrap()])
            // Task i of a Slurm job array numbered from 1.
            .env("SLURM_ARRAY_TASK_ID", (i + 1).to_string())
            .env("SLURM_ARRAY_TASK_MIN", "1")
            .env("SLURM_ARRAY_TASK_COUNT", "3")
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
        shards.push(s);
    }
    let merged = d.join("merged.jsonl");
    let mut args = vec!["batch", "--out", merged.to_str().unwrap(), "--merge"];
    args.extend(shards.iter().map(|s| s.to_str().unwrap()));
    batch(&args);
    assert_eq!(results(&merged), results(&full));
    // A shard missing: named, nothing written.
    let incomplete = d.join("incomplete.jsonl");
    let o = grasp(&[
        "batch",
        "--out",
        incomplete.to_str().unwrap(),
        "--merge",
        shards[0].to_str().unwrap(),
        shards[2].to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("have no result"), "{}", text(&o));
    assert!(!incomplete.exists());
    // A bad shard flag is named.
    let o = grasp(&[
        "batch",
        all.to_str().unwrap(),
        "--out",
        d.join("x").to_str().unwrap(),
        "--shard",
        "3/3",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("--shard"), "{}", text(&o));
}

#[test]
fn sweep_run_and_folders_match_batch() {
    let d = tmp("batch", "sweep");
    let (variants, results_a, results_b) =
        (d.join("v.jsonl"), d.join("a.jsonl"), d.join("b.jsonl"));
    let vary = [
        "--vary",
        "fingers[*].friction.mu=0.5,0.9",
        "--vary",
        "object.weight=1:3:3",
    ];
    let mut args = vec!["sweep", "--out", variants.to_str().unwrap()];
    let scene = example("cube_b.json");
    args.insert(1, &scene);
    args.extend(vary);
    batch(&args);
    batch(&[
        "batch",
        variants.to_str().unwrap(),
        "--out",
        results_a.to_str().unwrap(),
    ]);
    let mut args = vec![
        "sweep",
        &scene,
        "--run",
        "--out",
        results_b.to_str().unwrap(),
    ];
    args.extend(vary);
    batch(&args);
    assert_eq!(results(&results_a), results(&results_b));
    // The same scenes as files of a folder.
    let folder = d.join("scenes");
    std::fs::create_dir_all(&folder).unwrap();
    for (k, line) in std::fs::read_to_string(&variants)
        .unwrap()
        .lines()
        .enumerate()
    {
        let v: Value = serde_json::from_str(line).unwrap();
        std::fs::write(folder.join(format!("s{k}.json")), v["scene"].to_string()).unwrap();
    }
    let from_folder = d.join("f.jsonl");
    batch(&[
        "batch",
        folder.to_str().unwrap(),
        "--out",
        from_folder.to_str().unwrap(),
    ]);
    let forces = |p: &Path| -> Vec<Value> {
        results(p)
            .into_iter()
            .map(|v| v["fingers"].clone())
            .collect()
    };
    assert_eq!(forces(&from_folder), forces(&results_a));
    // A path that reaches nothing is named.
    let o = grasp(&[
        "sweep",
        &scene,
        "--vary",
        "fingers[9].friction.mu=1",
        "--out",
        d.join("z").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("fingers[9].friction.mu"), "{}", text(&o));
}
