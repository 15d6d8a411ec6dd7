//! Work bounds of a command, checked before any allocation: the memory a scene's solve needs
//! (estimated by `grasp_model::estimate_memory_bytes`) against `--max-memory`; and the input
//! files, read through `grasp_io::input_file` (regular files within a size limit) and noted,
//! so no output of the command replaces one of them.

use std::path::Path;
use std::sync::Mutex;

use anyhow::{bail, Result};
use grasp_io::input_file::{self, InputKind};
use grasp_io::RunInputs;
use grasp_model::Scene;
use grasp_model::{estimate_memory_bytes_with, finger_unknowns, takes_fft, ComplianceChoice};

/// Largest scene, schedule or directions file read, bytes.
pub const MAX_INPUT_BYTES: u64 = input_file::SCENE_FILE.max_bytes;

// The share of the machine's memory a run may plan to use without `--max-memory`.
pub use grasp_io::machine_memory::{DEFAULT_MEMORY_SHARE, FALLBACK_MEMORY_LIMIT};

/// The memory limit of a command.
#[derive(clap::Args, Debug)]
pub struct MemoryArg {
    /// Refuse scenes whose estimated memory exceeds this many bytes (suffixes K, M, G, T:
    /// 512M, 4G); default: a quarter of the machine's memory (MemTotal in /proc/meminfo).
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
}

/// Parses a byte count: a number with an optional binary suffix K, M, G or T (`512M`, `4G`,
/// `1.5G`, `1073741824`); a trailing `B` or `iB` is allowed.
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let t = t
        .strip_suffix("iB")
        .or_else(|| t.strip_suffix('B'))
        .unwrap_or(t);
    let (num, mult) = match t.chars().last().map(|c| c.to_ascii_uppercase()) {
        Some('K') => (&t[..t.len() - 1], 1u64 << 10),
        Some('M') => (&t[..t.len() - 1], 1 << 20),
        Some('G') => (&t[..t.len() - 1], 1 << 30),
        Some('T') => (&t[..t.len() - 1], 1 << 40),
        _ => (t, 1),
    };
    let bad = || {
        format!("`{text}` is not a size; give bytes with an optional K, M, G or T, e.g. 512M or 4G")
    };
    let x: f64 = num.trim().parse().map_err(|_| bad())?;
    let bytes = x * mult as f64;
    if !(bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64) {
        return Err(bad());
    }
    Ok(bytes as u64)
}

/// `--max-memory` or, without it, [`DEFAULT_MEMORY_SHARE`] of `MemTotal`; with a description
/// for messages.
pub fn memory_limit(flag: Option<u64>) -> (u64, String) {
    if let Some(b) = flag {
        return (b, format!("--max-memory {}", human(b)));
    }
    match grasp_io::machine_memory::mem_total_bytes() {
        Some(total) => {
            let b = (total as f64 * DEFAULT_MEMORY_SHARE) as u64;
            (
                b,
                format!(
                    "the default limit {} (a quarter of this machine's memory)",
                    human(b)
                ),
            )
        }
        None => (
            FALLBACK_MEMORY_LIMIT,
            format!(
                "the default limit {} (/proc/meminfo unreadable)",
                human(FALLBACK_MEMORY_LIMIT)
            ),
        ),
    }
}

/// Refuses a scene whose estimated memory exceeds the limit, naming the largest patch (every
/// patch in the form the automatic choice gives it).
pub fn check_memory(scene: &Scene, file: &Path, limit: (u64, &str)) -> Result<()> {
    check_memory_with(scene, file, limit, ComplianceChoice::Auto)
}

/// [`check_memory`] with the patch compliances in the form `compliance` gives them: the
/// estimate is that of the path that will run.
pub fn check_memory_with(
    scene: &Scene,
    file: &Path,
    limit: (u64, &str),
    compliance: ComplianceChoice,
) -> Result<()> {
    let fft = |f: &grasp_model::FingerSpec| takes_fft(scene, f, compliance);
    let need = estimate_memory_bytes_with(scene, fft);
    if need <= limit.0 {
        return Ok(());
    }
    let biggest = scene
        .fingers
        .iter()
        .enumerate()
        .max_by_key(|(_, f)| finger_unknowns(scene, f));
    let detail = biggest.map_or(String::new(), |(i, f)| {
        let n = finger_unknowns(scene, f);
        let form = match fft(f) {
            true => "the FFT operator".to_string(),
            false => format!("a dense {n} x {n} block"),
        };
        format!(
            " (largest: fingers[{i}] `{}`, grid {}x{}, {n} unknowns, {form})",
            f.name, f.patch.grid[0], f.patch.grid[1]
        )
    });
    let fix = match compliance {
        ComplianceChoice::Dense => "use a coarser grid or --compliance fft",
        _ => "use a coarser grid (`grasp study` shows the accuracy each grid gives)",
    };
    bail!(
        "{} needs an estimated {} of memory{detail}, more than {}; fix: {fix}, or raise \
         --max-memory",
        file.display(),
        human(need),
        limit.1
    )
}

/// Bytes for a reader: GiB, MiB or KiB.
pub fn human(b: u64) -> String {
    let x = b as f64;
    if x >= (1u64 << 30) as f64 {
        format!("{:.1} GiB", x / (1u64 << 30) as f64)
    } else if x >= (1u64 << 20) as f64 {
        format!("{:.1} MiB", x / (1u64 << 20) as f64)
    } else {
        format!("{:.1} KiB", x / 1024.0)
    }
}

/// The files this command has read (one run per process): outputs never replace one of them
/// ([`crate::output`]).
static INPUTS_READ: Mutex<RunInputs> = Mutex::new(RunInputs::new());

/// Notes files the command read.
pub fn note_inputs(files: &RunInputs) {
    INPUTS_READ
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .extend(files);
}

/// The files the command has read so far.
pub fn inputs_read() -> RunInputs {
    INPUTS_READ
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone()
}

/// Reads an input file through `grasp_io::input_file` (a regular file, checked before and
/// after opening, so a pipe never blocks; at most [`MAX_INPUT_BYTES`], bounded while reading)
/// as UTF-8 text, and notes it.
pub fn read_input(path: &Path, what: &'static str) -> Result<String> {
    let kind = InputKind {
        what,
        max_bytes: MAX_INPUT_BYTES,
    };
    let (text, identity) = input_file::read_text(path, kind)?;
    let mut read = RunInputs::new();
    read.add(path, identity);
    note_inputs(&read);
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_with_suffixes() {
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("4G"), Ok(4 << 30));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert_eq!(parse_bytes("2k"), Ok(2048));
        for bad in ["", "G", "-1G", "1e400", "lots", "0"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }
}
