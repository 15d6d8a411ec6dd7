//! Output files: never lose what the user has.
//!
//! - Targets are checked before any work: an existing regular file needs `--force`; a folder,
//!   a symbolic link, a device, a pipe or a socket is refused even with `--force`; the same
//!   file named twice (or naming an input) is refused.
//! - Every output is written to a temporary file in the target's folder,
//!   `.<name>.grasp-tmp-<pid>-<random>` (created new, so it never replaces anything), and moved
//!   into place only when the run succeeds. A failed run removes its temporary files and
//!   leaves the targets untouched; so does SIGINT or SIGTERM (exit 130 or 143), through the
//!   handler installed by [`install_signal_cleanup`].

use std::fs::{File, OpenOptions};
use std::hash::{BuildHasher, Hasher};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{bail, Context, Result};

/// Temporary files of this process not yet moved into place (removed on a signal).
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Installs a handler of SIGINT and SIGTERM that removes the pending temporary files and exits
/// with 128 + the signal number (130, 143).
pub fn install_signal_cleanup() -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])
        .context("cannot install the SIGINT/SIGTERM handler")?;
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            remove_pending_and_exit(128 + sig, |n| {
                Some(format!(
                    "interrupted: {n} temporary output file(s) removed; existing files are \
                     untouched"
                ))
            });
        }
    });
    Ok(())
}

/// Removes the pending temporary files, prints `note(how many)` (if any) on standard error and
/// ends the process with `code`, holding the lock until then: no temporary file is created or
/// moved after this.
pub fn remove_pending_and_exit(code: i32, note: impl FnOnce(usize) -> Option<String>) -> ! {
    let pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
    for p in pending.iter() {
        let _ = std::fs::remove_file(p);
    }
    if let Some(text) = note(pending.len()) {
        eprintln!("{text}");
    }
    std::process::exit(code);
}

/// Refuses targets that cannot be written safely (see the module documentation). `inputs`
/// are the files the command reads.
pub fn check_targets(outputs: &[&Path], inputs: &[&Path], force: bool) -> Result<()> {
    let mut seen: Vec<(PathBuf, &Path)> = inputs.iter().map(|p| (identity(p), *p)).collect();
    let n_inputs = seen.len();
    for (k, out) in outputs.iter().enumerate() {
        check_target(out, force)?;
        let id = identity(out);
        if let Some(i) = seen.iter().position(|(s, _)| *s == id) {
            let what = if i < n_inputs {
                "an input of this command"
            } else {
                "another output of this command"
            };
            bail!(
                "{} is also {what} ({}); give each output its own file",
                out.display(),
                seen[i].1.display()
            );
        }
        seen.push((id, outputs[k]));
    }
    Ok(())
}

/// One target: an existing entry must be a regular file, replaced only with `--force`.
fn check_target(path: &Path, force: bool) -> Result<()> {
    if path.file_name().is_none() {
        bail!("{} does not name a file; give a file name", path.display());
    }
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(());
    };
    let t = meta.file_type();
    let what = if t.is_symlink() {
        "a symbolic link"
    } else if t.is_dir() {
        "a folder"
    } else if !t.is_file() {
        "not a regular file (a device, a pipe or a socket)"
    } else if force {
        return Ok(());
    } else {
        bail!(
            "{} already exists; pass --force to overwrite it, or choose another name",
            path.display()
        );
    };
    bail!(
        "{} is {what}; grasp writes regular files only (even with --force): give a file name \
         that is free or a regular file",
        path.display()
    )
}

/// The file a path names, for comparing targets: canonical folder and file name.
fn identity(path: &Path) -> PathBuf {
    let name = path.file_name().map(PathBuf::from).unwrap_or_default();
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match parent.canonicalize() {
        Ok(dir) => dir.join(name),
        Err(_) => std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
    }
}

/// An output being written to its temporary file; removed on drop unless committed.
pub struct PendingOutput {
    target: PathBuf,
    tmp: PathBuf,
    committed: bool,
}

impl PendingOutput {
    /// Creates the target's folder if missing and a new temporary file beside the target.
    pub fn create(target: &Path) -> Result<(PendingOutput, File)> {
        let dir = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&dir).with_context(|| {
            format!(
                "cannot create folder {} for {}",
                dir.display(),
                target.display()
            )
        })?;
        let name = target.file_name().unwrap_or_default().to_string_lossy();
        for _ in 0..16 {
            let tmp = dir.join(format!(
                ".{name}.grasp-tmp-{}-{:016x}",
                std::process::id(),
                random()
            ));
            let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
            match OpenOptions::new().write(true).create_new(true).open(&tmp) {
                Ok(f) => {
                    pending.push(tmp.clone());
                    let out = PendingOutput {
                        target: target.to_path_buf(),
                        tmp,
                        committed: false,
                    };
                    return Ok((out, f));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => {
                    return Err(e).with_context(|| {
                        format!(
                            "cannot write {} (in folder {})",
                            target.display(),
                            dir.display()
                        )
                    })
                }
            }
        }
        bail!("cannot create a temporary file beside {}", target.display())
    }

    /// The temporary file being written.
    pub fn tmp(&self) -> &Path {
        &self.tmp
    }

    /// The file the user named.
    pub fn target(&self) -> &Path {
        &self.target
    }
}

impl Drop for PendingOutput {
    fn drop(&mut self) {
        if !self.committed {
            let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
            let _ = std::fs::remove_file(&self.tmp);
            pending.retain(|p| *p != self.tmp);
        }
    }
}

/// Moves every output into place at once (a signal waits until all are moved).
pub fn commit_all(outputs: Vec<PendingOutput>) -> Result<()> {
    let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
    for mut o in outputs {
        std::fs::rename(&o.tmp, &o.target).with_context(|| {
            format!(
                "cannot move the output into place at {}",
                o.target.display()
            )
        })?;
        o.committed = true;
        pending.retain(|p| *p != o.tmp);
    }
    Ok(())
}

/// Writes `bytes` to `pending`'s temporary file, naming the target on failure.
pub fn write_all(pending: &PendingOutput, mut file: File, bytes: &[u8]) -> Result<()> {
    let ctx = || format!("cannot write {}", pending.target().display());
    file.write_all(bytes).with_context(ctx)?;
    file.sync_all().with_context(ctx)
}

/// Checks `path` (see [`check_targets`]), writes `bytes` through a temporary file and moves it
/// into place.
pub fn write_new(path: &Path, bytes: &[u8], force: bool) -> Result<()> {
    check_targets(&[path], &[], force)?;
    let (pending, file) = PendingOutput::create(path)?;
    write_all(&pending, file, bytes)?;
    commit_all(vec![pending])
}

/// 64 random bits (the standard library's per-process random hash keys, a counter and the
/// clock): enough that a user cannot own the temporary name in advance.
fn random() -> u64 {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed));
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH);
    h.write_u128(now.map_or(0, |d| d.as_nanos()));
    h.finish()
}
