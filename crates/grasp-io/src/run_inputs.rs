//! The files a run read (or will read), by identity: an output may never be one of them
//! (`--force` on a scene reached through a symbolic link, a mesh, a schedule's CSV profile
//! or a directions file would otherwise destroy the input).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::input_file::FileIdentity;

/// The input files of a run: identity -> the path it was read by.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RunInputs {
    files: BTreeMap<FileIdentity, PathBuf>,
}

impl RunInputs {
    /// No inputs.
    pub const fn new() -> RunInputs {
        RunInputs {
            files: BTreeMap::new(),
        }
    }

    /// The files at `paths` that exist now (the ones that do not are refused when read).
    pub fn of_paths(paths: &[&Path]) -> RunInputs {
        let mut inputs = RunInputs::new();
        for p in paths {
            inputs.add_existing(p);
        }
        inputs
    }

    /// Notes a file read by `path`.
    pub fn add(&mut self, path: &Path, identity: FileIdentity) {
        self.files
            .entry(identity)
            .or_insert_with(|| path.to_path_buf());
    }

    /// Notes the file `path` names now (links followed), if it exists.
    pub fn add_existing(&mut self, path: &Path) {
        if let Ok(meta) = std::fs::metadata(path) {
            self.add(path, FileIdentity::of(&meta));
        }
    }

    /// Notes every file of `other`.
    pub fn extend(&mut self, other: &RunInputs) {
        for (id, p) in &other.files {
            self.files.entry(*id).or_insert_with(|| p.clone());
        }
    }

    /// The path an input with this identity was read by, if it is one.
    pub fn find(&self, identity: FileIdentity) -> Option<&Path> {
        self.files.get(&identity).map(PathBuf::as_path)
    }

    /// Number of distinct files.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// True when no file was noted.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// The paths, one per distinct file.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.files.values().map(PathBuf::as_path)
    }
}
