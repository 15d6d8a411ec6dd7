//! # grasp-batch: many grasps, one result line each
//!
//! Scenes come one per line of a JSONL file (`{"id": ..., "scene": {...}}` or a bare scene) or
//! one per file of a folder; each becomes one result line (the scene's id, its status, finger
//! forces, residual and time), in input order. A bad scene is an `invalid` line, never the end
//! of the batch. Work is spread over all cores, output stays in input order.
//!
//! For clusters: [`shard`] takes every N-th scene from the I-th (from `--shard I/N` or the
//! job-array environment of Slurm and Kubernetes), [`merge`] joins the shards' outputs and
//! checks that none is missing, and a run resumes by skipping the ids already in its output.
//! [`sweep`] expands a grid of variants of one scene into the JSONL a batch reads.
//!
//! Files: [`input`] (reading scenes), [`shard`], [`result_line`] (the output record),
//! [`runner`] (parallel, ordered, resumable), [`merge`], [`sweep`], [`error`]. No terminal
//! output: progress is reported through a callback.

pub mod error;
pub mod input;
pub mod merge;
pub mod option_names;
pub mod result_line;
pub mod runner;
pub mod shard;
pub mod sweep;

pub use error::BatchError;
pub use input::{BatchInput, SceneLine, UnparsedScene};
pub use result_line::{FingerForces, ResultLine, ResultStatus};
pub use runner::{run_batch, BatchOptions, BatchSummary};
pub use shard::Shard;
