//! The machine's memory (`MemTotal` of `/proc/meminfo`, read through [`crate::input_file`]),
//! for the default memory limits of the CLI and the Python module.

use std::path::Path;

use crate::input_file::{read_text, SYSTEM_FILE};

/// Share of the machine's memory a run may plan to use when no limit is given: a quarter,
/// since the machine is often shared (and estimates are estimates).
pub const DEFAULT_MEMORY_SHARE: f64 = 0.25;

/// The limit when `/proc/meminfo` cannot be read, bytes.
pub const FALLBACK_MEMORY_LIMIT: u64 = 4 << 30;

/// `MemTotal` of `/proc/meminfo`, bytes.
pub fn mem_total_bytes() -> Option<u64> {
    let (text, _) = read_text(Path::new("/proc/meminfo"), SYSTEM_FILE).ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kb.checked_mul(1024)
}

/// The default memory limit: [`DEFAULT_MEMORY_SHARE`] of `MemTotal`, or
/// [`FALLBACK_MEMORY_LIMIT`] when it cannot be read; bytes.
pub fn default_memory_limit() -> u64 {
    mem_total_bytes().map_or(FALLBACK_MEMORY_LIMIT, |total| {
        (total as f64 * DEFAULT_MEMORY_SHARE) as u64
    })
}
