//! `grasp margin` and `grasp solve --sensitivities` as a user runs them: outputs written and
//! consistent with the table, bad input named, existing files kept.

mod common;

use common::{example, grasp, text, tmp};

#[test]
fn margin_writes_json_plot_and_recording_and_names_the_smallest() {
    let d = tmp("margin", "outputs");
    let (json, svg, rrd) = (d.join("m.json"), d.join("m.svg"), d.join("m.rrd"));
    let o = grasp(&[
        "margin",
        &example("plate_handoff_coulomb.json"),
        "--json",
        json.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
        "--rrd",
        rrd.to_str().unwrap(),
    ]);
    let out = text(&o);
    assert_eq!(o.status.code(), Some(0), "{out}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let dirs = report["directions"].as_array().unwrap();
    assert_eq!(dirs.len(), 6, "planar: the six axis directions");
    // The commanded pads cannot react to a push along their axis (+-x): listed apart; the
    // smallest margin is over the other directions.
    let unresisted: Vec<u64> = report["unresisted"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    assert_eq!(unresisted, [0, 1]);
    let smallest = report["smallest"].as_u64().unwrap() as usize;
    let min = dirs
        .iter()
        .enumerate()
        .filter(|(i, _)| !unresisted.contains(&(*i as u64)))
        .map(|(_, d)| d["margin_n"].as_f64().unwrap_or(f64::INFINITY))
        .fold(f64::INFINITY, f64::min);
    assert!(min > 0.0 && min.is_finite());
    assert_eq!(dirs[smallest]["margin_n"].as_f64().unwrap(), min);
    assert!(out.contains("smallest margin"), "{out}");
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(picture.starts_with("<svg"));
    // The polar panel names its axes: the plate's plane of motion is x-z (e2 = -z), drawn
    // with +z up (it was drawn -z up: a push upwards plotted downwards).
    assert!(picture.contains("+x right, +z up"), "{picture}");
    assert!(!picture.contains("-z up"), "{picture}");
    // A bar per direction (plus the background), the smallest in red.
    assert!(picture.matches("<rect").count() > dirs.len(), "{picture}");
    assert!(picture.contains("#D62728"), "{picture}");
    // Rerun's own CLI (installed by scripts/test.sh) verifies the recording.
    if let Some(cli) = common::rerun_cli() {
        let v = std::process::Command::new(cli)
            .args(["rrd", "verify"])
            .arg(&rrd)
            .env("CI", "1")
            .output()
            .expect("run the rerun CLI");
        assert!(v.status.success(), "rerun rrd verify: {}", text(&v));
    }
    // Written files are not overwritten without --force.
    let again = grasp(&[
        "margin",
        &example("plate_handoff_coulomb.json"),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(again.status.code(), Some(1), "{}", text(&again));
}

#[test]
fn margin_directions_from_a_file_and_bad_ones_named() {
    let d = tmp("margin", "directions");
    let file = d.join("dirs.json");
    std::fs::write(&file, r#"[{"force": [0, 0, -2]}, {"torque": [0, 1, 0]}]"#).unwrap();
    let o = grasp(&[
        "margin",
        &example("plate_handoff_coulomb.json"),
        "--directions",
        file.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    // Down: 2 mu P - W = 2 x 0.4 x 8 - 4.448 = 1.952 N, bracketed to 1e-3 (and the discrete
    // pad's all-slip onset, 0.1 % early at nu = 0.45).
    assert!(text(&o).contains("1.95"), "{}", text(&o));
    std::fs::write(&file, r#"[{"force": [0, 0, 0]}]"#).unwrap();
    let bad = grasp(&[
        "margin",
        &example("plate_handoff_coulomb.json"),
        "--directions",
        file.to_str().unwrap(),
    ]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(text(&bad).contains("directions[0]"), "{}", text(&bad));
    for (flag, value) in [
        ("--directions", "0"),
        ("--tolerance", "0"),
        ("--length", "-1"),
    ] {
        let arg = format!("{flag}={value}");
        let o = grasp(&["margin", &example("cube_a.json"), &arg]);
        assert_eq!(o.status.code(), Some(1), "{flag} {value}");
        assert!(text(&o).contains(flag), "{flag}: {}", text(&o));
    }
}

#[test]
fn solve_sensitivities_print_and_write() {
    let d = tmp("margin", "sensitivities");
    let json = d.join("s.json");
    let o = grasp(&[
        "solve",
        &example("plate_handoff_coulomb.json"),
        "--sensitivities",
        "--json",
        json.to_str().unwrap(),
    ]);
    let out = text(&o);
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(out.contains("sensitivities at the active set"), "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let s = &v["sensitivities"];
    let names: Vec<&str> = s["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "force_e1",
            "force_e2",
            "torque_normal",
            "load:f1",
            "load:f2",
            "load:f3",
            "load:f4",
            "squeeze"
        ]
    );
    // Raising one commanded pad alone leaves no equilibrium: said, not a number.
    assert!(out.contains("load:f1: no derivative"), "{out}");
    assert_eq!(s["fingers"].as_array().unwrap().len(), 4);
}
