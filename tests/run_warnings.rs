//! Warnings travel with every solve a run makes: a hand-off's summary, its CSV and its MCAP
//! carry its steps' warnings (each once in the summary and the MCAP, with the steps it applies
//! to; each step's own in the CSV), a planned hand-off's report carries its checked run's, and
//! a grasp's margins carry the warnings of the grasp and of the solves at its margins.

mod support;

use std::path::Path;

use grasp_model::{
    axis_directions, disturbance_margins, ContactState, GraspModel, MarginOptions, SolveOptions,
    StepInputs, TalliedWarning,
};
use grasp_transfer::{CsvSink, McapSink, Schedule, StepRecord, TransferOptions};

/// The step indices whose records carry a warning starting with `prefix`.
fn steps_warning(records: &[StepRecord], prefix: &str) -> Vec<usize> {
    records
        .iter()
        .filter(|r| r.solution.warnings.iter().any(|w| w.starts_with(prefix)))
        .map(|r| r.index)
        .collect()
}

/// The step indices a tallied warning lists.
fn listed_steps(w: &TalliedWarning) -> Vec<usize> {
    assert_eq!(w.more_runs, 0, "{w:?}");
    w.steps.iter().flat_map(|r| r.first..=r.last).collect()
}

/// The one tallied warning starting with `prefix`.
fn the_warning<'a>(warnings: &'a [TalliedWarning], prefix: &str) -> &'a TalliedWarning {
    let found: Vec<&TalliedWarning> = warnings
        .iter()
        .filter(|w| w.message.starts_with(prefix))
        .collect();
    assert_eq!(found.len(), 1, "{prefix}: {warnings:#?}");
    found[0]
}

#[test]
fn a_hand_off_over_the_ridged_pad_carries_the_slope_warning_with_its_steps() {
    let scene = support::example_scene("ridged_pad_pinch.json");
    let text = r#"{"time": {"start": 0, "end": 1, "step": 0.5},
        "fingers": {"right": [{"ramp": {"keyframes": [[0, 2], [1, 1.2]]}}]}}"#;
    let schedule = Schedule::from_json_str(text, &scene.finger_names(), Path::new(".")).unwrap();
    let (records, summary) =
        grasp_transfer::run_collect(&scene, &schedule, TransferOptions::default(), &mut [])
            .unwrap();
    assert_eq!(summary.failed_step_count, 0, "{summary:?}");
    for (i, finger) in ["left", "right"].into_iter().enumerate() {
        let prefix = format!("fingers[{i}] `{finger}`: the surfaces' slope over the contact");
        let given = steps_warning(&records, &prefix);
        assert!(!given.is_empty(), "no slope warning: {records:?}");
        let w = the_warning(&summary.warnings, &prefix);
        assert_eq!(listed_steps(w), given, "{w:?}");
        assert_eq!(w.count, given.len());
        assert!(w.message.contains("forces are approximate"), "{w:?}");
        let time = |k: usize| records[k].time_s;
        assert_eq!(w.first_time_s, Some(time(given[0])));
        assert_eq!(w.last_time_s, Some(time(*given.last().unwrap())));
    }
}

#[test]
fn a_hand_off_steps_warning_names_the_finger_by_its_place_in_the_scene() {
    // At the first step of the disc hand-off only f3 and f4 (the scene's fingers[2] and [3])
    // are active: the step's model holds them first, but a message names them as the user
    // wrote them.
    let (scene, schedule) = support::transfer_example("disc_transfer");
    let (records, _) =
        grasp_transfer::run_collect(&scene, &schedule, TransferOptions::default(), &mut [])
            .unwrap();
    let first = &records[0].solution;
    assert_eq!(first.fingers[0].name, "f3", "{:?}", first.fingers);
    for w in &first.warnings {
        let named = |i: usize, f: &str| w.starts_with(&format!("fingers[{i}] `{f}`"));
        assert!(named(2, "f3") || named(3, "f4"), "{w}");
    }
    assert_eq!(first.warnings.len(), 2, "{:?}", first.warnings);
}

/// The metadata records of an MCAP file, name and map.
fn mcap_metadata(path: &Path) -> Vec<(String, std::collections::BTreeMap<String, String>)> {
    let bytes = std::fs::read(path).unwrap();
    mcap::read::LinearReader::new(&bytes)
        .unwrap()
        .filter_map(|r| match r.unwrap() {
            mcap::records::Record::Metadata(m) => Some((m.name, m.metadata)),
            _ => None,
        })
        .collect()
}

#[test]
fn the_csv_carries_each_steps_warnings_and_the_mcap_the_runs_once() {
    let (scene, schedule) = support::transfer_example("cylinder_handoff");
    let dir = std::env::temp_dir().join(format!("grasp-run-warnings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = CsvSink::create(&dir.join("h.csv")).unwrap();
    let mut mcap = McapSink::create(&dir.join("h.mcap")).unwrap();
    let (records, summary) = grasp_transfer::run_collect(
        &scene,
        &schedule,
        TransferOptions::default(),
        &mut [&mut csv, &mut mcap],
    )
    .unwrap();
    // The slope warning holds at some steps only (while A still squeezes hard).
    let slope = steps_warning(&records, "fingers[0] `a1`: the surfaces' slope");
    assert!(
        !slope.is_empty() && slope.len() < records.len(),
        "{slope:?}"
    );
    // CSV: a `warnings` column, each row its step's warnings.
    let text = std::fs::read_to_string(dir.join("h.csv")).unwrap();
    let rows = parse_csv(&text);
    let col = rows[0].iter().position(|h| h == "warnings").unwrap();
    assert_eq!(col, rows[0].len() - 1);
    for (row, r) in rows[1..].iter().zip(&records) {
        let cell = &row[col];
        let expected = r
            .solution
            .warnings
            .join(grasp_transfer::CSV_WARNING_SEPARATOR);
        assert_eq!(cell, &expected, "step {}", r.index);
    }
    // MCAP: one metadata record per warning of the summary, with its steps.
    let meta = mcap_metadata(&dir.join("h.mcap"));
    assert_eq!(meta.len(), summary.warnings.len(), "{meta:?}");
    assert!(!meta.is_empty());
    for ((name, m), w) in meta.iter().zip(&summary.warnings) {
        assert_eq!(name, grasp_transfer::WARNING_METADATA);
        assert_eq!(m["message"], w.message);
        assert_eq!(m["count"], w.count.to_string());
        assert_eq!(m["steps"], w.runs_text(|k| k.to_string()));
    }
    let a1 = the_warning(&summary.warnings, "fingers[0] `a1`: the surfaces' slope");
    assert_eq!(listed_steps(a1), slope);
}

#[test]
fn a_run_without_warnings_writes_no_warning_metadata() {
    let (scene, schedule) = support::transfer_example("plate_transfer");
    let dir = std::env::temp_dir().join(format!("grasp-run-quiet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut mcap = McapSink::create(&dir.join("p.mcap")).unwrap();
    let (_, summary) = grasp_transfer::run_collect(
        &scene,
        &schedule,
        TransferOptions::default(),
        &mut [&mut mcap],
    )
    .unwrap();
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    assert!(mcap_metadata(&dir.join("p.mcap")).is_empty());
}

#[test]
fn the_margins_of_a_grasp_with_an_undersized_patch_carry_its_warnings() {
    let scene = support::example_scene("disc_three_fingers.json");
    let model = std::sync::Arc::new(GraspModel::from_loaded(&scene).unwrap());
    let base = grasp_model::solve(&model).unwrap();
    assert!(!base.warnings.is_empty());
    let report = disturbance_margins(
        &model,
        &StepInputs::of_scene(&model),
        &ContactState::new(&model),
        SolveOptions::default(),
        &axis_directions(&model),
        &MarginOptions::default(),
    )
    .unwrap();
    // The grasp's own warnings, as a solve of it gives them.
    assert_eq!(report.warnings, base.warnings);
    // At the margins (here the search's cap) the fingers are pressed far beyond small strain:
    // the solves there say so, and the margins inherit it.
    let at_margins: Vec<&String> = report.directions.iter().flat_map(|d| &d.warnings).collect();
    assert!(
        at_margins.iter().any(|w| w.contains("beyond small strain")),
        "{at_margins:?}"
    );
    // The scene's own warnings are the report's, not repeated per direction.
    for w in model.scene_warnings() {
        assert!(!at_margins.contains(&w), "{w}");
    }
}

#[test]
fn a_planned_hand_off_reports_the_warnings_of_its_checked_run() {
    let dir = std::path::PathBuf::from(support::example_path(""));
    let (scene, schedule) =
        support::scene_and_schedule("disc_transfer.json", "disc_transfer.schedule.json");
    let text = std::fs::read_to_string(dir.join("disc_transfer.schedule.json")).unwrap();
    let spec: grasp_transfer::ScheduleSpec = serde_json::from_str(&text).unwrap();
    let options = grasp_transfer::PlanOptions {
        releasing: vec!["f3".into(), "f4".into()],
        receiving: vec!["f1".into(), "f2".into()],
        max_rate_n_per_s: Some(5.0),
        steps: Some(10),
        ..grasp_transfer::PlanOptions::default()
    };
    let template = grasp_transfer::Template {
        spec: &spec,
        schedule: &schedule,
    };
    let report = grasp_transfer::plan(&scene, Some(template), &options).unwrap();
    // Re-run as `grasp transfer` would run the planned schedule: the same warnings.
    let text = serde_json::to_string(&report.schedule).unwrap();
    let planned = Schedule::from_json_str(&text, &scene.finger_names(), &dir).unwrap();
    let (_, summary) =
        grasp_transfer::run_collect(&scene, &planned, TransferOptions::default(), &mut []).unwrap();
    assert!(!report.warnings.is_empty());
    assert_eq!(report.warnings, summary.warnings);
}

/// Reads RFC 4180 CSV: quoted fields may hold commas, doubled quotes and line breaks.
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let (mut rows, mut row, mut field) = (Vec::new(), Vec::new(), String::new());
    let mut chars = text.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => field.push(c),
        }
    }
    rows
}
