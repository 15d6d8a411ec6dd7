//! # grasp-batch: many grasps, one result line each
//!
//! Scenes come one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare scene) or
//! one per file of a folder; each becomes one result line (the scene's id, its status, finger
//! forces, residual and time), in input order. A bad scene is an `invalid` line, never the end
//! of the batch. Work is spread over all cores, output stays in input order.
//!
//! For clusters: [`shard`] takes every N-th scene from the I-th (from `--shard I/N` or the
//! job-array environment of Slurm and Kubernetes), [`merge`] joins the shards' outputs and
//! checks that they cover the input exactly once, and a run resumes by skipping the positions
//! already in its output (checked whole first: [`resume`]). Ids are unique (checked before
//! anything is solved: [`input_index`]). [`sweep`] makes the variants of one scene over a grid,
//! one at a time.
//!
//! Files: [`input`] (reading scenes, through `grasp_io`), [`input_index`] (count and ids),
//! [`shard`], [`result_line`] (the output record), [`runner`] (parallel, ordered),
//! [`resume`], [`merge`], [`sweep`], [`error`]. No terminal output: progress is reported
//! through a callback.

#![warn(missing_docs)]

pub mod error;
pub mod input;
pub mod input_index;
pub mod memory_budget;
pub mod merge;
pub mod option_names;
pub mod result_line;
pub mod resume;
pub mod runner;
pub mod shard;
pub mod sweep;

pub use error::BatchError;
pub use input::{BatchInput, SceneLine, UnparsedScene};
pub use input_index::InputIndex;
pub use result_line::{FingerForces, ResultLine, ResultStatus};
pub use resume::{read_batch_output, ResumePoint};
pub use runner::{run_batch, BatchOptions, BatchSummary, MAX_THREADS};
pub use shard::Shard;
