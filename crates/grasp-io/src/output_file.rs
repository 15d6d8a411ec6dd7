//! The one output policy of the project (the CLI and the Python module both write through it):
//! nothing the user has is lost or replaced without asking.
//!
//! - Targets are checked before any work ([`OutputSet::claim`]): a folder, a symbolic link
//!   (a dangling one too), a device, a FIFO or a socket is refused even with
//!   [`OutputRules::force`]; an existing regular file needs `force`; a target that is one of
//!   the run's inputs (by device and inode, so a scene reached through a link or a hard link
//!   counts) or another of its outputs is refused.
//! - Each target is locked for the whole run ([`crate::output_lock`]): a second run writing
//!   the same file is refused and told who holds it.
//! - Each output is written to a temporary file in the target's folder, with a name no one can
//!   guess (`.<name>.grasp-tmp-<pid>-<random>`), created exclusively and never through a link
//!   (`O_CREAT | O_EXCL | O_NOFOLLOW`), and moved into place only when the run succeeds
//!   ([`OutputSet::commit`]): without `force`, without replacing anything (a hard link that
//!   fails if the target appeared meanwhile); with `force`, by a rename that replaces only a
//!   regular file. A failed run removes its temporary files and leaves the targets untouched;
//!   a signal handler can do the same ([`crate::temporary_files::remove_all_for_exit`]).

use std::fs::{File, OpenOptions};
use std::hash::{BuildHasher, Hasher};
use std::io::Write;
use std::os::fd::AsRawFd;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Component, Path, PathBuf};

use crate::error::{OutputError, OutputErrorKind};
use crate::input_file::{describe_type, FileIdentity};
use crate::output_lock::OutputLock;
use crate::run_inputs::RunInputs;
use crate::sibling_names::{folder_of, hidden_sibling};
use crate::temporary_files::{register, registry, unregister, Live};

/// The option that allows replacing an existing file, as the API spells it in messages.
pub const FORCE: &str = "OutputRules::force";

/// Attempts at a fresh temporary name (each has 64 random bits).
const TEMPORARY_ATTEMPTS: usize = 16;

/// How a run's outputs may be written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OutputRules {
    /// Replace existing regular files (the CLI's `--force`, Python's `overwrite=True`).
    pub force: bool,
    /// Create a target's missing folders (the CLI, which says so); otherwise a missing
    /// folder is refused (Python).
    pub create_folders: bool,
}

/// One claimed target: checked, its folder present, locked.
#[derive(Debug)]
struct Claimed {
    target: PathBuf,
    _lock: OutputLock,
}

/// The outputs of a run, checked and locked until dropped.
#[derive(Debug)]
pub struct OutputSet {
    rules: OutputRules,
    claimed: Vec<Claimed>,
    created_folders: Vec<PathBuf>,
}

impl OutputSet {
    /// Checks every target against the policy (module documentation) and `inputs`, creates
    /// missing folders if the rules allow, and locks every target.
    pub fn claim(
        targets: &[&Path],
        inputs: &RunInputs,
        rules: OutputRules,
    ) -> Result<OutputSet, OutputError> {
        let mut seen: Vec<(PathBuf, Option<FileIdentity>, &Path)> = Vec::new();
        for t in targets {
            let identity = check_target(t, inputs, rules.force)?;
            let key = location_key(t);
            let same = seen
                .iter()
                .find(|(k, id, _)| *k == key || (identity.is_some() && *id == identity));
            if let Some((_, _, other)) = same {
                return Err(OutputError::new(
                    OutputErrorKind::Refused,
                    t,
                    format!(
                        "{} is also another output of this command ({})",
                        t.display(),
                        other.display()
                    ),
                    "give each output its own file",
                ));
            }
            seen.push((key, identity, t));
        }
        let mut set = OutputSet {
            rules,
            claimed: Vec::new(),
            created_folders: Vec::new(),
        };
        for t in targets {
            if let Err(e) = set.claim_one(t, inputs) {
                set.claimed.clear();
                for f in set.created_folders.iter().rev() {
                    let _ = std::fs::remove_dir(f);
                }
                return Err(e);
            }
        }
        Ok(set)
    }

    /// Makes the target's folder, locks the target, and checks it again under the lock.
    fn claim_one(&mut self, target: &Path, inputs: &RunInputs) -> Result<(), OutputError> {
        self.ensure_folder(target)?;
        let lock = OutputLock::acquire(target)?;
        check_target(target, inputs, self.rules.force)?;
        self.claimed.push(Claimed {
            target: target.to_path_buf(),
            _lock: lock,
        });
        Ok(())
    }

    /// The folder of `target` exists, or is created (noted) when the rules allow.
    fn ensure_folder(&mut self, target: &Path) -> Result<(), OutputError> {
        let folder = folder_of(target);
        match std::fs::metadata(&folder) {
            Ok(m) if m.is_dir() => return Ok(()),
            Ok(_) => {
                return Err(OutputError::new(
                    OutputErrorKind::Refused,
                    target,
                    format!("{}: {} is not a folder", target.display(), folder.display()),
                    "give a path inside a folder",
                ))
            }
            Err(_) if !self.rules.create_folders => {
                return Err(OutputError::new(
                    OutputErrorKind::MissingFolder,
                    target,
                    format!(
                        "{}: the folder {} does not exist",
                        target.display(),
                        folder.display()
                    ),
                    "create it first",
                ))
            }
            Err(_) => {}
        }
        let missing: Vec<PathBuf> = folder
            .ancestors()
            .take_while(|a| !a.as_os_str().is_empty() && std::fs::metadata(a).is_err())
            .map(Path::to_path_buf)
            .collect();
        std::fs::create_dir_all(&folder).map_err(|e| {
            OutputError::io(
                &folder,
                &format!("create folder for {}", target.display()),
                &e,
            )
        })?;
        self.created_folders.extend(missing.into_iter().rev());
        Ok(())
    }

    /// The folders [`OutputSet::claim`] created, outermost first.
    pub fn created_folders(&self) -> &[PathBuf] {
        &self.created_folders
    }

    /// The rules of this set.
    pub fn rules(&self) -> OutputRules {
        self.rules
    }

    /// Refuses a claimed target that is one of `inputs` (files learned after the claim: the
    /// meshes of a scene, the CSV profiles of a schedule, the files of a batch's lines).
    pub fn refuse_inputs(&self, inputs: &RunInputs) -> Result<(), OutputError> {
        for c in &self.claimed {
            if let Ok(m) = std::fs::metadata(&c.target) {
                if let Some(input) = inputs.find(FileIdentity::of(&m)) {
                    return Err(is_input(&c.target, input));
                }
            }
        }
        Ok(())
    }

    /// A new temporary file for the claimed `target`.
    pub fn create(&self, target: &Path) -> Result<PendingOutput, OutputError> {
        self.claimed_target(target)?;
        for _ in 0..TEMPORARY_ATTEMPTS {
            let tmp = hidden_sibling(
                target,
                &format!(".grasp-tmp-{}-{:016x}", std::process::id(), random()),
            );
            let mut list = registry();
            let opened = OpenOptions::new()
                .write(true)
                .create_new(true)
                .mode(0o666)
                .custom_flags(libc::O_NOFOLLOW)
                .open(&tmp);
            match opened {
                Ok(file) => {
                    register(&mut list, &tmp, Live::Temporary);
                    return Ok(PendingOutput {
                        target: target.to_path_buf(),
                        tmp,
                        file,
                        committed: false,
                    });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(OutputError::io(target, "write", &e)),
            }
        }
        Err(OutputError::new(
            OutputErrorKind::Io,
            target,
            format!("cannot create a temporary file beside {}", target.display()),
            "check the folder",
        ))
    }

    /// Opens the claimed `target` for appending (created if missing; never through a link):
    /// a resumed batch writes its lines straight into its output, under the lock.
    pub fn open_append(&self, target: &Path) -> Result<File, OutputError> {
        self.claimed_target(target)?;
        let file = OpenOptions::new()
            .read(true)
            .append(true)
            .create(true)
            .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
            .open(target)
            .map_err(|e| OutputError::io(target, "write", &e))?;
        match file.metadata() {
            Ok(m) if m.file_type().is_file() => Ok(file),
            Ok(m) => Err(not_writable(target, describe_type(m.file_type()))),
            Err(e) => Err(OutputError::io(target, "write", &e)),
        }
    }

    /// Moves every output into place (see the module documentation); a signal waits until
    /// all are moved. Outputs not moved (after an error) have their temporary files removed.
    pub fn commit(&self, mut outputs: Vec<PendingOutput>) -> Result<(), OutputError> {
        for o in &outputs {
            o.file
                .sync_all()
                .map_err(|e| OutputError::io(&o.target, "write", &e))?;
        }
        let mut list = registry();
        let mut result = Ok(());
        for o in outputs.iter_mut() {
            result = self.move_into_place(o);
            if result.is_err() {
                break;
            }
            o.committed = true;
            unregister(&mut list, &o.tmp);
        }
        drop(list);
        drop(outputs);
        result
    }

    /// Writes `bytes` to `target` through a temporary file and moves it into place.
    pub fn write(&self, target: &Path, bytes: &[u8]) -> Result<(), OutputError> {
        let mut pending = self.create(target)?;
        pending.write_all(bytes)?;
        self.commit(vec![pending])
    }

    fn claimed_target(&self, target: &Path) -> Result<(), OutputError> {
        if self.claimed.iter().any(|c| c.target == target) {
            return Ok(());
        }
        Err(OutputError::new(
            OutputErrorKind::Refused,
            target,
            format!(
                "{} was not checked and locked before writing",
                target.display()
            ),
            "claim every output first (`OutputSet::claim`)",
        ))
    }

    fn move_into_place(&self, o: &PendingOutput) -> Result<(), OutputError> {
        if self.rules.force {
            if let Ok(m) = std::fs::symlink_metadata(&o.target) {
                if !m.file_type().is_file() {
                    return Err(refused_kind(&o.target, &m));
                }
            }
            return std::fs::rename(&o.tmp, &o.target)
                .map_err(|e| OutputError::io(&o.target, "move the output into place at", &e));
        }
        match std::fs::hard_link(&o.tmp, &o.target) {
            Ok(()) => {
                let _ = std::fs::remove_file(&o.tmp);
                Ok(())
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(appeared(&o.target)),
            // A file system without hard links: check, then rename (the one window left).
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::PermissionDenied | std::io::ErrorKind::Unsupported
                ) =>
            {
                if std::fs::symlink_metadata(&o.target).is_ok() {
                    return Err(appeared(&o.target));
                }
                std::fs::rename(&o.tmp, &o.target)
                    .map_err(|e| OutputError::io(&o.target, "move the output into place at", &e))
            }
            Err(e) => Err(OutputError::io(
                &o.target,
                "move the output into place at",
                &e,
            )),
        }
    }
}

/// An output being written to its temporary file; removed on drop unless committed.
#[derive(Debug)]
pub struct PendingOutput {
    target: PathBuf,
    tmp: PathBuf,
    file: File,
    committed: bool,
}

impl PendingOutput {
    /// The temporary file, open for writing.
    pub fn file(&self) -> &File {
        &self.file
    }

    /// Another handle of the temporary file (for a writer that takes ownership of one).
    pub fn file_handle(&self) -> Result<File, OutputError> {
        self.file
            .try_clone()
            .map_err(|e| OutputError::io(&self.target, "write", &e))
    }

    /// A path that opens this very temporary file, whatever happens to its name meanwhile
    /// (`/proc/self/fd/N`), for writers that open a path themselves; the temporary path
    /// where `/proc` is not mounted.
    pub fn write_path(&self) -> PathBuf {
        let fd_path = PathBuf::from(format!("/proc/self/fd/{}", self.file.as_raw_fd()));
        if fd_path.exists() {
            fd_path
        } else {
            self.tmp.clone()
        }
    }

    /// The temporary file's path.
    pub fn tmp(&self) -> &Path {
        &self.tmp
    }

    /// The file the user named.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Writes all of `bytes`, naming the target on failure.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<(), OutputError> {
        (&self.file)
            .write_all(bytes)
            .map_err(|e| OutputError::io(&self.target, "write", &e))
    }
}

impl Drop for PendingOutput {
    fn drop(&mut self) {
        if !self.committed {
            let mut list = registry();
            let _ = std::fs::remove_file(&self.tmp);
            unregister(&mut list, &self.tmp);
        }
    }
}

/// One target as it is now: refused (see the module documentation), or fine; the identity of
/// the regular file there, if any.
fn check_target(
    path: &Path,
    inputs: &RunInputs,
    force: bool,
) -> Result<Option<FileIdentity>, OutputError> {
    let named = path.file_name().is_some_and(|n| n != "." && n != "..");
    if !named {
        return Err(OutputError::new(
            OutputErrorKind::Refused,
            path,
            format!("{} does not name a file", path.display()),
            "give a file name",
        ));
    }
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        // Missing, or under a path that is no folder (refused when the folder is made).
        Err(e)
            if e.kind() == std::io::ErrorKind::NotFound
                || e.raw_os_error() == Some(libc::ENOTDIR) =>
        {
            return Ok(None)
        }
        Err(e) => return Err(OutputError::io(path, "write", &e)),
    };
    if !meta.file_type().is_file() {
        return Err(refused_kind(path, &meta));
    }
    let identity = FileIdentity::of(&meta);
    if let Some(input) = inputs.find(identity) {
        return Err(is_input(path, input));
    }
    if !force {
        return Err(OutputError::new(
            OutputErrorKind::Exists,
            path,
            format!("{} already exists", path.display()),
            &format!("pass `{FORCE}` to replace it, or choose another name"),
        ));
    }
    Ok(Some(identity))
}

fn refused_kind(path: &Path, meta: &std::fs::Metadata) -> OutputError {
    let t = meta.file_type();
    let what = if t.is_symlink() {
        match std::fs::metadata(path) {
            Ok(_) => "a symbolic link".to_string(),
            Err(_) => "a symbolic link (dangling: its file does not exist)".to_string(),
        }
    } else if t.is_dir() {
        "a folder".to_string()
    } else {
        format!("not a regular file ({})", describe_type(t))
    };
    not_writable(path, &what)
}

fn not_writable(path: &Path, what: &str) -> OutputError {
    OutputError::new(
        OutputErrorKind::Refused,
        path,
        format!(
            "{} is {what}; grasp writes regular files only, even with `{FORCE}`",
            path.display()
        ),
        "give a file name that is free or names a regular file",
    )
}

fn is_input(path: &Path, input: &Path) -> OutputError {
    OutputError::new(
        OutputErrorKind::Refused,
        path,
        format!(
            "{} is also an input of this command ({})",
            path.display(),
            input.display()
        ),
        "write the output to another file",
    )
}

fn appeared(path: &Path) -> OutputError {
    OutputError::new(
        OutputErrorKind::Exists,
        path,
        format!(
            "{} appeared while the run was writing it (another program created it); it is kept \
             and this output was not written",
            path.display()
        ),
        &format!("move it away, or pass `{FORCE}`, and run again"),
    )
}

/// Where a target is, for comparing targets: its folder resolved (links, `..`) where it
/// exists, else the absolute path with `.` and `..` resolved by name.
fn location_key(path: &Path) -> PathBuf {
    let name = path.file_name().map(PathBuf::from).unwrap_or_default();
    if let Ok(dir) = folder_of(path).canonicalize() {
        return dir.join(name);
    }
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// 64 random bits (the standard library's per-process random hash keys, a counter and the
/// clock): enough that no one can create the temporary name in advance.
fn random() -> u64 {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed));
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH);
    h.write_u128(now.map_or(0, |d| d.as_nanos()));
    h.finish()
}
