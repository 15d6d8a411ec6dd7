//! `grasp batch` and `grasp sweep`: bad lines become `invalid` lines and the batch
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

/// Scenes that each fit `--max-memory` but not two at once (cube A's estimate is 1.0 MiB, the
/// limit 1.5 MiB) run one after the other on four workers: every scene is solved, the output
/// equal to one worker's (the workers once ran them all at once and the batch
/// aborted out of memory; `memory_budget.rs` tests that the admitted bytes never exceed the
/// limit).
#[test]
fn scenes_that_fit_the_memory_limit_only_one_at_a_time_all_solve() {
    let d = tmp("batch", "budget");
    let all = input(&d);
    let (one, four) = (d.join("one.jsonl"), d.join("four.jsonl"));
    for (out, jobs) in [(&one, "1"), (&four, "4")] {
        let log = batch(&[
            "batch",
            all.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--jobs",
            jobs,
            "--max-memory",
            "1.5M",
        ]);
        assert!(log.contains("solved 13"), "{log}");
    }
    assert_eq!(results(&one), results(&four));
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

/// The bytes of a file (empty if missing).
fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_default()
}

/// Hidden files a run left beside its output (temporary or lock files).
fn hidden(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".grasp-"))
        .collect()
}

/// A sweep of `n` variants of cube A (ids `<stem>-k`) as JSONL in `dir`.
fn variants(dir: &Path, stem: &str, n: usize) -> std::path::PathBuf {
    let scene = dir.join(format!("{stem}.json"));
    std::fs::copy(example("cube_a.json"), &scene).unwrap();
    let out = dir.join(format!("{stem}.jsonl"));
    let o = grasp(&[
        "sweep",
        scene.to_str().unwrap(),
        "--vary",
        &format!("object.weight=1:5:{n}"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    out
}

#[test]
fn resume_checks_the_whole_output_first_and_changes_nothing_otherwise() {
    let d = tmp("batch", "resume-check");
    let input = variants(&d, "cube", 6);
    let other = variants(&d, "other", 4);
    let other_out = d.join("other-results.jsonl");
    batch(&[
        "batch",
        other.to_str().unwrap(),
        "--out",
        other_out.to_str().unwrap(),
    ]);
    let ours = d.join("ours.jsonl");
    batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        ours.to_str().unwrap(),
        "--shard",
        "1/2",
    ]);
    let scene = std::fs::read_to_string(example("cube_a.json")).unwrap();
    let ours_text = std::fs::read_to_string(&ours).unwrap();
    let cases: Vec<(&str, Vec<u8>, Vec<&str>)> = vec![
        ("a scene file", scene.clone().into_bytes(), vec![]),
        (
            "a scene without a newline",
            scene.trim_end().as_bytes().to_vec(),
            vec![],
        ),
        ("one line of JSON", b"{\"object\": {}}\n".to_vec(), vec![]),
        ("another input's results", bytes(&other_out), vec![]),
        (
            "results of another shard",
            ours_text.clone().into_bytes(),
            vec!["--shard", "0/2"],
        ),
        (
            "results then garbage",
            format!("{ours_text}garbage").into_bytes(),
            vec!["--shard", "1/2"],
        ),
        ("a line that is not UTF-8", b"\xff\xfe\n".to_vec(), vec![]),
    ];
    for (what, content, extra) in cases {
        let out = d.join("out.jsonl");
        std::fs::write(&out, &content).unwrap();
        let mut args = vec![
            "batch",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.push("--resume");
        args.extend(extra);
        let o = grasp(&args);
        assert_eq!(o.status.code(), Some(1), "{what}: {}", text(&o));
        assert!(
            text(&o).contains("nothing was changed"),
            "{what}: {}",
            text(&o)
        );
        assert_eq!(bytes(&out), content, "{what}: the output changed");
    }
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}

#[test]
fn a_run_cut_inside_a_character_resumes_to_the_whole_run() {
    let d = tmp("batch", "resume-utf8");
    let input = variants(&d, "würfel", 6);
    let (full, part) = (d.join("full.jsonl"), d.join("part.jsonl"));
    batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        full.to_str().unwrap(),
    ]);
    let b = bytes(&full);
    // Three lines, then the fourth cut between the two bytes of its "ü".
    let starts: Vec<usize> = std::iter::once(0)
        .chain(
            b.iter()
                .enumerate()
                .filter(|(_, c)| **c == b'\n')
                .map(|(i, _)| i + 1),
        )
        .collect();
    let u = starts[3] + b[starts[3]..].iter().position(|c| *c == 0xc3).unwrap();
    std::fs::write(&part, &b[..u + 1]).unwrap();
    let log = batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        part.to_str().unwrap(),
        "--resume",
    ]);
    assert!(log.contains("3 already in the output"), "{log}");
    assert_eq!(results(&part), results(&full));
}

#[test]
fn duplicate_ids_are_refused_before_anything_is_written() {
    let d = tmp("batch", "dup");
    let scene: Value =
        serde_json::from_str(&std::fs::read_to_string(example("cube_a.json")).unwrap()).unwrap();
    let line = |id: &str| serde_json::json!({"id": id, "scene": scene}).to_string();
    let bare = scene.to_string();
    // Lines 1..6: a, b, a, a bare scene (line-4), b, and an explicit "line-4".
    let body = [
        line("a"),
        line("b"),
        line("a"),
        bare,
        line("b"),
        line("line-4"),
    ]
    .join("\n");
    let input = d.join("dup.jsonl");
    std::fs::write(&input, body).unwrap();
    let out = d.join("out.jsonl");
    std::fs::write(&out, "precious").unwrap();
    for extra in [vec!["--force"], vec!["--resume"]] {
        let mut args = vec![
            "batch",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = grasp(&args);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        let t = text(&o);
        assert!(
            t.contains("`a` on lines 1, 3")
                && t.contains("`b` on lines 2, 5")
                && t.contains("`line-4` on lines 4, 6"),
            "{t}"
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "precious");
    }
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}

#[test]
fn a_line_that_is_not_utf8_is_an_invalid_line_like_any_other() {
    let d = tmp("batch", "utf8");
    let good = std::fs::read_to_string(variants(&d, "c", 2)).unwrap();
    let mut body = good.lines().next().unwrap().as_bytes().to_vec();
    body.extend_from_slice(b"\n{\"id\": \"caf\xe9\", \"scene\": {}}\n\xff\n");
    body.extend_from_slice(good.lines().nth(1).unwrap().as_bytes());
    body.push(b'\n');
    let input = d.join("mixed.jsonl");
    std::fs::write(&input, body).unwrap();
    let out = d.join("out.jsonl");
    let log = batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        log.contains("solved 2") && log.contains("invalid 2"),
        "{log}"
    );
    let r = results(&out);
    assert_eq!(r.len(), 4);
    assert_eq!(
        (r[1]["id"].as_str(), r[2]["id"].as_str()),
        (Some("line-2"), Some("line-3"))
    );
    for k in [1, 2] {
        assert!(
            r[k]["reason"]
                .as_str()
                .unwrap()
                .contains("is not UTF-8 text"),
            "{}",
            r[k]
        );
    }
    assert_eq!(
        (r[0]["status"].as_str(), r[3]["status"].as_str()),
        (Some("solved"), Some("solved"))
    );
}

#[test]
fn merge_checks_that_the_shards_cover_the_input_exactly_once() {
    let d = tmp("batch", "merge-cover");
    let input = variants(&d, "m", 5);
    let other = variants(&d, "n", 3);
    let shard = |i: usize, n: usize, input: &Path, name: &str| {
        let s = d.join(name);
        batch(&[
            "batch",
            input.to_str().unwrap(),
            "--out",
            s.to_str().unwrap(),
            "--shard",
            &format!("{i}/{n}"),
        ]);
        s
    };
    let (s0, s1) = (
        shard(0, 2, &input, "s0.jsonl"),
        shard(1, 2, &input, "s1.jsonl"),
    );
    let foreign = shard(1, 2, &other, "foreign.jsonl");
    let (e1, e2) = (d.join("e1.jsonl"), d.join("e2.jsonl"));
    std::fs::write(&e1, "").unwrap();
    std::fs::write(&e2, "\n\n").unwrap();
    let cut = d.join("cut.jsonl");
    let s1_text = std::fs::read_to_string(&s1).unwrap();
    std::fs::write(&cut, &s1_text[..s1_text.len() - 10]).unwrap();
    let cases: Vec<(Vec<&Path>, &str)> = vec![
        (vec![&e1, &e2], "hold no result line"),
        (vec![&s0, &s0], "appears twice"),
        (vec![&s0, &s1, &s1], "appears twice"),
        (vec![&s0, &foreign], "different inputs"),
        (vec![&s0, &cut], "is unfinished"),
        (vec![&s0], "have no result (positions 1, 3)"),
        (vec![&s1, &e1], "have no result (positions 0, 2, 4)"),
    ];
    for (shards, words) in cases {
        let out = d.join("merged.jsonl");
        let mut args = vec!["batch", "--out", out.to_str().unwrap(), "--merge"];
        args.extend(shards.iter().map(|s| s.to_str().unwrap()));
        let o = grasp(&args);
        assert_eq!(o.status.code(), Some(1), "{shards:?}: {}", text(&o));
        assert!(text(&o).contains(words), "{shards:?}: {}", text(&o));
        assert!(!out.exists());
    }
    // An empty shard beside the complete ones is no harm.
    let out = d.join("merged.jsonl");
    batch(&[
        "batch",
        "--out",
        out.to_str().unwrap(),
        "--merge",
        s1.to_str().unwrap(),
        e1.to_str().unwrap(),
        s0.to_str().unwrap(),
    ]);
    let whole = d.join("whole.jsonl");
    batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
    ]);
    assert_eq!(results(&out), results(&whole));
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}

#[test]
fn stepped_slurm_arrays_map_to_shards_and_sparse_ones_are_refused() {
    let d = tmp("batch", "slurm-step");
    let input = variants(&d, "s", 7);
    let run = |id: usize, vars: &[(&str, &str)], out: &Path| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_grasp"));
        c.args([
            "batch",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        c.env("SLURM_ARRAY_TASK_ID", id.to_string());
        for (k, v) in vars {
            c.env(k, v);
        }
        c.output().unwrap()
    };
    // --array=3-11:4 (ids 3, 7, 11): MIN 3, MAX 11, STEP 4, COUNT 3.
    let vars = [
        ("SLURM_ARRAY_TASK_MIN", "3"),
        ("SLURM_ARRAY_TASK_MAX", "11"),
        ("SLURM_ARRAY_TASK_STEP", "4"),
        ("SLURM_ARRAY_TASK_COUNT", "3"),
    ];
    let mut shards = Vec::new();
    for id in [3, 7, 11] {
        let out = d.join(format!("shard-{id}.jsonl"));
        let o = run(id, &vars, &out);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
        shards.push(out);
    }
    let merged = d.join("merged.jsonl");
    let mut args = vec!["batch", "--out", merged.to_str().unwrap(), "--merge"];
    args.extend(shards.iter().map(|s| s.to_str().unwrap()));
    batch(&args);
    let whole = d.join("whole.jsonl");
    batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
    ]);
    assert_eq!(results(&merged), results(&whole));
    // --array=1,3,8 (3 ids from 1 to 8, no step): cannot be mapped; nor an id off the step.
    let sparse = [
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_MAX", "8"),
        ("SLURM_ARRAY_TASK_COUNT", "3"),
    ];
    for (id, vars, words) in [
        (3, &sparse[..], "evenly spaced"),
        (5, &vars[..], "is not one of the array's ids"),
    ] {
        let out = d.join("x.jsonl");
        let o = run(id, vars, &out);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(text(&o).contains(words), "{}", text(&o));
        assert!(!out.exists());
    }
}

#[test]
fn jobs_is_bounded_at_the_command_line() {
    let d = tmp("batch", "jobs");
    let input = variants(&d, "j", 2);
    let out = d.join("out.jsonl");
    let scene = example("cube_a.json");
    for bad in ["257", "20000", "100000", "-1", "many"] {
        let jobs = format!("--jobs={bad}");
        for args in [
            vec![
                "batch",
                input.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                &jobs,
            ],
            vec![
                "sweep",
                &scene,
                "--vary",
                "object.weight=1,2",
                "--run",
                "--out",
                out.to_str().unwrap(),
                &jobs,
            ],
        ] {
            let o = grasp(&args);
            assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
            assert!(
                text(&o).contains("--jobs") && text(&o).contains("to 256"),
                "{args:?}: {}",
                text(&o)
            );
            assert!(!out.exists());
        }
    }
    batch(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "256",
    ]);
    assert_eq!(results(&out).len(), 2);
}
