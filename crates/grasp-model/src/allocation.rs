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
/// names what it was for with [`OutOfMemory::named`]) when the allocation is refused. A long
/// one is written on all cores ([`resize_on_all_cores`]).
pub fn filled<T: Clone + Send + Sync>(len: usize, value: T) -> Result<Vec<T>, OutOfMemory> {
    let mut v = Vec::new();
    let bytes = (len as u64).saturating_mul(std::mem::size_of::<T>() as u64);
    v.try_reserve_exact(len)
        .map_err(|_| OutOfMemory::new("a buffer", bytes))?;
    resize_on_all_cores(&mut v, len, value);
    Ok(v)
}

/// New entries from which [`resize_on_all_cores`] writes on all cores (256 KiB of doubles).
const PARALLEL_FILL: usize = 1 << 15;

/// `v.resize(len, value)`, the new entries written on all cores when they are many: the first
/// write to a new buffer's pages is where the kernel maps and clears them, a tenth of a second
/// for a fine patch's few hundred megabytes when one thread does it all. The values are the
/// same whoever writes them.
pub fn resize_on_all_cores<T: Clone + Send + Sync>(v: &mut Vec<T>, len: usize, value: T) {
    let extra = len.saturating_sub(v.len());
    if extra >= PARALLEL_FILL {
        use rayon::prelude::*;
        v.par_extend(rayon::iter::repeat_n(value, extra));
    } else {
        v.resize(len, value);
    }
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
        let long = filled(PARALLEL_FILL + 3, 2.5f64).unwrap();
        assert!(long.len() == PARALLEL_FILL + 3 && long.iter().all(|&x| x == 2.5));
        let mut grown = vec![1.0f64; 5];
        resize_on_all_cores(&mut grown, 2 * PARALLEL_FILL, 0.0);
        assert_eq!(grown.len(), 2 * PARALLEL_FILL);
        assert!(grown[..5].iter().all(|&x| x == 1.0) && grown[5..].iter().all(|&x| x == 0.0));
        resize_on_all_cores(&mut grown, 3, 0.0);
        assert_eq!(grown, vec![1.0; 3]);
    }
}
