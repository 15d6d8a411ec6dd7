//! Every file the project reads goes through here: scenes, schedules, CSV load profiles,
//! meshes, height maps, direction files, batch inputs and their folder entries, shard outputs to merge, a
//! batch output to resume; and the files of `grasp.mujoco` (state files, rollouts, material
//! maps; a MuJoCo model is checked here before MuJoCo reads it).
//!
//! A read is of a regular file only: the path is checked before opening (a FIFO is never
//! opened, so it cannot block; a device such as `/dev/zero` is never read), and the opened
//! file is checked again (nothing can be swapped in between). Each kind of file has a size
//! limit ([`InputKind`]); the size is checked before reading and the read itself is bounded,
//! so a file that grows while being read cannot run away. Line files (JSONL) are read line by
//! line, each line bounded ([`MAX_LINE_BYTES`]), a line that is not UTF-8 reported as such
//! rather than ending the file.

use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Read, Take};
use std::os::unix::fs::{FileTypeExt, MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

use crate::error::InputFileError;

const MIB: u64 = 1 << 20;

/// A kind of input file: how messages name it and the largest it may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputKind {
    /// The name in messages ("scene file").
    pub what: &'static str,
    /// Largest size read, bytes.
    pub max_bytes: u64,
}

/// A scene (JSON), 64 MiB.
pub const SCENE_FILE: InputKind = InputKind {
    what: "scene file",
    max_bytes: 64 * MIB,
};
/// A load schedule (JSON), 64 MiB.
pub const SCHEDULE_FILE: InputKind = InputKind {
    what: "schedule file",
    max_bytes: 64 * MIB,
};
/// A CSV load profile of a schedule, 64 MiB.
pub const LOAD_PROFILE: InputKind = InputKind {
    what: "CSV profile",
    max_bytes: 64 * MIB,
};
/// An OBJ or STL mesh, 256 MiB (about 5 million triangles of binary STL).
pub const MESH_FILE: InputKind = InputKind {
    what: "mesh file",
    max_bytes: 256 * MIB,
};
/// A height map of a finger's texture (`.npy` or `.csv`), 256 MiB (a 4096 x 8192 map of
/// `f64`).
pub const HEIGHT_MAP_FILE: InputKind = InputKind {
    what: "height map file",
    max_bytes: 256 * MIB,
};
/// The JSONL input of a batch, 1 TiB: read line by line (memory is bounded by
/// [`MAX_LINE_BYTES`]); the size limit only stops a runaway file.
pub const BATCH_INPUT: InputKind = InputKind {
    what: "batch input",
    max_bytes: 1 << 40,
};
/// A shard's output to merge, read line by line, 1 TiB.
pub const SHARD_OUTPUT: InputKind = InputKind {
    what: "shard output",
    max_bytes: 1 << 40,
};
/// A batch output read back to resume, line by line, 1 TiB.
pub const BATCH_OUTPUT: InputKind = InputKind {
    what: "batch output",
    max_bytes: 1 << 40,
};
/// A MuJoCo model (MJCF or binary `.mjb`) of `grasp.mujoco`, checked before MuJoCo reads it,
/// 256 MiB.
pub const MUJOCO_MODEL: InputKind = InputKind {
    what: "MuJoCo model",
    max_bytes: 256 * MIB,
};
/// A MuJoCo state file of `grasp.mujoco` (qpos text, `.npy`, `.npz`, JSON), 64 MiB.
pub const MUJOCO_STATE: InputKind = InputKind {
    what: "state file",
    max_bytes: 64 * MIB,
};
/// A recorded MuJoCo rollout (`.npz`) of `grasp.mujoco`, 1 GiB.
pub const MUJOCO_ROLLOUT: InputKind = InputKind {
    what: "rollout",
    max_bytes: 1024 * MIB,
};
/// The material map (JSON) of `grasp.mujoco`, 64 MiB.
pub const MATERIAL_MAP: InputKind = InputKind {
    what: "material map",
    max_bytes: 64 * MIB,
};
/// A system file (`/proc/meminfo`), 1 MiB.
pub const SYSTEM_FILE: InputKind = InputKind {
    what: "system file",
    max_bytes: MIB,
};

/// Longest line of a line file (JSONL) read, bytes: a line holds one scene, so it has the
/// scene file's limit.
pub const MAX_LINE_BYTES: u64 = SCENE_FILE.max_bytes;

/// The file a path named when it was opened (device and inode): the same for every path that
/// reaches it (symbolic links, hard links, `..`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FileIdentity {
    /// Device number.
    pub device: u64,
    /// Inode number on that device.
    pub inode: u64,
}

impl FileIdentity {
    /// The identity of a file's metadata.
    pub fn of(meta: &std::fs::Metadata) -> FileIdentity {
        FileIdentity {
            device: meta.dev(),
            inode: meta.ino(),
        }
    }
}

/// What a file type is, for messages ("a folder", "a FIFO (named pipe)", ...).
pub fn describe_type(t: std::fs::FileType) -> &'static str {
    if t.is_dir() {
        "a folder"
    } else if t.is_symlink() {
        "a symbolic link"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}

/// An opened input file, checked regular and within its kind's limit.
#[derive(Debug)]
pub struct InputFile {
    file: File,
    path: PathBuf,
    kind: InputKind,
    identity: FileIdentity,
    len: u64,
}

impl InputFile {
    /// Opens `path` as a `kind` file (see the module documentation).
    pub fn open(path: &Path, kind: InputKind) -> Result<InputFile, InputFileError> {
        let unreadable = |e: std::io::Error| {
            InputFileError::new(
                path,
                format!("cannot read {} {}: {e}", kind.what, path.display()),
                &format!("give an existing, readable {}", kind.what),
            )
        };
        // Checked before opening: opening a FIFO would block, opening a device may act.
        let before = std::fs::metadata(path).map_err(unreadable)?;
        check_regular(path, kind, &before)?;
        let file = OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY)
            .open(path)
            .map_err(unreadable)?;
        // And the file opened: nothing was swapped in between.
        let meta = file.metadata().map_err(unreadable)?;
        check_regular(path, kind, &meta)?;
        if meta.len() > kind.max_bytes {
            return Err(too_large(path, kind, meta.len()));
        }
        Ok(InputFile {
            file,
            path: path.to_path_buf(),
            kind,
            identity: FileIdentity::of(&meta),
            len: meta.len(),
        })
    }

    /// The file's identity (device and inode).
    pub fn identity(&self) -> FileIdentity {
        self.identity
    }

    /// The path it was opened by.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Its size when opened, bytes.
    pub fn len(&self) -> u64 {
        self.len
    }

    /// True for an empty file.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The whole file, at most the kind's limit (a file that grew beyond it is refused).
    pub fn read_bytes(self) -> Result<Vec<u8>, InputFileError> {
        let (path, kind) = (self.path.clone(), self.kind);
        let mut bytes = Vec::new();
        self.file
            .take(kind.max_bytes + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| {
                InputFileError::new(
                    &path,
                    format!("cannot read {} {}: {e}", kind.what, path.display()),
                    &format!("give a readable {}", kind.what),
                )
            })?;
        if bytes.len() as u64 > kind.max_bytes {
            return Err(InputFileError::new(
                &path,
                format!(
                    "{} {} grew beyond {} MiB while being read",
                    kind.what,
                    path.display(),
                    kind.max_bytes / MIB
                ),
                &format!("give a {} that is not being written", kind.what),
            ));
        }
        Ok(bytes)
    }

    /// The whole file as UTF-8 text (see [`InputFile::read_bytes`]).
    pub fn read_text(self) -> Result<String, InputFileError> {
        let (path, kind) = (self.path.clone(), self.kind);
        String::from_utf8(self.read_bytes()?).map_err(|e| {
            InputFileError::new(
                &path,
                format!("{} {} is not UTF-8 text: {e}", kind.what, path.display()),
                "save it as plain (UTF-8) text",
            )
        })
    }

    /// The file line by line, reading at most the size it had when opened.
    pub fn lines(self) -> LineReader {
        let len = self.len;
        self.lines_upto(len)
    }

    /// The file line by line, reading at most `len` bytes (the size it had at an earlier
    /// pass: what was appended since is not read).
    pub fn lines_upto(self, len: u64) -> LineReader {
        let len = len.min(self.len);
        LineReader {
            reader: BufReader::with_capacity(1 << 16, self.file.take(len)),
            path: self.path,
            kind: self.kind,
            number: 0,
            offset: 0,
        }
    }
}

/// Reads a whole `kind` file as UTF-8 text; returns it with the file's identity.
pub fn read_text(path: &Path, kind: InputKind) -> Result<(String, FileIdentity), InputFileError> {
    let file = InputFile::open(path, kind)?;
    let identity = file.identity();
    Ok((file.read_text()?, identity))
}

/// Reads a whole `kind` file; returns its bytes with the file's identity.
pub fn read_bytes(path: &Path, kind: InputKind) -> Result<(Vec<u8>, FileIdentity), InputFileError> {
    let file = InputFile::open(path, kind)?;
    let identity = file.identity();
    Ok((file.read_bytes()?, identity))
}

fn check_regular(
    path: &Path,
    kind: InputKind,
    meta: &std::fs::Metadata,
) -> Result<(), InputFileError> {
    if meta.file_type().is_file() {
        return Ok(());
    }
    Err(InputFileError::new(
        path,
        format!(
            "{} {} is {}, not a regular file",
            kind.what,
            path.display(),
            describe_type(meta.file_type())
        ),
        &format!("give a {} (a regular file)", kind.what),
    ))
}

fn too_large(path: &Path, kind: InputKind, bytes: u64) -> InputFileError {
    InputFileError::new(
        path,
        format!(
            "{} {} has {bytes} bytes, more than the {} MiB a {} may have",
            kind.what,
            path.display(),
            kind.max_bytes / MIB,
            kind.what
        ),
        &format!("give a smaller {}", kind.what),
    )
}

/// What one line of a line file holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LineText {
    /// UTF-8 text, without its line ending (`\n` or `\r\n`).
    Text(String),
    /// Bytes that are not UTF-8 (the first bad one at this byte of the line).
    NotUtf8 {
        /// Bytes of valid UTF-8 before the first invalid one.
        valid_up_to: usize,
        /// The line's bytes, without its line ending.
        bytes: Vec<u8>,
    },
    /// A line longer than [`MAX_LINE_BYTES`] (skipped unread).
    TooLong {
        /// Its length, bytes.
        bytes: u64,
    },
}

/// One line of a line file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileLine {
    /// Line number, 1-based.
    pub number: usize,
    /// Byte offset of the line's start in the file.
    pub start: u64,
    /// True when the line ends with `\n` (false only for an unfinished last line).
    pub terminated: bool,
    /// What it holds.
    pub text: LineText,
}

impl FileLine {
    /// A problem with the line's content as a sentence (None for text).
    pub fn problem(&self) -> Option<String> {
        match &self.text {
            LineText::Text(_) => None,
            LineText::NotUtf8 { valid_up_to, .. } => Some(format!(
                "line {} is not UTF-8 text (invalid byte after {valid_up_to} bytes)",
                self.number
            )),
            LineText::TooLong { bytes } => Some(format!(
                "line {} has {bytes} bytes, more than the {} MiB a line may have",
                self.number,
                MAX_LINE_BYTES / MIB
            )),
        }
    }
}

/// The lines of a file, each read with a bound.
#[derive(Debug)]
pub struct LineReader {
    reader: BufReader<Take<File>>,
    path: PathBuf,
    kind: InputKind,
    number: usize,
    offset: u64,
}

impl LineReader {
    /// The next line, or `None` at the end of the file.
    pub fn next_line(&mut self) -> Result<Option<FileLine>, InputFileError> {
        let start = self.offset;
        let (bytes, total, terminated) = self.read_bounded().map_err(|e| {
            InputFileError::new(
                &self.path,
                format!(
                    "cannot read {} {}: {e}",
                    self.kind.what,
                    self.path.display()
                ),
                &format!("give a readable {}", self.kind.what),
            )
        })?;
        if total == 0 {
            return Ok(None);
        }
        self.number += 1;
        self.offset += total;
        let text = match bytes {
            None => LineText::TooLong { bytes: total },
            Some(mut b) => {
                if b.last() == Some(&b'\n') {
                    b.pop();
                    if b.last() == Some(&b'\r') {
                        b.pop();
                    }
                }
                match String::from_utf8(b) {
                    Ok(s) => LineText::Text(s),
                    Err(e) => LineText::NotUtf8 {
                        valid_up_to: e.utf8_error().valid_up_to(),
                        bytes: e.into_bytes(),
                    },
                }
            }
        };
        Ok(Some(FileLine {
            number: self.number,
            start,
            terminated,
            text,
        }))
    }

    /// Bytes of the next line (None when longer than the limit: skipped), the bytes it took,
    /// and whether it ended with `\n`.
    fn read_bounded(&mut self) -> std::io::Result<(Option<Vec<u8>>, u64, bool)> {
        let mut buf = Some(Vec::new());
        let mut total = 0u64;
        loop {
            let avail = self.reader.fill_buf()?;
            if avail.is_empty() {
                return Ok((buf, total, false));
            }
            let (n, found) = match avail.iter().position(|&b| b == b'\n') {
                Some(i) => (i + 1, true),
                None => (avail.len(), false),
            };
            if let Some(b) = buf.as_mut() {
                if (b.len() + n) as u64 > MAX_LINE_BYTES + 2 {
                    buf = None;
                } else {
                    b.extend_from_slice(&avail[..n]);
                }
            }
            total += n as u64;
            self.reader.consume(n);
            if found {
                return Ok((buf, total, true));
            }
        }
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// The entries of folder `dir` whose name ends in `.{extension}` (folders among them left
/// out), sorted by name; at most `max_entries`. Each entry is read later through
/// [`InputFile`], so a FIFO or a device named `*.json` is refused when read.
pub fn folder_entries(
    dir: &Path,
    extension: &str,
    max_entries: usize,
) -> Result<Vec<PathBuf>, InputFileError> {
    let unreadable = |e: std::io::Error| {
        InputFileError::new(
            dir,
            format!("cannot list folder {}: {e}", dir.display()),
            "give a readable folder",
        )
    };
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(unreadable)? {
        let path = entry.map_err(unreadable)?.path();
        if path.extension().is_none_or(|x| x != extension) || path.is_dir() {
            continue;
        }
        if files.len() == max_entries {
            return Err(InputFileError::new(
                dir,
                format!(
                    "folder {} holds more than {max_entries} .{extension} files",
                    dir.display()
                ),
                "split it into several folders",
            ));
        }
        files.push(path);
    }
    files.sort();
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("grasp-io-input-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn only_regular_files_are_read() {
        let d = scratch("kinds");
        let fifo = d.join("pipe.json");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.as_ref().is_ok_and(|s| s.success()), "mkfifo: {made:?}");
        let mut cases: Vec<(PathBuf, &str)> = vec![
            ("/dev/zero".into(), "a device"),
            ("/dev/null".into(), "a device"),
            (d.clone(), "a folder"),
            (fifo, "a FIFO"),
        ];
        let link = d.join("link.json");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        cases.push((link, "a device"));
        for (path, kind) in cases {
            let e = InputFile::open(&path, SCENE_FILE).unwrap_err();
            assert!(
                e.message.contains(kind) && e.message.contains("not a regular file"),
                "{path:?}: {e}"
            );
        }
        // A link to a regular file is read (the file it names is checked).
        let real = d.join("real.json");
        std::fs::write(&real, "{}").unwrap();
        let link = d.join("to-real.json");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let (text, id) = read_text(&link, SCENE_FILE).unwrap();
        assert_eq!(text, "{}");
        assert_eq!(id, read_text(&real, SCENE_FILE).unwrap().1);
    }

    #[test]
    fn sizes_are_bounded_before_and_while_reading() {
        let d = scratch("size");
        let big = d.join("big.json");
        let f = File::create(&big).unwrap();
        f.set_len(SCENE_FILE.max_bytes + 1).unwrap();
        let e = InputFile::open(&big, SCENE_FILE).unwrap_err();
        assert!(e.message.contains("more than the 64 MiB"), "{e}");
        // Exactly at the limit is read.
        f.set_len(SCENE_FILE.max_bytes).unwrap();
        assert_eq!(
            InputFile::open(&big, SCENE_FILE)
                .unwrap()
                .read_bytes()
                .unwrap()
                .len() as u64,
            SCENE_FILE.max_bytes
        );
        // Grown after opening: refused, not read on.
        let file = InputFile::open(&big, SCENE_FILE).unwrap();
        f.set_len(SCENE_FILE.max_bytes + 4096).unwrap();
        let e = file.read_bytes().unwrap_err();
        assert!(e.message.contains("grew beyond"), "{e}");
        let bad = d.join("latin1.json");
        std::fs::write(&bad, b"{\"a\": \"\xe9\"}").unwrap();
        assert!(read_text(&bad, SCENE_FILE)
            .unwrap_err()
            .message
            .contains("not UTF-8"));
    }

    #[test]
    fn lines_are_bounded_and_bad_bytes_are_reported_per_line() {
        let d = scratch("lines");
        let p = d.join("in.jsonl");
        let mut body = b"first\r\n\xff\xfe bad\nthird\n".to_vec();
        let long = vec![b'x'; (MAX_LINE_BYTES + 10) as usize];
        body.extend_from_slice(&long);
        body.extend_from_slice(b"\nlast-unfinished");
        std::fs::write(&p, &body).unwrap();
        let mut r = InputFile::open(&p, BATCH_INPUT).unwrap().lines();
        let mut got = Vec::new();
        while let Some(l) = r.next_line().unwrap() {
            got.push(l);
        }
        assert_eq!(got.len(), 5);
        assert_eq!(got[0].text, LineText::Text("first".into()));
        assert!(
            matches!(&got[1].text, LineText::NotUtf8 { valid_up_to: 0, bytes } if bytes[..] == b"\xff\xfe bad"[..])
        );
        assert!(got[1].problem().unwrap().contains("line 2 is not UTF-8"));
        assert_eq!(got[2].text, LineText::Text("third".into()));
        // "first\r\n" then the 7 bytes of the second line.
        assert_eq!(got[2].start, 7 + 7);
        assert_eq!(
            got[3].text,
            LineText::TooLong {
                bytes: MAX_LINE_BYTES + 11
            }
        );
        assert_eq!(got[4].text, LineText::Text("last-unfinished".into()));
        assert!(got[3].terminated && !got[4].terminated);
        assert_eq!(got[4].start + 15, body.len() as u64);
    }

    #[test]
    fn folder_entries_skip_folders_and_are_sorted_and_bounded() {
        let d = scratch("folder");
        for n in ["b.json", "a.json", "c.txt"] {
            std::fs::write(d.join(n), "{}").unwrap();
        }
        std::fs::create_dir_all(d.join("sub.json")).unwrap();
        let e = folder_entries(&d, "json", 10).unwrap();
        assert_eq!(e, vec![d.join("a.json"), d.join("b.json")]);
        assert!(folder_entries(&d, "json", 1)
            .unwrap_err()
            .message
            .contains("more than 1"));
    }
}
