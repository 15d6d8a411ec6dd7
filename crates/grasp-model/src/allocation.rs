//! Fallible allocation of the large buffers of a model and a solve: a zeroed vector or a check
//! that a solve's working memory can be had, each reporting [`OutOfMemory`] (what, how many
//! bytes, the fix) where an ordinary allocation would abort the whole process.
//!
//! Rust aborts on a failed allocation (`memory allocation of N bytes failed`, exit 134): under
//! an address-space limit (`ulimit -v`, a batch of scenes sharing one) the kernel tables and
//! spectra of a fine patch are what fails first, so those are allocated here, and a solve
//! checks that its working vectors fit before it starts ([`check_room`]).

use crate::error::OutOfMemory;

/// A vector of `len` copies of `value`, or [`OutOfMemory`] (named `a buffer`; the caller
/// names what it was for with [`OutOfMemory::named`]) when the allocation is refused.
pub fn filled<T: Clone>(len: usize, value: T) -> Result<Vec<T>, OutOfMemory> {
    let mut v = Vec::new();
    let bytes = (len as u64).saturating_mul(std::mem::size_of::<T>() as u64);
    v.try_reserve_exact(len)
        .map_err(|_| OutOfMemory::new("a buffer", bytes))?;
    v.resize(len, value);
    Ok(v)
}

/// Room kept above what [`check_room`] is asked for: the small buffers (FFT scratch, a few
/// vectors) allocated ordinarily around the large ones.
pub const HEADROOM_BYTES: u64 = 16 << 20;

/// Needs smaller than this are not checked by [`check_room`]: a check costs two system calls,
/// which a batch of many small scenes or a hand-off's many steps would pay for nothing.
pub const CHECKED_ABOVE_BYTES: u64 = 8 << 20;

/// Checks that `bytes` and [`HEADROOM_BYTES`] more can be allocated now (reserved and given
/// back at once, never touched, so it costs no memory), or [`OutOfMemory`] for `what` (of
/// `bytes`): taken before building a finger's compliance and before the many vectors of a
/// solve, which are allocated ordinarily, so that they find the room they need. Needs up to
/// [`CHECKED_ABOVE_BYTES`] pass unchecked.
pub fn check_room(bytes: u64, what: impl FnOnce() -> String) -> Result<(), OutOfMemory> {
    if bytes <= CHECKED_ABOVE_BYTES {
        return Ok(());
    }
    let mut probe: Vec<u8> = Vec::new();
    let with_headroom = bytes.saturating_add(HEADROOM_BYTES);
    match usize::try_from(with_headroom).map(|len| probe.try_reserve_exact(len)) {
        Ok(Ok(())) => Ok(()),
        _ => Err(OutOfMemory::new(what(), bytes)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An allocation no machine can give (half the address space) is reported, with its
    /// size, not aborted; a small one is given, filled.
    #[test]
    fn refused_allocations_are_reported() {
        let huge = (isize::MAX as usize) / 16;
        let e = filled(huge, 0.0f64).unwrap_err();
        assert_eq!(e.bytes, huge as u64 * 8);
        assert!(
            e.to_string()
                .starts_with("not enough memory for a buffer ("),
            "{e}"
        );
        let e = check_room(u64::MAX, || "the test's vectors".into()).unwrap_err();
        assert!(e.to_string().contains("the test's vectors"), "{e}");
        assert_eq!(filled(3, 1.5f64).unwrap(), vec![1.5; 3]);
        assert!(check_room(1 << 20, String::new).is_ok());
        assert!(check_room(CHECKED_ABOVE_BYTES + 1, String::new).is_ok());
    }
}
