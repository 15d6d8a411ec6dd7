//! Work bounds of a command, checked before any allocation: the memory a scene's solve needs
//! against `--max-memory` (the one check, `grasp_io::MemoryLimit::check`); and the input
//! files, read through `grasp_io::InputFile` (regular files within a size limit) and noted,
//! so no output of the command replaces one of them.

use std::path::Path;
use std::sync::Mutex;

use anyhow::{anyhow, Result};
use grasp_io::{InputKind, MemoryLimit, RunInputs, SCENE_FILE};
use grasp_model::{ComplianceChoice, LoadedScene};

/// Largest scene, schedule or directions file read, bytes.
pub const MAX_INPUT_BYTES: u64 = SCENE_FILE.max_bytes;

/// The memory limit of a command.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct MemoryArg {
    /// Refuse scenes whose estimated memory exceeds this many bytes (suffixes K, M, G, T:
    /// 512M, 4G); default: a quarter of the machine's memory (MemTotal in /proc/meminfo); a
    /// limit above the machine's memory is cut to it.
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
}

impl MemoryArg {
    /// `--max-memory` or, without it, the default limit.
    pub fn limit(&self) -> MemoryLimit {
        MemoryLimit::of(self.max_memory)
    }

    /// Refuses the scene read from `file` when its estimated memory, every patch in the form
    /// `compliance` gives it, exceeds the limit.
    pub fn check(
        &self,
        scene: &LoadedScene,
        file: &Path,
        compliance: ComplianceChoice,
    ) -> Result<()> {
        self.limit()
            .check(scene, compliance)
            .map(|_| ())
            .map_err(|e| anyhow!("{} {e}", file.display()))
    }
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

/// Reads an input file through `grasp_io::InputFile` (a regular file, checked before and
/// after opening, so a pipe never blocks; at most [`MAX_INPUT_BYTES`], bounded while reading)
/// as UTF-8 text, and notes it.
pub fn read_input(path: &Path, what: &'static str) -> Result<String> {
    let kind = InputKind {
        what,
        max_bytes: MAX_INPUT_BYTES,
    };
    let (text, identity) = grasp_io::read_text(path, kind)?;
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
