//! How this crate's messages name the options a caller can change (see
//! `grasp_model::option_names`): as the Rust API spells them, between backticks; front ends
//! respell them (the CLI: `--jobs`, `--shard`, `--vary`). The memory limit is grasp-io's
//! (`grasp_io::MAX_MEMORY`).

/// Worker threads, [`crate::BatchOptions::threads`].
pub const THREADS: &str = "BatchOptions::threads";
/// The shard of the input, [`crate::Shard::parse`].
pub const SHARD: &str = "Shard::parse";
/// One axis of a sweep, [`crate::Axis::parse`].
pub const SWEEP_AXIS: &str = "Axis::parse";
