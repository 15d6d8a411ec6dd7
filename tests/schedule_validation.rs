//! Bad schedules: each class of mistake gives an error naming the path and the fix; a CSV
//! profile drives a finger's load.

use std::path::{Path, PathBuf};

use grasp_transfer::{Command, Schedule};
use serde_json::{json, Value};

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
                && m.contains("t_s, load_n")),
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
