//! # grasp-batch: many grasps, one result line each
//!
//! Scenes come one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare scene) or
//! one per file of a folder; each becomes one result line (the scene's id, its status, finger
//! forces, residual and time), in input order. A bad scene is an `invalid` line, never the end
//! of the batch. Work is spread over all cores, output stays in input order.
//!
//! For clusters: a [`Shard`] takes every N-th scene from the I-th (from `--shard I/N` or the
//! job-array environment of Slurm and Kubernetes), [`merge()`] joins the shards' outputs and
//! checks that they cover the input exactly once, and a run resumes by skipping the positions
//! already in its output (checked whole first: [`read_batch_output`]). Ids are unique (checked
//! before anything is solved: [`InputIndex`]). A [`Sweep`] makes the variants of one scene over
//! a grid ([`Axis`]), one at a time.
//!
//! The face, in data-flow order: [`BatchInput`] (reading scenes, through `grasp_io`),
//! [`InputIndex`] (count and ids), [`Shard`], [`run_batch`] (parallel, ordered) writing one
//! [`ResultLine`] a scene (and, for a scene with a sensor, its arrays and labels to a
//! [`TactileDataset`]), [`read_batch_output`] (resume), [`merge()`], [`Sweep`], [`BatchError`]; [`option_names`] says how messages name this crate's options. The files are
//! private. No terminal output: progress is reported through a callback.

#![warn(missing_docs)]

mod error;
mod input;
mod input_index;
mod memory_budget;
mod merge;
pub mod option_names;
mod result_line;
mod resume;
mod runner;
mod shard;
mod sweep;
mod tactile_dataset;

// ---- The input: scenes one a line or one a file, counted and identified ----
pub use input::{BatchInput, SceneLine, UnparsedScene};
pub use input_index::InputIndex;
pub use shard::Shard;

// ---- The run: parallel, in input order, one result line a scene ----
pub use result_line::{FingerForces, ResultLine, ResultStatus};
pub use runner::{run_batch, BatchOptions, BatchSummary, MAX_THREADS};

// ---- Resuming and merging outputs ----
pub use merge::merge;
pub use resume::{read_batch_output, ResumePoint};

// ---- Sweeps: the variants of one scene over a grid ----
pub use sweep::{Axis, Sweep, MAX_VARIANTS};
pub use tactile_dataset::TactileDataset;

// ---- Errors ----
pub use error::BatchError;
