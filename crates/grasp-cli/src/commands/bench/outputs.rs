//! `grasp bench`'s rows on writing a fine patch's solution: the Hertz example solved once on
//! 1024 x 1024 elements (256 x 256 with `--quick`), then written as `--json` and as `--npz`
//! ([`grasp_bench::measure_output_writing`]), each write against its target: the JSON within half the
//! solve's time with the process's peak under 1.2 GB, the `.npz` within a tenth of the solve.
//! `--case outputs` runs these rows alone.

use anyhow::Result;
use grasp_bench::{measure_output_writing, WriteCost};

use super::{time, verdict, Row, ScratchFolder, HEADER};

/// The rows' name for `--case`.
pub(super) const CASE: &str = "outputs";

/// Largest time of each format's write over the solve's: JSON, `.npz`.
const WRITE_OVER_SOLVE: [(&str, f64); 2] = [("json", 0.5), ("npz", 0.1)];

/// Largest peak resident memory of a solve with its JSON written, bytes (1.2 GB).
const JSON_PEAK_BYTES: f64 = 1.2e9;

/// The solve's row and one row per output format.
pub(super) fn output_rows(quick: bool) -> Result<Vec<Row>> {
    let grid = if quick { 256 } else { 1024 };
    let folder = ScratchFolder::create()?;
    let costs = measure_output_writing(grid, &folder.path)?;
    drop(folder);
    let mib = |b: Option<u64>| b.map_or("-".into(), |b| format!("{:.2}", b as f64 / 1048576.0));
    let name = format!("hertz_{grid}x{grid} outputs");
    let mut solve = vec![String::new(); HEADER.len()];
    solve[0] = name.clone();
    solve[1] = "build + solve".into();
    solve[3] = time(costs.solve_s);
    solve[5] = "1".into();
    solve[6] = (grid * grid).to_string();
    solve[9] = mib(costs.solve_peak_bytes);
    let mut rows = vec![solve];
    for w in &costs.writes {
        rows.push(write_row(&name, w, costs.solve_s, mib(w.peak_bytes)));
    }
    Ok(rows)
}

/// One format's row: its time, size, the process's peak so far, and its targets.
fn write_row(name: &str, w: &WriteCost, solve_s: f64, peak_mib: String) -> Row {
    let ratio = w.time_s / solve_s;
    let limit = WRITE_OVER_SOLVE
        .iter()
        .find(|(f, _)| *f == w.format)
        .map_or(f64::INFINITY, |(_, l)| *l);
    let mut target = format!(
        "{ratio:.2}x solve {}",
        verdict(ratio, limit, |x| format!("{x:.1}x"))
    );
    if let (Some(peak), "json") = (w.peak_bytes, w.format) {
        let gb = |b: f64| format!("{:.1} GB", b / 1e9);
        target.push_str(&format!(
            "; peak {}",
            verdict(peak as f64, JSON_PEAK_BYTES, gb)
        ));
    }
    let mut row = vec![String::new(); HEADER.len()];
    row[0] = format!("{name} --{}", w.format);
    row[1] = "write + sync".into();
    row[3] = time(w.time_s);
    row[4] = format!("{:.1} MB", w.bytes as f64 / 1e6);
    row[5] = "1".into();
    row[9] = peak_mib;
    row[11] = target;
    row
}
