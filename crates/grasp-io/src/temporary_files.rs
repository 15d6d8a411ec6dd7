//! The hidden files this process has live beside its outputs (temporary files not yet moved
//! into place, lock files held), so that a signal handler can remove them before the process
//! ends: [`remove_all_for_exit`].

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// What a live file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Live {
    /// A temporary output, moved into place on success.
    Temporary,
    /// An output's lock file.
    Lock,
}

static LIVE: Mutex<Vec<(PathBuf, Live)>> = Mutex::new(Vec::new());

/// The registry, locked (a panic elsewhere does not make it unusable).
pub(crate) fn registry() -> MutexGuard<'static, Vec<(PathBuf, Live)>> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Notes a live file.
pub(crate) fn register(list: &mut Vec<(PathBuf, Live)>, path: &Path, kind: Live) {
    list.push((path.to_path_buf(), kind));
}

/// Forgets a file (moved into place, or removed).
pub(crate) fn unregister(list: &mut Vec<(PathBuf, Live)>, path: &Path) {
    list.retain(|(p, _)| p != path);
}

/// Removes every live temporary and lock file of this process and keeps the registry locked,
/// so no temporary file is created or moved into place afterwards; for a signal handler that
/// then ends the process. Returns the number of temporary outputs removed.
pub fn remove_all_for_exit() -> usize {
    let list = registry();
    let mut removed = 0;
    for (p, kind) in list.iter() {
        if std::fs::remove_file(p).is_ok() && *kind == Live::Temporary {
            removed += 1;
        }
    }
    // Held until the process exits.
    std::mem::forget(list);
    removed
}
