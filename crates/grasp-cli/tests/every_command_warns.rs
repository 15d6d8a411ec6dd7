//! Every command that solves shows the warnings of its solves, each once with the solves it
//! applies to (`transfer`, `plan`, `margin`, `plot`, `study`), and labels a peak pressure at a
//! sharp edge as grid-dependent where it prints one (`solve`, `study`).

mod common;
use common::{example, grasp, text};

fn tmp(tag: &str) -> std::path::PathBuf {
    common::tmp("warns", tag)
}

/// The text's lines starting with `warning: ` followed by `prefix`, each with the line under it.
fn warnings_with_steps<'a>(t: &'a str, prefix: &str) -> Vec<(&'a str, &'a str)> {
    let lines: Vec<&str> = t.lines().collect();
    lines
        .windows(2)
        .filter(|w| w[0].starts_with(&format!("warning: {prefix}")))
        .map(|w| (w[0], w[1]))
        .collect()
}

#[test]
fn transfer_prints_each_warning_once_with_the_steps_it_applies_to() {
    let dir = tmp("transfer");
    let csv = dir.join("h.csv");
    let o = grasp(&[
        "transfer",
        &example("cylinder_handoff.json"),
        "--schedule",
        &example("cylinder_handoff.schedule.json"),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    // Gripper A's jaws press beyond the half-space's small slopes while they squeeze hard:
    // the warning once per jaw, its figures' ranges, and the steps (18 of 41).
    for jaw in ["fingers[0] `a1`", "fingers[1] `a2`"] {
        let found = warnings_with_steps(&t, jaw);
        assert_eq!(found.len(), 1, "{t}");
        let (warning, steps) = found[0];
        assert!(
            warning.contains("the surfaces' slope over the contact reaches 0.339 to 0.357"),
            "{warning}"
        );
        assert_eq!(
            steps, "  at 18 of 41 steps: 0-17 (t = 0.000 to 0.425 s)",
            "{t}"
        );
    }
    // The CSV has every step's own.
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert!(csv.lines().next().unwrap().ends_with(",warnings"));
    let slope_rows = csv.lines().skip(1).filter(|l| l.contains("slope")).count();
    assert_eq!(slope_rows, 18, "{csv}");
}

#[test]
fn plan_prints_and_reports_the_warnings_of_its_checked_run() {
    let dir = tmp("plan");
    let (out, report) = (dir.join("d.schedule.json"), dir.join("d.json"));
    let o = grasp(&[
        "plan",
        &example("disc_transfer.json"),
        "--releasing",
        "f3,f4",
        "--receiving",
        "f1,f2",
        "--template",
        &example("disc_transfer.schedule.json"),
        "--max-rate",
        "5",
        "--steps",
        "10",
        "--out",
        out.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    let found = warnings_with_steps(&t, "fingers[2] `f3`: the patch boundary carries");
    assert_eq!(found.len(), 1, "{t}");
    assert!(found[0].1.starts_with("  at 10 of 11 steps: 0-9"), "{t}");
    // The report: the same warnings, named with the CLI's flags.
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let warnings = r["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 4, "{warnings:?}");
    for w in warnings {
        let message = w["message"].as_str().unwrap();
        assert!(message.contains("`--auto-patch`"), "{message}");
        assert_eq!(w["count"], 10);
    }
}

#[test]
fn margin_prints_and_writes_the_warnings_of_the_grasp_and_of_its_margins() {
    let dir = tmp("margin");
    let json = dir.join("m.json");
    let o = grasp(&[
        "margin",
        &example("disc_three_fingers.json"),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    // The grasp's own warnings as `grasp solve` prints them.
    let solve = text(&grasp(&["solve", &example("disc_three_fingers.json")]));
    let own: Vec<&str> = solve
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect();
    assert!(!own.is_empty());
    for w in &own {
        assert!(t.contains(w), "{w}\n{t}");
    }
    // At the margins (the search's cap) the fingers are far beyond small strain: said once per
    // finger, with the directions it applies to.
    let strain = warnings_with_steps(&t, "fingers[2] `f3`: its compression");
    assert_eq!(strain.len(), 1, "{t}");
    assert!(strain[0].1.contains("directions' margins: #"), "{t}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["warnings"].as_array().unwrap().len(), own.len());
    let first = r["warnings"][0].as_str().unwrap();
    assert!(first.contains("`--auto-patch`"), "{first}");
    assert!(r["directions"][0]["warnings"]
        .as_array()
        .is_some_and(|w| !w.is_empty()));
}

#[test]
fn plot_prints_the_warnings_of_its_solve() {
    let dir = tmp("plot");
    let out = dir.join("d.svg");
    let o = grasp(&[
        "plot",
        &example("disc_three_fingers.json"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert_eq!(
        t.lines()
            .filter(|l| l.starts_with("warning: ") && l.contains("patch boundary carries"))
            .count(),
        2,
        "{t}"
    );
}

#[test]
fn study_of_the_edge_pinch_reports_the_peaks_growth_as_a_singular_edge() {
    let o = grasp(&["study", &example("edge_pinch.json"), "--grids", "12,24,48"]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("| p_max [Pa] |"), "{t}");
    assert_eq!(t.matches("(at an edge)").count(), 4, "{t}"); // three rows and the legend
    let trend = t
        .lines()
        .find(|l| l.starts_with("peak pressure: "))
        .unwrap_or_else(|| panic!("{t}"));
    assert!(
        trend.contains("the peak grows as n^0.")
            && trend.contains("a singular edge")
            && trend.contains("not a converged value"),
        "{trend}"
    );
}

#[test]
fn solve_labels_a_peak_pressure_at_a_sharp_edge_and_not_a_smooth_one() {
    let edge = text(&grasp(&["solve", &example("edge_pinch.json")]));
    assert!(
        edge.contains("p_max of left, right lies at a sharp edge of the contact"),
        "{edge}"
    );
    let hertz = text(&grasp(&["solve", &example("hertz_sphere_on_flat.json")]));
    assert!(!hertz.contains("sharp edge"), "{hertz}");
}

#[test]
fn transfer_files_name_options_as_the_cli_does() {
    // The disc's patches are too small: the warning points to an option, which the CSV's
    // column and the MCAP's metadata name by its flag, as the summary does.
    let dir = tmp("flags");
    let (csv, mcap) = (dir.join("d.csv"), dir.join("d.mcap"));
    let o = grasp(&[
        "transfer",
        &example("disc_transfer.json"),
        "--schedule",
        &example("disc_transfer.schedule.json"),
        "--csv",
        csv.to_str().unwrap(),
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("grow it with `--auto-patch`"),
        "{}",
        text(&o)
    );
    let csv = std::fs::read_to_string(&csv).unwrap();
    // Each of the four fingers at 150 of the 151 steps.
    assert_eq!(csv.matches("grow it with `--auto-patch`").count(), 4 * 150);
    assert!(!csv.contains("auto_patch"), "{csv}");
    let mcap = String::from_utf8_lossy(&std::fs::read(&mcap).unwrap()).into_owned();
    assert_eq!(mcap.matches("grow it with `--auto-patch`").count(), 4);
    assert!(!mcap.contains("auto_patch"));
}
