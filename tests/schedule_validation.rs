//! Bad schedules: each class of mistake gives an error naming the path and the fix; a CSV
//! profile drives a finger's load.

use std::path::{Path, PathBuf};

use grasp_transfer::{Command, Schedule};
use serde_json::{json, Value};

mod support;

fn names() -> Vec<String> {
    ["f1", "f2", "f3", "f4"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-schedule-test-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn problems(v: &Value, dir: &Path) -> Vec<String> {
    match Schedule::from_json_str(&v.to_string(), &names(), dir) {
        Ok(_) => panic!("schedule accepted"),
        Err(e) => e.problems().iter().map(|p| p.to_string()).collect(),
    }
}

fn assert_problem(v: &Value, path: &str, words: &str) {
    let p = problems(v, Path::new("."));
    assert!(
        p.iter()
            .any(|m| m.starts_with(path) && m.contains(words) && m.contains("fix")),
        "want {path} / {words}: {p:#?}"
    );
}

fn base() -> Value {
    json!({"time": {"start": 0, "end": 1, "step": 0.5},
           "fingers": {"f1": [{"ramp": {"keyframes": [[0, 2.0], [1, 0.0]]}}]}})
}

#[test]
fn unknown_finger() {
    let mut v = base();
    v["fingers"]["f9"] = json!([{"held": {}}]);
    assert_problem(&v, "fingers.f9", "no finger named `f9`");
}

#[test]
fn negative_load() {
    let mut v = base();
    v["fingers"]["f1"][0]["ramp"]["keyframes"][1] = json!([1, -3.0]);
    assert_problem(&v, "fingers.f1[0].ramp.keyframes[1]", "-3 N");
}

#[test]
fn times_not_increasing() {
    let mut v = base();
    v["time"] = json!({"times": [0, 0.5, 0.5, 1.0]});
    assert_problem(&v, "time.times[2]", "not after");
    let mut v = base();
    v["fingers"]["f1"][0]["ramp"]["keyframes"] = json!([[0, 1.0], [0, 2.0]]);
    assert_problem(&v, "fingers.f1[0].ramp.keyframes[1]", "not after");
    let mut v = base();
    v["time"] = json!({"start": 2, "end": 1, "step": 0.1});
    assert_problem(&v, "time.end", "before the start");
    let mut v = base();
    v["fingers"]["f2"] = json!([{"held": {"until": 5}}, {"held": {"until": 2}}]);
    assert_problem(&v, "fingers.f2[1]", "before the previous phase");
}

#[test]
fn csv_columns_missing() {
    let dir = tmpdir("cols");
    std::fs::write(dir.join("p.csv"), "t_s,load_n\n0,1\n1,2\n").unwrap();
    let mut v = base();
    v["fingers"]["f2"] =
        json!([{"csv": {"path": "p.csv", "time_column": "time", "load_column": "load_n"}}]);
    let p = problems(&v, &dir);
    assert!(
        p.iter()
            .any(|m| m.starts_with("fingers.f2[0].csv.time_column")
                && m.contains("`time`")
                && m.contains("`t_s`, `load_n`")),
        "{p:#?}"
    );
    let mut v = base();
    v["fingers"]["f2"] =
        json!([{"csv": {"path": "missing.csv", "time_column": "t_s", "load_column": "load_n"}}]);
    let p = problems(&v, &dir);
    assert!(
        p.iter()
            .any(|m| m.starts_with("fingers.f2[0].csv.path") && m.contains("cannot read")),
        "{p:#?}"
    );
}

#[test]
fn unknown_fields_and_phases() {
    let mut v = base();
    v["fingers"]["f1"] = json!([{"squeeze": {}}]);
    let p = problems(&v, Path::new("."));
    assert!(p[0].starts_with("fingers.f1[0]"), "{p:?}");
    let mut v = base();
    v["tiem"] = json!(1);
    assert!(problems(&v, Path::new("."))[0].contains("tiem"));
}

#[test]
fn csv_profile_and_easings_drive_the_load() {
    let dir = tmpdir("ok");
    std::fs::write(dir.join("p.csv"), "t_s,load_n\n0,4\n1,0\n").unwrap();
    let v = json!({"time": {"times": [0, 0.25, 0.5, 1.0]},
    "fingers": {
        "f1": [{"csv": {"path": "p.csv", "time_column": "t_s", "load_column": "load_n"}}],
        "f2": [{"ramp": {"keyframes": [[0, 0.0], [1, 2.0]], "easing": "smoothstep"}}],
        "f3": [{"ramp": {"keyframes": [[0, 1.0], [1, 3.0]], "easing": "step"}}]
    }});
    let s = Schedule::from_json_str(&v.to_string(), &names(), &dir).unwrap();
    assert_eq!(s.command(0, 0.25, 0.0, Command::Held), Command::Load(3.0));
    assert_eq!(s.command(0, 1.0, 0.0, Command::Held), Command::Released);
    assert_eq!(s.command(1, 0.5, 0.0, Command::Held), Command::Load(1.0));
    assert_eq!(s.command(2, 0.5, 0.0, Command::Held), Command::Load(1.0));
    assert_eq!(s.command(2, 1.0, 0.0, Command::Held), Command::Load(3.0));
    // An unscheduled finger keeps the scene's command.
    assert_eq!(s.command(3, 0.5, 0.0, Command::Held), Command::Held);
}

#[test]
fn step_counts_are_bounded_without_overflow() {
    let mut v = base();
    v["time"] = json!({"start": 0, "end": 1e308, "step": 0.1});
    assert_problem(&v, "time.end", "outside [0e0, 1e9] s");
    let mut v = base();
    v["time"] = json!({"start": 0, "end": 1e9, "step": 1e-6});
    assert_problem(&v, "time.step", "more than 1000000");
    // Steps shorter than a nanosecond (the logs' unit), a span's or between listed times:
    // a step of 5e-324 s once broke the viscoelastic step with non-finite program data.
    for step in [5e-324, 1e-300, 9.9e-10] {
        let mut v = base();
        v["time"] = json!({"start": 0, "end": 1e-8, "step": step});
        assert_problem(&v, "time.step", "give a step of at least 1e-9 s");
        let mut v = base();
        v["time"] = json!({"times": [0.0, step, 0.5]});
        assert_problem(&v, "time.times[1]", "space the times at least 1e-9 s apart");
    }
    let mut v = base();
    v["time"] = json!({"start": 0, "end": 1e6, "step": 1});
    assert_problem(&v, "time.step", "gives 1.000e6 steps");
    let mut v = base();
    let times: Vec<f64> = (0..2_000_001).map(|i| i as f64 * 1e-3).collect();
    v["time"] = json!({ "times": times });
    assert_problem(&v, "time.times", "lists 2000001 times, more than 1000000");
}

#[test]
fn loads_and_times_outside_the_physical_range() {
    let mut v = base();
    v["fingers"]["f1"][0]["ramp"]["keyframes"][0] = json!([0, 1e308]);
    assert_problem(
        &v,
        "fingers.f1[0].ramp.keyframes[0]",
        "neither 0 nor in [1e-15, 1e7] N",
    );
    let mut v = base();
    v["fingers"]["f2"] = json!([{"held": {"until": 1e300}}]);
    assert_problem(&v, "fingers.f2[0].held.until", "outside");
    let dir = tmpdir("range");
    std::fs::write(dir.join("big.csv"), "t_s,load_n\n0,1\n1,1e308\n").unwrap();
    let mut v = base();
    v["fingers"]["f2"] =
        json!([{"csv": {"path": "big.csv", "time_column": "t_s", "load_column": "load_n"}}]);
    let p = problems(&v, &dir);
    assert!(
        p.iter().any(
            |m| m.starts_with("fingers.f2[0].csv.path (row 3 of big.csv)")
                && m.contains("neither 0 nor")
        ),
        "{p:#?}"
    );
}

#[test]
fn duplicate_finger_names_in_a_schedule() {
    let text = r#"{"time": {"times": [0, 1]},
        "fingers": {"f1": [{"held": {}}], "f2": [{"held": {}}], "f1": [{"ramp": {"keyframes": [[0, 1]]}}]}}"#;
    let e = Schedule::from_json_str(text, &names(), Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.contains("fingers: `f1` is given twice"), "{e}");
}

#[test]
fn trailing_data_after_the_schedule() {
    let text = format!("{}\n{}", base(), base());
    let e = Schedule::from_json_str(&text, &names(), Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.contains("trailing characters at line 2 column 1"), "{e}");
}

#[test]
fn nested_schedule_errors_name_the_inner_field() {
    let cases = [
        (
            json!({"start": "0", "end": 1, "step": 0.5}),
            None,
            "time.start: invalid type: string",
        ),
        (
            json!({"times": [0, "1"]}),
            None,
            "time.times[1]: invalid type: string",
        ),
        (
            json!({"start": 0, "end": 1, "step": 0.5}),
            Some(json!([{"ramp": {"keyframes": [[0, "lots"]]}}])),
            "fingers.f1[0].ramp.keyframes[0][1]: expected a load in newtons or \"current\"; found the string \"lots\"",
        ),
        (
            json!({"start": 0, "end": 1, "step": 0.5}),
            Some(json!([{"held": {"until": "later"}}])),
            "fingers.f1[0].held.until: invalid type: string",
        ),
        (
            json!({"stop": 1}),
            None,
            "time: expected {\"start\", \"end\", \"step\"} or {\"times\": [...]}; found an object with the key(s) `stop`",
        ),
    ];
    for (time, f1, want) in cases {
        let mut v = base();
        v["time"] = time;
        if let Some(f) = f1 {
            v["fingers"]["f1"] = f;
        }
        let p = problems(&v, Path::new("."));
        assert!(p[0].starts_with(want), "want `{want}`, got {p:#?}");
    }
}

/// Runs `f` on a thread and fails the test if it does not return within `secs`.
fn within<T: Send + 'static>(secs: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || tx.send(f()).ok());
    rx.recv_timeout(std::time::Duration::from_secs(secs))
        .expect("did not return in time (blocked on the file?)")
}

#[test]
fn csv_profiles_only_from_regular_files_of_bounded_size() {
    let dir = tmpdir("special");
    let fifo = dir.join("pipe.csv");
    support::fifo(&fifo);
    let mut cases = vec![("/dev/zero".to_string(), "not a regular file")];
    cases.push((dir.display().to_string(), "not a regular file"));
    cases.push((fifo.display().to_string(), "not a regular file"));
    let big = dir.join("big.csv");
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(64 * 1024 * 1024 + 1).unwrap();
    cases.push((big.display().to_string(), "more than the 64 MiB"));
    for (path, words) in cases {
        let mut v = base();
        v["fingers"]["f2"] =
            json!([{"csv": {"path": path, "time_column": "t_s", "load_column": "load_n"}}]);
        let p = within(10, move || problems(&v, Path::new("/")));
        assert!(
            p.iter()
                .any(|m| m.starts_with("fingers.f2[0].csv.path") && m.contains(words)),
            "{p:#?}"
        );
    }
}

/// The longest run of digits in `text` (a number written out in full has 309 for 1e308).
fn longest_digit_run(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// Extreme values in every numeric field class of a schedule (span times and step, explicit
/// times, keyframe times and loads, held until, external wrench keyframes) are quoted in
/// exponent form: no message holds a run of more than 17 digits (the most a shortest
/// round-trip `f64` needs). Every case with a huge value is refused.
#[test]
fn extreme_numbers_are_quoted_in_exponent_form() {
    let huge = [1e308, -1e308, 1e300, 5e-324, -1e-300];
    let mut refused = 0;
    for x in huge {
        let mut cases = Vec::new();
        let mut v = base();
        v["time"] = json!({"start": x, "end": x, "step": x});
        cases.push(v);
        let mut v = base();
        v["time"] = json!({"times": [0, x, 1e308]});
        cases.push(v);
        let mut v = base();
        v["fingers"]["f1"][0]["ramp"]["keyframes"] = json!([[x, x], [1e308, 2.0]]);
        cases.push(v);
        let mut v = base();
        v["fingers"]["f2"] = json!([{"held": {"until": x}}, {"held": {"until": -x}}]);
        cases.push(v);
        let mut v = base();
        v["external"] = json!({"ramp": {"keyframes": [[x, {"force": [x, 0, 0]}], [-x, {"torque": [0, x, 0]}]]}});
        cases.push(v);
        for v in cases {
            // A tiny positive value can be a valid time (a span from 5e-324 s to itself).
            if let Err(e) = Schedule::from_json_str(&v.to_string(), &names(), Path::new(".")) {
                refused += 1;
                for p in e.problems() {
                    let p = p.to_string();
                    assert!(longest_digit_run(&p) <= 17, "{x:e}: {p}");
                }
            }
        }
    }
    assert!(refused >= 3 * 5, "{refused} refused");
}

/// A wrench CSV that names a missing column (or a file that is missing, or no column at all)
/// is one problem at `external.csv`, not a second "has no keyframe" besides it.
#[test]
fn a_bad_external_csv_is_one_problem() {
    let dir = tmpdir("wrench");
    std::fs::write(dir.join("w.csv"), "t_s,fz_n\n0,0\n1,2\n").unwrap();
    let csv = |path: &str, force: Value| {
        let mut v = base();
        v["external"] = json!({"csv": {"path": path, "time_column": "t_s",
                                        "force_columns": force}});
        v
    };
    for (v, at, words) in [
        (
            csv("w.csv", json!([null, null, "fy_n"])),
            "external.csv.columns",
            "`fy_n`",
        ),
        (
            csv("gone.csv", json!([null, null, "fz_n"])),
            "external.csv.path",
            "gone.csv",
        ),
        (
            csv("w.csv", json!([null, null, null])),
            "external.csv",
            "no force or torque",
        ),
    ] {
        let p = problems(&v, &dir);
        assert_eq!(p.len(), 1, "{p:#?}");
        assert!(p[0].starts_with(at) && p[0].contains(words), "{p:#?}");
    }
    let mut v = csv("w.csv", json!([null, null, "fz_n"]));
    std::fs::write(dir.join("w.csv"), "t_s,fz_n\n0,0\n1,abc\n").unwrap();
    let p = problems(&v, &dir);
    assert_eq!(p.len(), 1, "{p:#?}");
    assert!(
        p[0].contains("the load `abc` is not a finite number"),
        "{p:#?}"
    );
    v["external"]["csv"]["time_column"] = json!("time");
    let p = problems(&v, &dir);
    assert!(
        p.len() == 1 && p[0].contains("(columns: `t_s`, `fz_n`)"),
        "{p:#?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Approach ramps and holds: a bad approach or duration is named with the fix; a
/// hold keeps the phase before's last command for its duration, then the next phase runs.
#[test]
fn approach_ramps_and_holds() {
    let mut v = base();
    v["fingers"] = json!({"f1": [{"approach": {"keyframes": [[0, 0.001], [1, 2.0]]}}]});
    // Negative approaches withdraw the finger (a jaw opened), up to 1 m either way.
    assert_problem(
        &v,
        "fingers.f1[0].approach.keyframes[1]",
        "outside [-1, 1] m",
    );
    v["fingers"]["f1"][0]["approach"]["keyframes"][1][1] = json!(-1.5);
    assert_problem(
        &v,
        "fingers.f1[0].approach.keyframes[1]",
        "outside [-1, 1] m",
    );
    let mut v = base();
    v["fingers"] =
        json!({"f1": [{"approach": {"keyframes": [[0, 0.001]]}}, {"hold": {"duration_s": -2}}]});
    assert_problem(&v, "fingers.f1[1].hold.duration_s", "is -2 s");
    // The fix names the range, its upper bound included.
    v["fingers"]["f1"][1]["hold"]["duration_s"] = json!(2e9);
    assert_problem(&v, "fingers.f1[1].hold.duration_s", "in (0, 1e9]");
    let v = json!({"time": {"start": 0, "end": 4, "step": 0.5},
        "fingers": {"f1": [
            {"approach": {"keyframes": [[0, 0.0], [1, 0.002]]}},
            {"hold": {"duration_s": 2}},
            {"ramp": {"keyframes": [[3.5, 5.0]]}}]}});
    let s = Schedule::from_json_str(&v.to_string(), &names(), Path::new(".")).unwrap();
    let at = |t: f64| s.command(0, t, 0.0, Command::Held);
    assert_eq!(at(0.0), Command::Held);
    assert_eq!(at(0.5), Command::Approach(0.001));
    assert_eq!(at(2.0), Command::Approach(0.002));
    assert_eq!(at(3.0), Command::Approach(0.002));
    assert_eq!(at(3.5), Command::Load(5.0));
}
