//! What writing a fine patch's solution costs: the Hertz example on an `n x n` grid solved
//! once (model build and solve, as `grasp solve` does), then its solution written as
//! `grasp solve --json` and `--npz` write it (the same library functions, into a file of a
//! scratch folder, synced to disk as the CLI's outputs are), each timed, with the process's
//! peak resident memory from the start of the solve to the end of that write. Its rows in the
//! table (the `outputs` case): the solve's, then each write's against its targets (the JSON
//! within half the solve's time with the process's peak under 1.2 GB, the `.npz` within a
//! tenth of the solve), on 1024 x 1024 elements (256 x 256 when quick).

use std::io::BufWriter;
use std::path::Path;
use std::time::Instant;

use grasp_io::SolutionRecord;
use grasp_model::{ComplianceChoice, GraspModel, LoadedScene};

use crate::error::BenchError;
use crate::peak_memory;
use crate::scratch_folder::ScratchFolder;
use crate::table::{mib, time, verdict, Row};

/// The name of these rows as a case (`grasp bench --case outputs`).
pub const OUTPUTS_CASE: &str = "outputs";

/// Largest time of each format's write over the solve's: JSON, `.npz`.
const WRITE_OVER_SOLVE: [(&str, f64); 2] = [("json", 0.5), ("npz", 0.1)];

/// Largest peak resident memory of a solve with its JSON written, bytes (1.2 GB).
const JSON_PEAK_BYTES: f64 = 1.2e9;

/// One output format's cost.
#[derive(Debug, Clone)]
pub struct WriteCost {
    /// `"json"` or `"npz"`.
    pub format: &'static str,
    /// Time to write and sync the file, s.
    pub time_s: f64,
    /// The file's size, bytes.
    pub bytes: u64,
    /// Peak resident memory of the process from the start of the solve to the end of this
    /// write, above its resident memory at the start, bytes (`None` where `/proc` does not
    /// tell).
    pub peak_bytes: Option<u64>,
}

/// The solve and the writes of one grid.
#[derive(Debug, Clone)]
pub struct OutputCosts {
    /// Elements along each side.
    pub grid: usize,
    /// Model build and solve, s.
    pub solve_s: f64,
    /// Peak resident memory of the solve alone, above the start, bytes.
    pub solve_peak_bytes: Option<u64>,
    /// The writes, JSON then `.npz`.
    pub writes: Vec<WriteCost>,
}

/// Solves the Hertz example on `grid x grid` elements and writes its solution in each format
/// into `folder` (files removed afterwards).
pub fn measure_output_writing(grid: usize, folder: &Path) -> Result<OutputCosts, BenchError> {
    let name = format!("hertz_{grid}x{grid} outputs");
    let fail = |message: String| BenchError::Run {
        case: name.clone(),
        message,
    };
    let (text, _) = crate::case::bundled("hertz_sphere_on_flat")
        .ok_or_else(|| fail("the bundled Hertz example is missing".into()))?;
    let mut scene: serde_json::Value =
        serde_json::from_str(text).map_err(|e| fail(e.to_string()))?;
    scene["fingers"][0]["patch"]["grid"] = serde_json::json!([grid, grid]);
    let scene = LoadedScene::from_json_str(&scene.to_string()).map_err(|e| fail(e.to_string()))?;
    let reset = peak_memory::reset_peak();
    let base = peak_memory::rss_bytes().unwrap_or(0);
    let clock = Instant::now();
    let model = GraspModel::from_loaded_with(&scene, ComplianceChoice::Auto)
        .map_err(|e| fail(e.to_string()))?;
    let solution = grasp_model::solve(&model).map_err(|e| fail(e.to_string()))?;
    let solve_s = clock.elapsed().as_secs_f64();
    let peak = || {
        let peak = peak_memory::peak_rss_bytes().filter(|_| reset);
        peak.map(|p| p.saturating_sub(base))
    };
    let solve_peak_bytes = peak();
    let record = SolutionRecord {
        solution: &solution,
        time: None,
        sensitivities: None,
        sensors: None,
    };
    let json = timed_write(&folder.join("solution.json"), |w| {
        grasp_io::write_solution_json(w, &record).map_err(std::io::Error::from)
    })
    .map_err(|e| fail(format!("writing the JSON: {e}")))?;
    let json = WriteCost {
        format: "json",
        peak_bytes: peak(),
        ..json
    };
    let npz = timed_write(&folder.join("solution.npz"), |w| {
        let mut archive = grasp_io::NpzArchive::new(w);
        archive.add_solution("", &solution)?;
        archive.finish().map(drop)
    });
    let npz = npz.map_err(|e| fail(format!("writing the npz: {e}")))?;
    let npz = WriteCost {
        format: "npz",
        peak_bytes: peak(),
        ..npz
    };
    Ok(OutputCosts {
        grid,
        solve_s,
        solve_peak_bytes,
        writes: vec![json, npz],
    })
}

/// Creates `path`, writes it with `write` through a buffer, syncs it, times it all, and
/// removes it.
fn timed_write(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> std::io::Result<WriteCost> {
    let clock = Instant::now();
    let file = std::fs::File::create(path)?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    write(&mut w)?;
    let file = w.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()?;
    let time_s = clock.elapsed().as_secs_f64();
    let bytes = file.metadata()?.len();
    std::fs::remove_file(path)?;
    Ok(WriteCost {
        format: "",
        time_s,
        bytes,
        peak_bytes: None,
    })
}

/// The solve's row and one row per output format, on 1024 x 1024 elements (256 x 256 when
/// `quick`), written in a scratch folder.
pub(crate) fn output_rows(quick: bool) -> Result<Vec<Row>, BenchError> {
    let grid = if quick { 256 } else { 1024 };
    let folder = ScratchFolder::create()?;
    let costs = measure_output_writing(grid, folder.path())?;
    drop(folder);
    let name = format!("hertz_{grid}x{grid} outputs");
    let mut rows = vec![Row {
        case: name.clone(),
        timed: "build + solve".into(),
        median: time(costs.solve_s),
        runs: "1".into(),
        unknowns: (grid * grid).to_string(),
        peak_mib: mib(costs.solve_peak_bytes),
        ..Row::default()
    }];
    for w in &costs.writes {
        rows.push(write_row(&name, w, costs.solve_s));
    }
    Ok(rows)
}

/// One format's row: its time, size, the process's peak so far, and its targets.
fn write_row(name: &str, w: &WriteCost, solve_s: f64) -> Row {
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
    Row {
        case: format!("{name} --{}", w.format),
        timed: "write + sync".into(),
        median: time(w.time_s),
        range: format!("{:.1} MB", w.bytes as f64 / 1e6),
        runs: "1".into(),
        peak_mib: mib(w.peak_bytes),
        target,
        ..Row::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small fine patch (72 x 72, written as columns): both formats are written, sized,
    /// timed and removed again.
    #[test]
    fn both_formats_are_measured_and_removed() {
        let folder =
            std::env::temp_dir().join(format!("grasp-output-costs-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let costs = measure_output_writing(72, &folder).unwrap();
        let formats: Vec<&str> = costs.writes.iter().map(|w| w.format).collect();
        assert_eq!(formats, ["json", "npz"]);
        // Each holds at least the 5184 elements' 8-byte pressures.
        assert!(costs
            .writes
            .iter()
            .all(|w| w.bytes > 5184 * 8 && w.time_s > 0.0));
        assert!(costs.solve_s > 0.0);
        assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 0);
        std::fs::remove_dir(&folder).unwrap();
    }
}
