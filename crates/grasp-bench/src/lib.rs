//! The benchmark cases of the project (the benchmark table) and how they are measured, shared by
//! the `grasp bench` command (a table with both solvers side by side) and `cargo bench -p
//! grasp-bench` (divan). Data flow: [`case`] names a case and prepares its inputs from the
//! bundled example scenes; [`sample`] runs a prepared case once and says what it cost;
//! [`statistics`] folds repeated samples (median, spread, growth exponent); [`peak_memory`]
//! reads the process's resident memory (Linux `/proc`); [`peer`] runs the peer library
//! (tamaas, through `scripts/peer-hertz.py`) on a Hertz case's grid;
//! [`output_writing`] times writing a fine patch's solution in each output format;
//! [`mod@thread_scaling`] times a case on one thread and on every core.

#![warn(missing_docs)]

pub mod case;
pub mod error;
pub mod output_writing;
pub mod peak_memory;
pub mod peer;
pub mod sample;
pub mod statistics;
pub mod thread_scaling;

pub use case::{
    Case, CaseKind, Prepared, CASES, FFT_CASES, HELD_CASES, LAYER_CASES, LAYER_PAIRS, MARGIN_PAIRS,
    PEER_CASES,
};
pub use error::BenchError;
pub use sample::Sample;
pub use thread_scaling::{thread_scaling, ThreadScaling};
