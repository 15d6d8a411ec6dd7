//! Names of the hidden files an output keeps beside its target while it is written: its
//! temporary files (`.<name>.grasp-tmp-<pid>-<random>`) and its lock file
//! (`.<name>.grasp-lock`). In the target's own folder, so moving a finished file into place is
//! a rename within one file system. A long target name is shortened (with a hash of the whole
//! name, so two long names stay apart) to keep within the 255 bytes a file name may have.

use std::ffi::OsString;
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::{Path, PathBuf};

/// Longest part of the target's name kept in a sibling's name, bytes.
const MAX_KEPT_NAME_BYTES: usize = 160;

/// The folder of `target` (`.` for a bare file name).
pub fn folder_of(target: &Path) -> PathBuf {
    match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `.<name><suffix>` in the folder of `target`.
pub fn hidden_sibling(target: &Path, suffix: &str) -> PathBuf {
    let name = target.file_name().unwrap_or_default().as_bytes();
    let mut out = b".".to_vec();
    if name.len() > MAX_KEPT_NAME_BYTES {
        out.extend_from_slice(&name[..MAX_KEPT_NAME_BYTES]);
        out.extend_from_slice(format!("-{:016x}", fnv1a(name)).as_bytes());
    } else {
        out.extend_from_slice(name);
    }
    out.extend_from_slice(suffix.as_bytes());
    folder_of(target).join(OsString::from_vec(out))
}

/// FNV-1a, 64 bits: a hash that is the same in every build (the CLI and the Python module
/// must find the same lock file).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stay_short_and_apart() {
        assert_eq!(
            hidden_sibling(Path::new("out/a.csv"), ".grasp-lock"),
            Path::new("out/.a.csv.grasp-lock")
        );
        assert_eq!(
            hidden_sibling(Path::new("a.csv"), ".x"),
            Path::new("./.a.csv.x")
        );
        let a = "a".repeat(250);
        let b = format!("{}b", "a".repeat(249));
        let (sa, sb) = (
            hidden_sibling(Path::new(&a), ".grasp-lock"),
            hidden_sibling(Path::new(&b), ".grasp-lock"),
        );
        assert_ne!(sa, sb);
        assert!(sa.file_name().unwrap().len() < 255);
    }
}
