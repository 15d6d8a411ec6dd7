//! `grasp bench` runs and prints a well-formed table (a smoke run on the quick cases with the
//! native solver; the full table is in docs/benchmarks.md). Timings are not asserted: speed targets
//! belong to the benchmark itself, not to tests. What is asserted holds on any machine: the
//! rows and columns are there, each timed median lies inside its range, a warm step needs no
//! more iterations than a cold one, and a bad case name is refused with the list of names.

mod common;
use common::grasp;

/// Parses "1.234 ms", "56.7 us" or "1.20 s" into seconds.
fn seconds(cell: &str) -> f64 {
    let (v, unit) = cell.trim().split_once(' ').expect("value and unit");
    let v: f64 = v.parse().expect("number");
    v * match unit {
        "us" => 1e-6,
        "ms" => 1e-3,
        "s" => 1.0,
        other => panic!("unit {other}"),
    }
}

#[test]
fn quick_native_bench_prints_a_markdown_table() {
    let out = grasp(&[
        "bench",
        "--quick",
        "--markdown",
        "--solver",
        "native",
        "--case",
        "cube_a_5x5,plate_handoff_warm,plate_handoff_cold",
        "--min-time",
        "0",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<Vec<&str>> = stdout
        .lines()
        .filter(|l| l.starts_with('|'))
        .map(|l| l.trim_matches('|').split(" | ").map(str::trim).collect())
        .collect();
    assert!(rows.iter().all(|r| r.len() == 12), "{stdout}");
    let row = |name: &str| {
        rows.iter()
            .find(|r| r[0] == name)
            .unwrap_or_else(|| panic!("no row {name}: {stdout}"))
    };
    for name in ["cube_a_5x5", "plate_handoff_warm", "plate_handoff_cold"] {
        let r = row(name);
        assert_eq!(r[2], "native");
        let median = seconds(r[3]);
        let (lo, hi) = r[4].split_once('-').expect("range");
        assert!(seconds(lo) <= median && median <= seconds(hi), "{r:?}");
        assert!(r[6].parse::<usize>().expect("unknowns") > 0, "{r:?}");
    }
    assert_eq!(
        row("cube_a_5x5")[6],
        "225",
        "3 fingers x 25 elements x 3 unknowns"
    );
    let iterations = |name: &str| row(name)[7].parse::<f64>().expect("iterations");
    assert!(iterations("plate_handoff_warm") <= iterations("plate_handoff_cold"));
    let ratio = row("plate hand-off warm/cold");
    assert!(ratio[11].starts_with("<= 0.2 ("), "{ratio:?}");
    // Standard error is a pipe here, not a terminal: one plain progress line per case, no
    // carriage returns (they garble a log file).
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains('\r'), "{stderr:?}");
    for name in ["cube_a_5x5", "plate_handoff_warm", "plate_handoff_cold"] {
        let line = format!("bench: {name} (native)");
        assert!(
            stderr.lines().any(|l| l == line),
            "no `{line}` in {stderr:?}"
        );
    }
}

#[test]
fn an_unknown_case_is_refused_with_the_list_of_cases() {
    let out = grasp(&["bench", "--case", "cube_z"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr.contains("--case cube_z") && stderr.contains("cube_a_5x5"),
        "{stderr}"
    );
    // As every command's errors: `error: ...`, not Rust's `Error: ...` of a returned `Err`.
    assert!(stderr.starts_with("error: --case cube_z"), "{stderr}");
}

#[test]
fn a_peer_python_that_does_not_exist_is_refused_before_any_case_runs() {
    let out = grasp(&[
        "bench",
        "--case",
        "hertz_128x128_fft",
        "--peer",
        "/nonexistent/python",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--peer /nonexistent/python: no such file"),
        "{stderr}"
    );
    assert!(!stderr.contains("bench: hertz_128x128_fft"), "{stderr}");
}
