//! Resident memory of this process, from Linux `/proc/self/status` (`VmRSS`, `VmHWM`). The
//! peak (`VmHWM`) is reset by writing `5` to `/proc/self/clear_refs` (Linux >= 4.0), so a
//! case's peak is measured from its own start. Elsewhere these read `None`.

/// Reads one `kB` field of `/proc/self/status`, bytes.
fn status_field_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Peak resident memory of this process since it started or since the last
/// [`reset_peak`], bytes.
pub fn peak_rss_bytes() -> Option<u64> {
    status_field_bytes("VmHWM:")
}

/// Resident memory of this process now, bytes.
pub fn rss_bytes() -> Option<u64> {
    status_field_bytes("VmRSS:")
}

/// Resets the peak to the current resident memory; false when the system does not allow it
/// (the peak then covers the whole process so far).
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}
