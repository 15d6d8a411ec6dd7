//! Every number a command takes as a flag is range-checked before any work:
//! out-of-range, non-finite and overflowing values of every f64 and count flag of `solve`,
//! `margin`, `study`, `bench`, `plot` and `transfer` exit 1 at once, naming the flag, the value
//! in readable form (no 309-digit numbers) and the range; the library's ranges
//! (`SolveOptions::validate`, `MarginOptions::validate`) are the ones the CLI applies, respelled
//! as flags. Values at the ends of the ranges run to an answer in bounded time (the extreme
//! `--length` that panicked and the tiny `--tolerance` that never returned are now refused, and
//! the in-range extremes finish).

mod common;

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{example, tmp};

/// Wall-time bound of a run that is refused before any work, s.
const REFUSED_WITHIN_S: u64 = 20;
/// Wall-time bound of a run at the ends of the ranges, s.
const FINISHED_WITHIN_S: u64 = 300;

/// Runs `grasp args`, killed after `secs`: (output, wall time); panics on the timeout.
fn run(args: &[&str], secs: u64) -> (Output, f64) {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_grasp"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run grasp");
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("grasp {args:?} did not return within {secs} s");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let out = child.wait_with_output().expect("output");
    (out, start.elapsed().as_secs_f64())
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The longest run of digits in `text` (a number written in full has 309 for 1e308).
fn longest_digit_run(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// `grasp <command...> <flag> <value>` for each bad value: exit 1 within
/// [`REFUSED_WITHIN_S`], no panic, the flag named, every `words` present, numbers readable.
fn refused(command: &[&str], flag: &str, values: &[&str], words: &[&str]) {
    for value in values {
        let arg = format!("{flag}={value}");
        let mut args = command.to_vec();
        args.push(&arg);
        let (o, _) = run(&args, REFUSED_WITHIN_S);
        let all = text(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {all}");
        assert!(!all.contains("panicked"), "{args:?}: {all}");
        assert!(all.contains(flag), "{args:?} does not name {flag}: {all}");
        for w in words {
            assert!(all.contains(w), "{args:?} does not say {w:?}: {all}");
        }
        assert!(longest_digit_run(&all) <= 20, "{args:?}: {all}");
    }
}

const NON_FINITE: [&str; 4] = ["nan", "inf", "-inf", "1e400"];

#[test]
fn solve_tolerance_outside_the_library_range_is_refused() {
    let scene = example("cube_a.json");
    refused(
        &["solve", &scene],
        "--tolerance",
        &["2e-16", "1e-300", "0", "-1e-10", "0.5", "1e308", "5e-324"],
        &["[1e-14, 0.01]", "e.g. 1e-10"],
    );
    refused(&["solve", &scene], "--tolerance", &NON_FINITE, &["[1e-14"]);
    // The value is quoted as given, in exponent form.
    let (o, _) = run(&["solve", &scene, "--tolerance=1e308"], REFUSED_WITHIN_S);
    assert!(text(&o).contains("`--tolerance` is 1e308;"), "{}", text(&o));
}

#[test]
fn margin_length_tolerance_and_directions_outside_their_ranges_are_refused() {
    let scene = example("cube_a.json");
    let margin = ["margin", scene.as_str()];
    refused(
        &margin,
        "--length",
        &["1e305", "1e308", "0", "-1", "1e-10", "1001", "5e-324"],
        &["[1e-9, 1000]"],
    );
    refused(&margin, "--length", &NON_FINITE, &["[1e-9, 1000]"]);
    refused(
        &margin,
        "--tolerance",
        &["2e-16", "1e-300", "0", "1e-10", "0.6", "1e308"],
        &["[1e-9, 0.5]"],
    );
    refused(&margin, "--tolerance", &NON_FINITE, &["[1e-9, 0.5]"]);
    refused(&margin, "--directions", &["0", "10001"], &["10000"]);
    refused(
        &margin,
        "--directions",
        &[
            "planes:3",
            "planes:361",
            "planes:nan",
            "planes:18446744073709551616",
        ],
        &["planes:", "360"],
    );
}

#[test]
fn study_grids_bench_times_and_lists_outside_their_ranges_are_refused() {
    let scene = example("cube_a.json");
    refused(
        &["study", &scene],
        "--grids",
        // Up to 2048 elements a side (the FFT compliance takes grids above 64 x 64).
        &["0", "2049", "1048577", "5,0", "18446744073709551615"],
        &["[1, 2048]"],
    );
    let many: Vec<String> = (1..=33).map(|k| k.to_string()).collect();
    refused(&["study", &scene], "--grids", &[&many.join(",")], &["32"]);
    refused(
        &["bench"],
        "--min-time",
        &["-1", "3601", "1e308", "nan", "inf"],
        &["[0, 3600]"],
    );
    refused(&["bench"], "--solver", &["native,native"], &["twice"]);
    refused(&["bench"], "--case", &["cube_a_5x5,cube_a_5x5"], &["twice"]);
}

#[test]
fn memory_limits_of_every_command_are_refused_when_not_a_size() {
    let scene = example("cube_a.json");
    let d = tmp("ranges", "memory");
    let out = d.join("p.svg");
    let schedule = example("plate_transfer.schedule.json");
    let plate = example("plate_transfer.json");
    let bad = ["nan", "1e400", "-1", "0", "abc", "99999999999T"];
    refused(&["solve", &scene], "--max-memory", &bad, &[]);
    refused(&["margin", &scene], "--max-memory", &bad, &[]);
    refused(&["study", &scene], "--max-memory", &bad, &[]);
    refused(
        &["plot", &scene, "--out", out.to_str().unwrap()],
        "--max-memory",
        &bad,
        &[],
    );
    refused(
        &["transfer", &plate, "--schedule", &schedule],
        "--max-memory",
        &bad,
        &[],
    );
}

/// The ends of the ranges run to an answer: the largest `--length` (1e3 m, the class of the
/// 1e305 that panicked in the predictor) and the smallest `--tolerance` (1e-9, the class of
/// the 2e-16 that never returned) give a report with finite numbers, every bracket narrowed
/// to the tolerance or the reason it was not; the solve's smallest tolerance finishes.
#[test]
fn the_ends_of_the_ranges_finish_with_finite_reports() {
    let d = tmp("ranges", "ends");
    let scene = example("cube_a.json");
    for (flag, value) in [("--length", "1000"), ("--tolerance", "1e-9")] {
        let json = d.join(format!("m{flag}.json"));
        let (o, secs) = run(
            &[
                "margin",
                &scene,
                &format!("{flag}={value}"),
                "--json",
                json.to_str().unwrap(),
            ],
            FINISHED_WITHIN_S,
        );
        let all = text(&o);
        assert_eq!(o.status.code(), Some(0), "{flag} {value}: {all}");
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        for m in report["directions"].as_array().unwrap() {
            // How far it held: the margin when a magnitude that fails was found (then
            // `margin_n` is that number), else the cap or an undetermined margin's lower bound.
            let margin = m["held_to_n"].as_f64().unwrap();
            assert!(margin.is_finite() && margin >= 0.0, "{m}");
            assert_eq!(
                m["margin_n"].as_f64(),
                m["fails_at_n"].as_f64().map(|_| margin),
                "{m}"
            );
            if let (Some(hi), None) = (m["fails_at_n"].as_f64(), m.get("stopped_early")) {
                let tol: f64 = if flag == "--tolerance" { 1e-9 } else { 1e-3 };
                // Narrowed to the tolerance, or stopped at the zero-margin floor (1e-6 of the
                // load scale).
                let floor = 1e-6 * report["load_scale_n"].as_f64().unwrap();
                assert!(hi - margin <= tol * hi || hi <= floor, "{m}");
            }
        }
        eprintln!("margin {flag}={value}: {secs:.1} s");
    }
    let (o, _) = run(&["solve", &scene, "--tolerance=1e-14"], FINISHED_WITHIN_S);
    let all = text(&o);
    match o.status.code() {
        Some(0) => {}
        Some(2) => assert!(all.contains("no convergence"), "{all}"),
        other => panic!("exit {other:?}: {all}"),
    }
}
