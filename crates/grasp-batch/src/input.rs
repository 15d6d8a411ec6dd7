//! Reading the scenes of a batch: a JSONL file (one scene per line, `{"id": ..., "scene":
//! {...}}` with an optional `"vary"` note, or a bare scene whose id is `line-<n>`), a folder
//! of `*.json` scene files (id: the file name without `.json`, in name order), or the variants
//! of a sweep (made one at a time). Blank lines are skipped (they have no position). A line
//! that is not a usable scene (not JSON, not UTF-8, too long) is kept as the problems found
//! in it. Every file is read through `grasp_io::InputFile` (regular files, bounded).
//!
//! The input is read twice: once to count the scenes and check their ids
//! ([`BatchInput::index`]), once to solve them ([`BatchInput::for_each_unparsed`]); a file
//! that changes between the two is refused.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use grasp_io::{
    base_dir_of, folder_entries, scene_from_json_str_noting, scene_from_value, FileIdentity,
    FileLine, InputFile, LineText, RunInputs, BATCH_INPUT, SCENE_FILE,
};
use grasp_model::{strict_json::from_str_strict, strict_json::StrictValue};
use grasp_model::{InputProblem, LoadedScene};
use serde_json::Value;

use crate::error::{io, BatchError};
use crate::input_index::{default_id, id_of, line_id, InputIndex, MAX_SCENES};
use crate::sweep::Sweep;

/// Where the scenes are.
#[derive(Debug, Clone)]
pub enum BatchInput {
    /// A JSONL file (its identity and size when first opened).
    Jsonl {
        /// The file.
        path: PathBuf,
        /// Its device and inode.
        identity: FileIdentity,
        /// Its size, bytes: later passes read no further.
        len: u64,
    },
    /// The scene files of a folder, sorted by name.
    Folder(Vec<PathBuf>),
    /// JSONL lines in memory (a library caller's; mesh paths relative to the working folder).
    Lines(Vec<String>),
    /// The variants of a sweep; mesh files relative to `base` (the swept scene's folder).
    Sweep {
        /// The grid.
        sweep: Arc<Sweep>,
        /// The folder mesh paths start from.
        base: PathBuf,
    },
}

/// One scene of the input.
#[derive(Debug, Clone)]
pub struct SceneLine {
    /// Position in the input (0-based, blank lines not counted).
    pub index: usize,
    /// The scene's id.
    pub id: String,
    /// The `"vary"` note of a sweep variant (carried into the result).
    pub vary: Option<Value>,
    /// The scene as read (its shapes, its height maps), or every problem found in it.
    pub scene: Result<LoadedScene, Vec<InputProblem>>,
    /// The files read for it (a folder's scene file, mesh files).
    pub files: RunInputs,
}

impl BatchInput {
    /// A JSONL file or a folder.
    pub fn open(path: &Path) -> Result<BatchInput, BatchError> {
        let meta = std::fs::metadata(path).map_err(|e| io(path, e))?;
        if meta.is_dir() {
            return Ok(BatchInput::Folder(folder_entries(
                path, "json", MAX_SCENES,
            )?));
        }
        let file = InputFile::open(path, BATCH_INPUT)?;
        Ok(BatchInput::Jsonl {
            path: path.to_path_buf(),
            identity: file.identity(),
            len: file.len(),
        })
    }

    /// The files this input is made of (the JSONL file, or the folder's scene files).
    pub fn files(&self) -> RunInputs {
        let mut inputs = RunInputs::new();
        match self {
            BatchInput::Jsonl { path, identity, .. } => inputs.add(path, *identity),
            BatchInput::Folder(files) => files.iter().for_each(|f| inputs.add_existing(f)),
            BatchInput::Lines(_) | BatchInput::Sweep { .. } => {}
        }
        inputs
    }

    /// The first pass: the number of scenes and their ids; duplicate ids refused.
    pub fn index(&self) -> Result<InputIndex, BatchError> {
        let mut index = InputIndex::default();
        match self {
            BatchInput::Jsonl { .. } | BatchInput::Lines(_) => {
                self.for_each_line(&mut |i, line| {
                    let id = match &line.text {
                        LineText::Text(t) => line_id(t, line.number),
                        _ => default_id(line.number),
                    };
                    index.add(id, i, line.number)
                })?;
            }
            BatchInput::Folder(files) => {
                for (i, f) in files.iter().enumerate() {
                    index.add(file_id(f), i, i + 1)?;
                }
            }
            BatchInput::Sweep { sweep, .. } => {
                // Ids made unique by construction: only the count is needed.
                index.scenes = sweep.len();
            }
        }
        index.refuse_duplicates()?;
        Ok(index)
    }

    /// Visits every scene in order; `wanted(index)` decides which are handed over, as read
    /// and not yet parsed ([`UnparsedScene::parse`] may then run on a worker thread).
    /// Returns the number of scenes.
    pub fn for_each_unparsed(
        &self,
        wanted: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(UnparsedScene) -> Result<(), BatchError>,
    ) -> Result<usize, BatchError> {
        match self {
            BatchInput::Jsonl { .. } | BatchInput::Lines(_) => {
                let base = match self {
                    BatchInput::Jsonl { path, .. } => base_dir_of(path),
                    _ => PathBuf::new(),
                };
                self.for_each_line(&mut |index, line| {
                    if !wanted(index) {
                        return Ok(());
                    }
                    visit(UnparsedScene::Line {
                        index,
                        line,
                        base: base.clone(),
                    })
                })
            }
            BatchInput::Folder(files) => {
                for (index, f) in files.iter().enumerate() {
                    if wanted(index) {
                        visit(UnparsedScene::File {
                            index,
                            path: f.clone(),
                        })?;
                    }
                }
                Ok(files.len())
            }
            BatchInput::Sweep { sweep, base } => {
                for index in (0..sweep.len()).filter(|i| wanted(*i)) {
                    let (id, vary, scene) = sweep.variant(index)?;
                    visit(UnparsedScene::Variant {
                        index,
                        id,
                        vary,
                        scene,
                        base: base.clone(),
                    })?;
                }
                Ok(sweep.len())
            }
        }
    }

    /// Visits every scene, parsed (see [`BatchInput::for_each_unparsed`]).
    pub fn for_each(
        &self,
        wanted: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(SceneLine) -> Result<(), BatchError>,
    ) -> Result<usize, BatchError> {
        self.for_each_unparsed(wanted, &mut |u| visit(u.parse()))
    }

    /// The non-blank lines of a JSONL input with their positions; a file must still be the
    /// one first opened, read no further than its size then.
    fn for_each_line(
        &self,
        visit: &mut dyn FnMut(usize, FileLine) -> Result<(), BatchError>,
    ) -> Result<usize, BatchError> {
        let (path, identity, len) = match self {
            BatchInput::Jsonl {
                path,
                identity,
                len,
            } => (path, identity, len),
            BatchInput::Lines(lines) => return for_each_memory_line(lines, visit),
            _ => return Ok(0),
        };
        let file = InputFile::open(path, BATCH_INPUT)?;
        if file.identity() != *identity || file.len() < *len {
            return Err(io(
                path,
                "changed while the batch read it (replaced or cut); run again on a file that \
                 is not being written",
            ));
        }
        let mut lines = file.lines_upto(*len);
        let mut index = 0;
        while let Some(line) = lines.next_line()? {
            if matches!(&line.text, LineText::Text(t) if t.trim().is_empty()) {
                continue;
            }
            visit(index, line)?;
            index += 1;
        }
        Ok(index)
    }
}

/// The non-blank lines held in memory, as lines of a file.
fn for_each_memory_line(
    lines: &[String],
    visit: &mut dyn FnMut(usize, FileLine) -> Result<(), BatchError>,
) -> Result<usize, BatchError> {
    let mut index = 0;
    for (n, text) in lines.iter().enumerate() {
        if text.trim().is_empty() {
            continue;
        }
        let line = FileLine {
            number: n + 1,
            start: 0,
            terminated: true,
            text: LineText::Text(text.clone()),
        };
        visit(index, line)?;
        index += 1;
    }
    Ok(index)
}

/// A folder entry's id: its file name without `.json`.
fn file_id(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// One scene of the input as read, before parsing.
#[derive(Debug, Clone)]
pub enum UnparsedScene {
    /// A JSONL line: position, the line, and the folder mesh files are read relative to.
    Line {
        /// Position in the input (0-based).
        index: usize,
        /// The line as read.
        line: FileLine,
        /// The folder its mesh files are read relative to.
        base: PathBuf,
    },
    /// A scene file of a folder (read when parsed).
    File {
        /// Position in the input (0-based).
        index: usize,
        /// The file.
        path: PathBuf,
    },
    /// A sweep variant, already a JSON value.
    Variant {
        /// Position in the sweep (0-based).
        index: usize,
        /// The variant's id.
        id: String,
        /// The values varied in this variant.
        vary: Value,
        /// The scene with those values set.
        scene: Value,
        /// The folder its mesh files are read relative to.
        base: PathBuf,
    },
}

impl UnparsedScene {
    /// The position in the input.
    pub fn index(&self) -> usize {
        match self {
            UnparsedScene::Line { index, .. }
            | UnparsedScene::File { index, .. }
            | UnparsedScene::Variant { index, .. } => *index,
        }
    }

    /// The scene's id and scene (or the problems found in it), and the files read.
    pub fn parse(self) -> SceneLine {
        match self {
            UnparsedScene::Line { index, line, base } => parse_line(index, line, &base),
            UnparsedScene::File { index, path } => parse_file(index, &path),
            UnparsedScene::Variant {
                index,
                id,
                vary,
                scene,
                base,
            } => {
                let mut files = RunInputs::new();
                let scene = scene_from_value(scene, &base, &mut files).map_err(|e| e.problems());
                SceneLine {
                    index,
                    id,
                    vary: Some(vary),
                    scene,
                    files,
                }
            }
        }
    }
}

fn problem(path: &str, message: &str) -> InputProblem {
    InputProblem {
        path: path.into(),
        message: message.into(),
        fix: "write one scene per line (UTF-8 JSON): {\"id\": \"...\", \"scene\": {...}} or a \
              bare scene"
            .into(),
    }
}

/// A scene file of a folder.
fn parse_file(index: usize, path: &Path) -> SceneLine {
    let mut files = RunInputs::new();
    let scene = grasp_io::read_text(path, SCENE_FILE)
        .map_err(|e| {
            vec![InputProblem {
                path: ".".into(),
                message: e.message,
                fix: e.fix,
            }]
        })
        .and_then(|(t, identity)| {
            files.add(path, identity);
            scene_from_json_str_noting(&t, &base_dir_of(path), &mut files).map_err(|e| e.problems())
        });
    SceneLine {
        index,
        id: file_id(path),
        vary: None,
        scene,
        files,
    }
}

/// One line of a JSONL input, parsed once; mesh files are read relative to `base` (the
/// file's folder).
fn parse_line(index: usize, line: FileLine, base: &Path) -> SceneLine {
    let number = line.number;
    let invalid = |id: String, p: InputProblem| SceneLine {
        index,
        id,
        vary: None,
        scene: Err(vec![p]),
        files: RunInputs::new(),
    };
    let text = match line.text {
        LineText::Text(t) => t,
        other => {
            let why = FileLine {
                text: other,
                ..line
            }
            .problem()
            .unwrap_or_default();
            return invalid(default_id(number), problem(".", &why));
        }
    };
    let value = match from_str_strict::<StrictValue>(&text) {
        Ok(StrictValue(v)) => v,
        Err(e) => return invalid(line_id(&text, number), problem(&e.path, &e.message)),
    };
    let mut files = RunInputs::new();
    let mut obj = match value {
        Value::Object(o) if o.contains_key("scene") => o,
        bare => {
            let scene = scene_from_value(bare, base, &mut files).map_err(|e| e.problems());
            return SceneLine {
                index,
                id: default_id(number),
                vary: None,
                scene,
                files,
            };
        }
    };
    let id = id_of(&obj, number);
    if let Some(k) = obj
        .keys()
        .find(|k| !["id", "scene", "vary"].contains(&k.as_str()))
    {
        return invalid(
            id,
            problem(k, "unknown key of a batch line (id, scene, vary)"),
        );
    }
    let scene_value = obj.remove("scene").unwrap_or(Value::Null);
    let scene = scene_from_value(scene_value, base, &mut files).map_err(|e| {
        e.problems()
            .into_iter()
            .map(|p| InputProblem {
                path: format!("scene.{}", p.path),
                ..p
            })
            .collect()
    });
    SceneLine {
        index,
        id,
        vary: obj.remove("vary"),
        scene,
        files,
    }
}
