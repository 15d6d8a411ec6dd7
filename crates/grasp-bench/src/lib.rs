//! The benchmark cases of the project (the benchmark table) and how they are measured, shared by
//! the `grasp bench` command (a table with both solvers side by side) and `cargo bench -p
//! grasp-bench` (divan). Data flow: a [`Case`] names a case and prepares its inputs from the
//! bundled example scenes ([`bundled`], [`Prepared`]); a [`Sample`] runs a prepared case once
//! and says what it cost (with the process's resident memory, read from Linux `/proc`);
//! [`median_and_range`] and [`growth_exponent`] fold repeated samples; [`PeerProblem`] runs the
//! peer library (tamaas, through `scripts/peer-hertz.py`) on a Hertz case's grid;
//! [`measure_output_writing`] times writing a fine patch's solution in each output format;
//! [`thread_scaling()`] times a case on one thread and on every core. The files are private:
//! this page is the crate's whole face.

#![warn(missing_docs)]

mod case;
mod error;
mod output_writing;
mod peak_memory;
mod peer;
mod sample;
mod statistics;
mod thread_scaling;

// ---- The cases and their inputs ----
pub use case::{
    bundled, Case, CaseKind, Prepared, CASES, FFT_CASES, HELD_CASES, LAYER_CASES, LAYER_PAIRS,
    MARGIN_PAIRS, PEER_CASES, PLAN_QUESTION,
};

// ---- Measuring: one sample, repeated samples folded, threads ----
pub use sample::Sample;
pub use statistics::{growth_exponent, median_and_range};
pub use thread_scaling::{thread_scaling, ThreadScaling};

// ---- The peer library's run of a Hertz case ----
pub use peer::{PeerError, PeerProblem, PeerRecord};

// ---- Writing a fine patch's solution in each output format ----
pub use output_writing::{measure_output_writing, WriteCost};

// ---- Errors ----
pub use error::BenchError;
