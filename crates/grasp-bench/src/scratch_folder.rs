//! A private scratch folder for the rows that write files (the whole `grasp transfer` command's
//! outputs, a fine patch's solution): `grasp-bench-<pid>-<random>` in the temporary folder,
//! mode 0700, created fresh (an existing folder or link of that name is never used), removed
//! with everything in it when dropped.

use std::path::{Path, PathBuf};

use crate::error::BenchError;

/// Attempts at a fresh scratch folder name.
const SCRATCH_ATTEMPTS: usize = 16;

/// A private scratch folder, removed on drop.
pub(crate) struct ScratchFolder {
    path: PathBuf,
}

impl ScratchFolder {
    /// Creates a fresh folder in the temporary folder.
    pub(crate) fn create() -> Result<ScratchFolder, BenchError> {
        use std::hash::{BuildHasher, Hasher};
        use std::os::unix::fs::DirBuilderExt;
        let base = std::env::temp_dir();
        for attempt in 0..SCRATCH_ATTEMPTS {
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_usize(attempt);
            h.write_u128(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos()),
            );
            let path = base.join(format!(
                "grasp-bench-{}-{:016x}",
                std::process::id(),
                h.finish()
            ));
            // mkdir never follows a link and fails on any existing name.
            match std::fs::DirBuilder::new().mode(0o700).create(&path) {
                Ok(()) => return Ok(ScratchFolder { path }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(source) => {
                    return Err(BenchError::Io {
                        doing: format!("creating {}", path.display()),
                        source,
                    })
                }
            }
        }
        Err(BenchError::NoScratchFolder { base })
    }

    /// The folder.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchFolder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}
