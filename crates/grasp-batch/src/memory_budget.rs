//! The memory the scenes solved at once may take together: each worker admits its scene only
//! when the scene's estimate fits in what the running ones leave of the limit, and waits
//! otherwise (each scene alone is within the limit: `MemoryLimit::check` refused the others),
//! so `--jobs` workers never hold more than `--max-memory` between them by estimate.

use std::sync::{Condvar, Mutex};

/// Bytes left of the batch's limit, shared by the workers.
#[derive(Debug)]
pub struct MemoryBudget {
    /// Bytes not yet admitted.
    free: Mutex<u64>,
    /// Signalled when a scene gives its bytes back.
    returned: Condvar,
}

/// A scene's admitted bytes, given back when it is dropped.
#[derive(Debug)]
pub struct Admitted<'a> {
    budget: &'a MemoryBudget,
    bytes: u64,
}

impl MemoryBudget {
    /// A budget of `bytes`.
    pub fn new(bytes: u64) -> MemoryBudget {
        MemoryBudget {
            free: Mutex::new(bytes),
            returned: Condvar::new(),
        }
    }

    /// Waits until `bytes` (at most the whole budget) are free, and takes them.
    pub fn admit(&self, bytes: u64) -> Admitted<'_> {
        let mut free = self.free.lock().unwrap_or_else(|p| p.into_inner());
        while *free < bytes {
            free = self.returned.wait(free).unwrap_or_else(|p| p.into_inner());
        }
        *free -= bytes;
        Admitted {
            budget: self,
            bytes,
        }
    }

    /// Bytes free now (for the tests).
    #[cfg(test)]
    pub(crate) fn free_bytes(&self) -> u64 {
        *self.free.lock().unwrap_or_else(|p| p.into_inner())
    }
}

impl Drop for Admitted<'_> {
    fn drop(&mut self) {
        let mut free = self.budget.free.lock().unwrap_or_else(|p| p.into_inner());
        *free += self.bytes;
        self.budget.returned.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU64, Ordering};

    /// Eight workers each admitting 3 of a budget of 10 units: never more than 9 held at once
    /// (three scenes), every scene admitted in the end, the budget whole again.
    #[test]
    fn workers_never_hold_more_than_the_budget() {
        let budget = MemoryBudget::new(10);
        let held = AtomicU64::new(0);
        let peak = AtomicU64::new(0);
        std::thread::scope(|s| {
            for _ in 0..8 {
                s.spawn(|| {
                    for _ in 0..20 {
                        let _a = budget.admit(3);
                        let now = held.fetch_add(3, Ordering::SeqCst) + 3;
                        peak.fetch_max(now, Ordering::SeqCst);
                        std::thread::yield_now();
                        held.fetch_sub(3, Ordering::SeqCst);
                    }
                });
            }
        });
        assert!(peak.load(Ordering::SeqCst) <= 9, "{peak:?}");
        assert_eq!(budget.free_bytes(), 10);
    }
}
