//! A solution's files: `--json` (its JSON text, streamed into the file) and `--npz` (its
//! element fields as NumPy arrays), each written to its claimed temporary file and moved into
//! place.

use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};

use crate::output::Outputs;

/// Writes `record` as the solution's JSON text into the claimed `out`
/// ([`grasp_io::write_solution_json`]: streamed, no copy of the text in memory) and says so,
/// with the file's size and the time taken.
pub fn write_json(outs: &Outputs, out: &Path, record: &grasp_io::SolutionRecord<'_>) -> Result<()> {
    let clock = Instant::now();
    let pending = outs.create(out)?;
    let mut writer = BufWriter::with_capacity(1 << 20, pending.file());
    grasp_io::write_solution_json(&mut writer, record)
        .and_then(|()| writer.flush().map_err(serde_json::Error::io))
        .with_context(|| format!("cannot write {}", out.display()))?;
    drop(writer);
    outs.commit(vec![pending])?;
    say_written(out, clock);
    Ok(())
}

/// Writes the element fields of `solution` and its `sensors`' readings as an `.npz` archive
/// into the claimed `out` ([`grasp_io::NpzArchive`]: one array per field and finger) and says so, with the file's
/// size and the time taken.
pub fn write_npz(
    outs: &Outputs,
    out: &Path,
    solution: &grasp_model::Solution,
    sensors: &[grasp_model::SensorReadings],
) -> Result<()> {
    let clock = Instant::now();
    let pending = outs.create(out)?;
    grasp_io::write_solution_npz(&pending, solution, sensors)?;
    outs.commit(vec![pending])?;
    say_written(out, clock);
    Ok(())
}

/// `wrote PATH (SIZE in TIME)`: the file written since `clock` started.
pub fn say_written(out: &Path, clock: Instant) {
    let seconds = clock.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(out).map_or(0, |m| m.len()) as f64;
    let size = match bytes {
        b if b < 1e6 => format!("{:.1} kB", b / 1e3),
        b => format!("{:.1} MB", b / 1e6),
    };
    println!("wrote {} ({size} in {seconds:.2} s)", out.display());
}
