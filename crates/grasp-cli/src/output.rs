//! Output files: never overwrite what the user has without `--force`.

use std::io::Write;
use std::path::Path;

use anyhow::{bail, Context, Result};

/// Fails early if `path` exists and `force` is not set; creates its folder if missing.
pub fn check_writable(path: &Path, force: bool) -> Result<()> {
    if path.exists() && !force {
        bail!(
            "{} already exists; pass --force to overwrite it, or choose another name",
            path.display()
        );
    }
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() && !dir.is_dir() {
            std::fs::create_dir_all(dir).with_context(|| {
                format!(
                    "cannot create folder {} for {}",
                    dir.display(),
                    path.display()
                )
            })?;
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file in the same folder, so an interrupted
/// write never leaves a half file in place of the user's.
pub fn write_new(path: &Path, bytes: &[u8], force: bool) -> Result<()> {
    check_writable(path, force)?;
    let tmp = path.with_extension("partial");
    let mut f =
        std::fs::File::create(&tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
    f.write_all(bytes)
        .with_context(|| format!("cannot write {}", tmp.display()))?;
    f.sync_all().ok();
    std::fs::rename(&tmp, path).with_context(|| format!("cannot move into {}", path.display()))?;
    Ok(())
}
