//! How this crate's messages name the options a caller can change (see
//! `grasp_model::option_names`): as the Rust API spells them, between backticks; front ends
//! respell them (the CLI: `--jobs`, `--shard`, `--vary`, `--max-memory`).

/// Worker threads, [`crate::BatchOptions::threads`].
pub const THREADS: &str = "BatchOptions::threads";
/// Memory limit per scene, [`crate::BatchOptions::max_memory_bytes`].
pub const MAX_MEMORY: &str = "BatchOptions::max_memory_bytes";
/// The shard of the input, [`crate::Shard::parse`].
pub const SHARD: &str = "Shard::parse";
/// One axis of a sweep, [`crate::sweep::Axis::parse`].
pub const SWEEP_AXIS: &str = "Axis::parse";
