//! Reading the scenes of a batch: a JSONL file (one scene per line, `{"id": ..., "scene":
//! {...}}` with an optional `"vary"` note, or a bare scene whose id is `line-<n>`) or a folder
//! of `*.json` scene files (id: the file name without `.json`, in name order). Blank lines are
//! skipped (they have no position). A line that is not a usable scene is kept as the problems
//! found in it.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use grasp_io::{base_dir_of, scene_from_json_str};
use grasp_model::scene::strict_json::{from_str_strict, StrictValue};
use grasp_model::{InputProblem, Scene};
use serde_json::Value;

use crate::error::{io, BatchError};

/// Where the scenes are.
#[derive(Debug, Clone)]
pub enum BatchInput {
    /// A JSONL file.
    Jsonl(PathBuf),
    /// The scene files of a folder, sorted by name.
    Folder(Vec<PathBuf>),
    /// JSONL lines in memory (a sweep run directly).
    Lines(Vec<String>),
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
    /// The scene, or every problem found in it.
    pub scene: Result<Scene, Vec<InputProblem>>,
}

impl BatchInput {
    /// A JSONL file or a folder.
    pub fn open(path: &Path) -> Result<BatchInput, BatchError> {
        let meta = std::fs::metadata(path).map_err(|e| io(path, e))?;
        if meta.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| io(path, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "json") && p.is_file())
                .collect();
            files.sort();
            Ok(BatchInput::Folder(files))
        } else if meta.is_file() {
            Ok(BatchInput::Jsonl(path.to_path_buf()))
        } else {
            Err(io(
                path,
                "is neither a JSONL file nor a folder of scene files",
            ))
        }
    }

    /// Visits every scene in order; `wanted(index)` decides which are parsed (the others
    /// are passed over cheaply: a shard, a resumed run). Returns the number of scenes.
    pub fn for_each(
        &self,
        wanted: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(SceneLine) -> Result<(), BatchError>,
    ) -> Result<usize, BatchError> {
        self.for_each_unparsed(wanted, &mut |u| visit(u.parse()))
    }

    /// Like [`BatchInput::for_each`], but hands over each wanted scene as read, not yet
    /// parsed ([`UnparsedScene::parse`] may then run on a worker thread).
    pub fn for_each_unparsed(
        &self,
        wanted: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(UnparsedScene) -> Result<(), BatchError>,
    ) -> Result<usize, BatchError> {
        match self {
            BatchInput::Jsonl(path) => {
                let file = std::fs::File::open(path).map_err(|e| io(path, e))?;
                let base = base_dir_of(path);
                let mut index = 0;
                for (n, line) in BufReader::new(file).lines().enumerate() {
                    let line = line.map_err(|e| io(path, format!("line {}: {e}", n + 1)))?;
                    if line.trim().is_empty() {
                        continue;
                    }
                    if wanted(index) {
                        visit(UnparsedScene::Line {
                            index,
                            number: n + 1,
                            text: line,
                            base: base.clone(),
                        })?;
                    }
                    index += 1;
                }
                Ok(index)
            }
            BatchInput::Lines(lines) => {
                let mut index = 0;
                for (n, line) in lines.iter().enumerate() {
                    if line.trim().is_empty() {
                        continue;
                    }
                    if wanted(index) {
                        visit(UnparsedScene::Line {
                            index,
                            number: n + 1,
                            text: line.clone(),
                            base: PathBuf::new(),
                        })?;
                    }
                    index += 1;
                }
                Ok(index)
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
        }
    }
}

/// One scene of the input as read, before parsing.
#[derive(Debug, Clone)]
pub enum UnparsedScene {
    /// A JSONL line: position, 1-based line number (for the default id), text, and the
    /// folder mesh files are read relative to.
    Line {
        index: usize,
        number: usize,
        text: String,
        base: PathBuf,
    },
    /// A scene file of a folder (read when parsed).
    File { index: usize, path: PathBuf },
}

impl UnparsedScene {
    /// The scene's id and scene (or the problems found in it).
    pub fn parse(self) -> SceneLine {
        match self {
            UnparsedScene::Line {
                index,
                number,
                text,
                base,
            } => parse_line(index, number, &text, &base),
            UnparsedScene::File { index, path } => {
                let id = path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let scene = std::fs::read_to_string(&path)
                    .map_err(|e| {
                        vec![problem(
                            ".",
                            &format!("cannot read {}: {e}", path.display()),
                        )]
                    })
                    .and_then(|t| {
                        scene_from_json_str(&t, &base_dir_of(&path)).map_err(|e| e.problems())
                    });
                SceneLine {
                    index,
                    id,
                    vary: None,
                    scene,
                }
            }
        }
    }
}

fn problem(path: &str, message: &str) -> InputProblem {
    InputProblem {
        path: path.into(),
        message: message.into(),
        fix: "write one scene per line: {\"id\": \"...\", \"scene\": {...}} or a bare scene".into(),
    }
}

/// One JSONL line (`number` 1-based, for the default id).
/// One line of a JSONL input; mesh files are read relative to `base` (the file's folder).
fn parse_line(index: usize, number: usize, line: &str, base: &Path) -> SceneLine {
    let default_id = format!("line-{number}");
    let value = match from_str_strict::<StrictValue>(line) {
        Ok(StrictValue(v)) => v,
        Err(e) => {
            return SceneLine {
                index,
                id: default_id,
                vary: None,
                scene: Err(vec![problem(&e.path, &e.message)]),
            }
        }
    };
    let Some(obj) = value.as_object().filter(|o| o.contains_key("scene")) else {
        // A bare scene.
        let scene = scene_from_json_str(line, base).map_err(|e| e.problems());
        return SceneLine {
            index,
            id: default_id,
            vary: None,
            scene,
        };
    };
    let id = match obj.get("id") {
        Some(Value::String(s)) => s.clone(),
        Some(Value::Number(n)) => n.to_string(),
        _ => default_id,
    };
    let unknown: Vec<&String> = obj
        .keys()
        .filter(|k| !["id", "scene", "vary"].contains(&k.as_str()))
        .collect();
    let scene = if let Some(k) = unknown.first() {
        Err(vec![problem(
            k,
            "unknown key of a batch line (id, scene, vary)",
        )])
    } else {
        scene_from_json_str(&obj["scene"].to_string(), base).map_err(|e| {
            e.problems()
                .into_iter()
                .map(|p| InputProblem {
                    path: format!("scene.{}", p.path),
                    ..p
                })
                .collect()
        })
    };
    SceneLine {
        index,
        id,
        vary: obj.get("vary").cloned(),
        scene,
    }
}
