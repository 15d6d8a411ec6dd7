//! # grasp-io: the files the project reads and writes
//!
//! The contact model does no I/O; every file the project touches goes through this crate, used
//! by the CLI, `grasp-batch`, `grasp-transfer` (CSV profiles) and the Python module alike:
//!
//! - [`input_file`]: every read is of a regular file (never a FIFO, a device or a folder),
//!   within a size limit of its kind, read with a bound even if the file grows; line files
//!   (JSONL) line by line, each line bounded, a line that is not UTF-8 reported as such.
//! - [`mesh_file`]: OBJ and STL meshes (an OBJ's materials are never read);
//!   [`height_map_file`]: the height maps of textures (`.npy`, `.csv`).
//! - [`scene_file`]: scenes with the files they name resolved against the scene's folder, and
//!   every file read noted ([`run_inputs`]).
//! - [`output_file`]: the one output policy (checked targets, inputs never overwritten, no
//!   replacing without `force`, exclusive unguessable temporary files moved into place on
//!   success); [`output_lock`]: every output locked for the run; [`temporary_files`]: the
//!   live hidden files a signal handler removes.
//! - [`solution_json`]: a solution's JSON text, streamed (a fine patch's element fields one
//!   array a line); [`solution_npz`]: a solution's element fields as a NumPy `.npz` archive.
//! - [`machine_memory`]: the machine's memory, for default memory limits;
//!   [`memory_limit`]: the one check of a scene's estimated memory against a run's limit.
//!
//! Unix only (device and inode numbers, `O_NOFOLLOW`, `/proc/self/fd`, `flock`).

#![warn(missing_docs)]

pub mod error;
pub mod height_map_file;
pub mod input_file;
pub mod machine_memory;
pub mod memory_limit;
pub mod mesh_file;
pub mod output_file;
pub mod output_lock;
pub mod run_inputs;
pub mod scene_file;
pub mod sibling_names;
pub mod solution_json;
pub mod solution_npz;
pub mod temporary_files;

pub use error::{InputFileError, OutputError, OutputErrorKind};
pub use input_file::{FileIdentity, InputFile, InputKind};
pub use memory_limit::{MemoryError, MemoryLimit};
pub use mesh_file::read_mesh;
pub use output_file::{OutputRules, OutputSet, PendingOutput};
pub use run_inputs::RunInputs;
pub use scene_file::{
    base_dir_of, read_scene_file, scene_from_json_str, SceneFile, SceneFileError,
};
pub use solution_json::write_solution_json;
pub use solution_npz::{write_solution_npz, NpzArchive};
