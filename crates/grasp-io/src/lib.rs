//! # grasp-io: the files the project reads and writes
//!
//! The contact model does no I/O; every file the project touches goes through this crate, used
//! by the CLI, `grasp-batch`, `grasp-transfer` (CSV profiles) and the Python module alike:
//!
//! - Reading ([`InputFile`], [`read_text`], [`read_bytes`]): every read is of a regular file
//!   (never a FIFO, a device or a folder), within a size limit of its kind ([`InputKind`]:
//!   [`SCENE_FILE`], [`SCHEDULE_FILE`], ...), read with a bound even if the file grows; line
//!   files (JSONL) line by line ([`LineReader`]), each line bounded, a line that is not UTF-8
//!   reported as such.
//! - [`read_mesh`]: OBJ and STL meshes (an OBJ's materials are never read); the height maps of
//!   textures (`.npy`, `.csv`, at most [`MAX_PIXELS`] heights).
//! - [`read_scene_file`], [`scene_from_json_str`]: scenes with the files they name resolved
//!   against the scene's folder (a `grasp_model::LoadedScene`: the plain scene and the meshes'
//!   posed shapes and the height maps beside it), and every file read noted ([`RunInputs`]).
//! - [`OutputSet`]: the one output policy (checked targets, inputs never overwritten, no
//!   replacing without [`OutputRules::force`], exclusive unguessable temporary files moved into
//!   place on success, every output locked for the run); [`remove_all_for_exit`]: the live
//!   hidden files a signal handler removes.
//! - [`SolutionRecord`]: what a solution's JSON file holds (the solution, the solve's time,
//!   the sensitivities); [`write_solution_json`]: its text, streamed (a fine patch's element
//!   fields one array a line); [`write_solution_npz`]: a solution's element fields as a NumPy
//!   `.npz` archive ([`NpzArchive`]).
//! - [`default_memory_limit`]: a share of the machine's memory, for default memory limits;
//!   [`MemoryLimit::check`]: the one check of a scene's estimated memory against a run's limit.
//!
//! The files are private: this page is the crate's whole face, its names grouped below in
//! data-flow order.
//!
//! Unix only (device and inode numbers, `O_NOFOLLOW`, `/proc/self/fd`, `flock`).

#![warn(missing_docs)]

mod error;
mod height_map_file;
mod input_file;
mod machine_memory;
mod memory_limit;
mod mesh_file;
mod output_file;
mod output_lock;
mod run_inputs;
mod scene_file;
mod sibling_names;
mod solution_json;
mod solution_npz;
mod solution_record;
mod temporary_files;

// ---- Reading a file: a regular file within its kind's size limit, lines bounded ----
pub use input_file::{
    folder_entries, read_bytes, read_text, FileIdentity, FileLine, InputFile, InputKind,
    LineReader, LineText, MAX_LINE_BYTES,
};
pub use input_file::{
    BATCH_INPUT, BATCH_OUTPUT, LOAD_PROFILE, MATERIAL_MAP, MUJOCO_MODEL, MUJOCO_ROLLOUT,
    MUJOCO_STATE, SCENE_FILE, SCHEDULE_FILE, SHARD_OUTPUT,
};

// ---- Scenes and the files they name (meshes, height maps), every file read noted ----
pub use height_map_file::MAX_PIXELS;
pub use mesh_file::read_mesh;
pub use run_inputs::RunInputs;
pub use scene_file::{
    base_dir_of, read_scene_file, scene_from_json_str, scene_from_json_str_noting,
    scene_from_json_str_with_arrays, scene_from_value, HeightArrays, SceneFile, SceneFileError,
};

// ---- The memory limit of a run ----
pub use machine_memory::{default_memory_limit, DEFAULT_MEMORY_SHARE, FALLBACK_MEMORY_LIMIT};
pub use memory_limit::{MemoryError, MemoryLimit};

// ---- Writing: the output policy, the hidden files a signal handler removes, solutions ----
pub use output_file::{OutputRules, OutputSet, PendingOutput};
pub use solution_json::write_solution_json;
pub use solution_npz::{write_solution_npz, NpzArchive};
pub use solution_record::SolutionRecord;
pub use temporary_files::remove_all_for_exit;

// ---- How messages name this crate's options (front ends respell them) ----
pub use memory_limit::MAX_MEMORY;
pub use output_file::FORCE;

// ---- Errors ----
pub use error::{InputFileError, OutputError, OutputErrorKind};
