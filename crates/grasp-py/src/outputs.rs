//! Output files of a Python-driven run, with the CLI's rules: nothing the user wrote is
//! replaced unless `overwrite=True`; each file is written under a temporary name beside its
//! target and moved into place only when the run completes (an interrupted or failed run
//! leaves existing files untouched).

use std::path::{Path, PathBuf};

use pyo3::exceptions::{PyFileExistsError, PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;

/// Refuses targets that repeat, overwrite an input, exist (unless `overwrite`), or lie in a
/// folder that does not exist; `names` says which argument each target came from.
pub fn check_targets(targets: &[(&str, &Path)], inputs: &[&Path], overwrite: bool) -> PyResult<()> {
    for (i, (name, t)) in targets.iter().enumerate() {
        if let Some((other, _)) = targets[..i].iter().find(|(_, u)| u == t) {
            return Err(PyValueError::new_err(format!(
                "{name} and {other} are the same file {}; give each output its own path",
                t.display()
            )));
        }
        if inputs.iter().any(|p| same_file(p, t)) {
            return Err(PyValueError::new_err(format!(
                "{name}={} is an input of this run; choose another output path",
                t.display()
            )));
        }
        if t.exists() && !overwrite {
            return Err(PyFileExistsError::new_err(format!(
                "{name}={} exists; pass overwrite=True to replace it",
                t.display()
            )));
        }
        let parent = t.parent().filter(|p| !p.as_os_str().is_empty());
        if parent.is_some_and(|p| !p.is_dir()) {
            return Err(PyFileNotFoundError::new_err(format!(
                "{name}={}: the folder does not exist; create it first",
                t.display()
            )));
        }
    }
    Ok(())
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// A file being written under a temporary name; removed on drop unless committed.
pub struct Pending {
    pub tmp: PathBuf,
    pub target: PathBuf,
    committed: bool,
}

impl Pending {
    /// The temporary name of `target`: a hidden file in the same folder (so the final
    /// rename stays on one file system).
    pub fn new(target: &Path) -> Pending {
        let name = target
            .file_name()
            .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        let tmp = target.with_file_name(format!(".{name}.partial-{}", std::process::id()));
        Pending {
            tmp,
            target: target.to_path_buf(),
            committed: false,
        }
    }

    /// Moves the finished file into place.
    pub fn commit(mut self) -> std::io::Result<()> {
        std::fs::rename(&self.tmp, &self.target)?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}
