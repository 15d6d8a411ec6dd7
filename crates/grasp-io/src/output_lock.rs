//! The lock every output holds while a run writes it: an exclusive advisory lock (`flock`) on
//! a lock file beside the target (`.<name>.grasp-lock`), holding the process id of the run.
//! A second run (another process, or another thread of this one) that names the same output
//! is refused at once, told who holds it. The lock ends with the run (also when it is killed:
//! the system releases it); the lock file is removed when the lock is released.
//!
//! A lock file that is no longer the file its path names (removed by its releasing holder
//! between our open and our lock) is let go and opened again, so two runs can never each hold
//! a lock "on" the same target.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::Read;
use std::os::unix::fs::{FileExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

use crate::error::{OutputError, OutputErrorKind};
use crate::input_file::{describe_type, FileIdentity};
use crate::sibling_names::hidden_sibling;
use crate::temporary_files::{register, registry, unregister, Live};

/// Suffix of a lock file's name.
pub const LOCK_SUFFIX: &str = ".grasp-lock";

/// Attempts at locking when the lock file keeps being replaced under us.
const LOCK_ATTEMPTS: usize = 16;

/// A held lock on one output.
#[derive(Debug)]
pub struct OutputLock {
    // Closing the file releases the lock (after the lock file is removed: see Drop).
    file: File,
    path: PathBuf,
    identity: FileIdentity,
}

impl OutputLock {
    /// Takes the lock of `target` (whose folder must exist), or says who holds it.
    pub fn acquire(target: &Path) -> Result<OutputLock, OutputError> {
        let path = hidden_sibling(target, LOCK_SUFFIX);
        for _ in 0..LOCK_ATTEMPTS {
            let file = open_lock_file(target, &path)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => return Err(held_by(target, &path, file)),
                Err(TryLockError::Error(e)) => {
                    return Err(OutputError::io(&path, "lock the output lock file", &e))
                }
            }
            let identity = match file.metadata() {
                Ok(m) => FileIdentity::of(&m),
                Err(e) => return Err(OutputError::io(&path, "read", &e)),
            };
            let still_there = std::fs::symlink_metadata(&path)
                .is_ok_and(|m| m.file_type().is_file() && FileIdentity::of(&m) == identity);
            if !still_there {
                continue; // released and removed meanwhile: open the new one
            }
            let mut list = registry();
            write_holder(&file, &path)?;
            register(&mut list, &path, Live::Lock);
            return Ok(OutputLock {
                file,
                path,
                identity,
            });
        }
        Err(OutputError::new(
            OutputErrorKind::Locked,
            target,
            format!(
                "cannot lock {}: its lock file {} keeps changing",
                target.display(),
                path.display()
            ),
            "another run is starting and ending on the same output; try again",
        ))
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        let mut list = registry();
        // Removed while still held: whoever opened it meanwhile sees it gone and retries.
        let ours = std::fs::symlink_metadata(&self.path)
            .is_ok_and(|m| FileIdentity::of(&m) == self.identity);
        if ours {
            let _ = std::fs::remove_file(&self.path);
        }
        unregister(&mut list, &self.path);
        let _ = self.file.unlock();
    }
}

/// Opens (creating) the lock file, never through a symbolic link, and checks it is a file.
fn open_lock_file(target: &Path, path: &Path) -> Result<File, OutputError> {
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .mode(0o644)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
        .open(path)
        .map_err(|e| {
            let what = std::fs::symlink_metadata(path)
                .map(|m| describe_type(m.file_type()))
                .unwrap_or("unusable");
            if e.raw_os_error() == Some(libc::ELOOP) || what != "unusable" {
                lock_file_refused(target, path, what)
            } else {
                OutputError::io(path, "create the lock file", &e)
            }
        })?;
    match file.metadata() {
        Ok(m) if m.file_type().is_file() => Ok(file),
        Ok(m) => Err(lock_file_refused(
            target,
            path,
            describe_type(m.file_type()),
        )),
        Err(e) => Err(OutputError::io(path, "read", &e)),
    }
}

fn lock_file_refused(target: &Path, path: &Path, what: &str) -> OutputError {
    OutputError::new(
        OutputErrorKind::Refused,
        target,
        format!(
            "the lock file of {} ({}) is {what}, not a lock file of grasp",
            target.display(),
            path.display()
        ),
        "remove it (grasp creates and removes its lock files itself)",
    )
}

/// Writes this process's id into the held lock file, in place and of fixed width (a reader
/// never sees a file cut short, only the previous holder's id or ours).
fn write_holder(file: &File, path: &Path) -> Result<(), OutputError> {
    let text = format!("{:>10}\n", std::process::id());
    file.write_all_at(text.as_bytes(), 0)
        .and_then(|()| file.set_len(text.len() as u64))
        .map_err(|e| OutputError::io(path, "write", &e))
}

/// The refusal when another run holds the lock, naming its process when known.
fn held_by(target: &Path, path: &Path, file: File) -> OutputError {
    let mut text = String::new();
    let _ = file.take(64).read_to_string(&mut text);
    let holder = match text.trim().parse::<u32>() {
        Ok(pid) if pid == std::process::id() => {
            format!("another run of grasp in this process ({pid})")
        }
        Ok(pid) => format!("another run of grasp (process {pid})"),
        Err(_) => "another run of grasp (starting: its process id is not written yet)".into(),
    };
    OutputError::new(
        OutputErrorKind::Locked,
        target,
        format!(
            "{} is being written by {holder}: its lock file {} is held",
            target.display(),
            path.display()
        ),
        "wait until that run ends, or choose another output",
    )
}
