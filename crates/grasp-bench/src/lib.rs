//! The benchmark cases of the project, how they are measured, and the benchmark table they make,
//! shared by the `grasp bench` command (the table, both solvers side by side) and `cargo bench
//! -p grasp-bench` (divan, the cases alone). Data flow: a [`Case`] names a case and prepares its
//! inputs from the bundled example scenes ([`bundled`], [`Prepared`]); a [`Sample`] runs a
//! prepared case once and says what it cost (with the process's resident memory, read from
//! Linux `/proc`); [`median_and_range`] and [`growth_exponent`] fold repeated samples;
//! [`PeerProblem`] runs the peer library (tamaas, through `scripts/peer-hertz.py`) on a Hertz
//! case's grid; [`measure_output_writing`] times writing a fine patch's solution in each output
//! format; [`thread_scaling()`] times a case on one thread and on every core.
//!
//! The table: [`run_bench`] runs what a [`BenchConfig`] asks (each case measured with each
//! solver, then the rows derived from them, the whole `grasp transfer` command timed from
//! outside, the batch runner's throughput, the outputs' cost) and returns a [`BenchReport`]:
//! its [`Row`]s and notes, as aligned text or Markdown. It prints nothing: which case runs is
//! told to a callback, and the caller prints the report. Its I/O is what the measurements
//! need: `/proc` for memory, the peer's and `grasp transfer`'s processes, and the files they
//! and the output rows write, in a private scratch folder removed afterwards.
//!
//! The files are private: this page is the crate's whole face.

#![warn(missing_docs)]

mod batch_throughput;
mod bench_run;
mod case;
mod derived_rows;
mod error;
mod measurement;
mod output_writing;
mod peak_memory;
mod peer;
mod peer_rows;
mod sample;
mod scratch_folder;
mod statistics;
mod table;
mod tactile_dataset_rows;
mod thread_scaling;
mod whole_command;

// ---- The cases and their inputs ----
pub use case::{
    bundled, Case, CaseKind, Prepared, CASES, FFT_CASES, HELD_CASES, LAYER_CASES, LAYER_PAIRS,
    MARGIN_PAIRS, PEER_CASES, PLAN_QUESTION, ROUGH_CASES,
};

// ---- Measuring: one sample, repeated samples folded, threads ----
pub use sample::Sample;
pub use statistics::{growth_exponent, median_and_range};
pub use thread_scaling::{thread_scaling, ThreadScaling};

// ---- The peer library's run of a Hertz case ----
pub use peer::{Peer, PeerError, PeerProblem, PeerRecord};

// ---- Writing a fine patch's solution in each output format ----
pub use output_writing::{measure_output_writing, WriteCost, OUTPUTS_CASE};
pub use tactile_dataset_rows::TACTILE_DATASET_CASE;

// ---- The table ----
pub use bench_run::{case_names, run_bench, BenchConfig, BenchReport};
pub use table::{Row, HEADER, LEGEND};

// ---- Errors ----
pub use error::BenchError;
