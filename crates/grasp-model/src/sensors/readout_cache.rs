//! Read-outs kept for later: a sensor's read-out operator depends only on its grid and the
//! patch's element grid, so a hand-off's steps and a batch's grasps of the same geometry build
//! it once. A small process-wide list per kind of operator, the most recent first, keyed by
//! the bits of everything the operator is built from; a hit returns the very operator a build
//! would make, so readings do not depend on what is kept.

use std::sync::{Arc, Mutex};

use crate::model::influence::GridSpec;
use crate::scene::sensor_spec::TaxelGridSpec;

/// Operators kept per kind.
const KEPT: usize = 8;

/// The largest operator kept, bytes (its caller's estimate).
pub(crate) const MAX_KEPT_BYTES: usize = 64 << 20;

/// Operators of one kind, each with its key.
pub(crate) struct ReadoutCache<T> {
    kept: Mutex<Vec<(Vec<u64>, Arc<T>)>>,
}

impl<T> ReadoutCache<T> {
    /// An empty list.
    pub(crate) const fn new() -> Self {
        ReadoutCache {
            kept: Mutex::new(Vec::new()),
        }
    }

    /// The operator of `key`: kept (moved to the front), or built by `build` and kept when
    /// `keep` (a large operator is used once and dropped: the list holds at most
    /// [`KEPT`] x [`MAX_KEPT_BYTES`]).
    pub(crate) fn get_or_build<E>(
        &self,
        key: Vec<u64>,
        keep: bool,
        build: impl FnOnce() -> Result<T, E>,
    ) -> Result<Arc<T>, E> {
        if let Ok(mut list) = self.kept.lock() {
            if let Some(at) = list.iter().position(|(k, _)| *k == key) {
                let hit = list.remove(at);
                let op = Arc::clone(&hit.1);
                list.insert(0, hit);
                return Ok(op);
            }
        }
        let op = Arc::new(build()?);
        if let (true, Ok(mut list)) = (keep, self.kept.lock()) {
            // Another thread may have built it meanwhile: keep one.
            if !list.iter().any(|(k, _)| *k == key) {
                list.insert(0, (key, Arc::clone(&op)));
                list.truncate(KEPT);
            }
        }
        Ok(op)
    }
}

/// The key of a taxel grid `spec` on the element grid `patch`: every number either is built
/// from, bit for bit.
pub(crate) fn taxel_key(spec: &TaxelGridSpec, patch: &GridSpec) -> Vec<u64> {
    let mut k = vec![
        patch.nx as u64,
        patch.ny as u64,
        patch.hx.to_bits(),
        patch.hy.to_bits(),
    ];
    k.extend(spec.count.map(|c| c as u64));
    let numbers = [
        spec.pitch_m,
        spec.size_m,
        spec.depth_m,
        spec.rotation_rad,
        spec.offset_m[0],
        spec.offset_m[1],
    ];
    k.extend(numbers.map(f64::to_bits));
    k
}
