//! The benchmark cases of the project, how they are measured, and the benchmark table they make,
//! shared by the `grasp bench` command (the table, both solvers side by side) and `cargo bench
//! -p grasp-bench` (divan, the cases alone). Data flow: [`case`] names a case and prepares its
//! inputs from the bundled example scenes; [`sample`] runs a prepared case once and says what it
//! cost; [`statistics`] folds repeated samples (median, spread, growth exponent);
//! [`peak_memory`] reads the process's resident memory (Linux `/proc`); [`peer`] runs the peer
//! library (tamaas, through `scripts/peer-hertz.py`) on a Hertz case's grid; [`output_writing`]
//! times writing a fine patch's solution in each output format; [`mod@thread_scaling`] times a
//! case on one thread and on every core.
//!
//! The table: [`run_bench`] runs what a [`BenchConfig`] asks (each case measured with each
//! solver, then the rows derived from them, the whole `grasp transfer` command timed from
//! outside, the batch runner's throughput, the outputs' cost) and returns a [`BenchReport`]:
//! its [`Row`]s and notes, as aligned text or Markdown. It prints nothing: which case runs is
//! told to a callback, and the caller prints the report. Its I/O is what the measurements
//! need: `/proc` for memory, the peer's and `grasp transfer`'s processes, and the files they
//! and the output rows write, in a private scratch folder removed afterwards.

#![warn(missing_docs)]

mod batch_throughput;
mod bench_run;
pub mod case;
mod derived_rows;
pub mod error;
mod measurement;
pub mod output_writing;
pub mod peak_memory;
pub mod peer;
mod peer_rows;
pub mod sample;
mod scratch_folder;
pub mod statistics;
mod table;
pub mod thread_scaling;
mod whole_command;

pub use bench_run::{case_names, run_bench, BenchConfig, BenchReport};
pub use case::{
    Case, CaseKind, Prepared, CASES, FFT_CASES, HELD_CASES, LAYER_CASES, LAYER_PAIRS, MARGIN_PAIRS,
    PEER_CASES,
};
pub use error::BenchError;
pub use output_writing::OUTPUTS_CASE;
pub use peer::Peer;
pub use sample::Sample;
pub use table::{Row, HEADER, LEGEND};
pub use thread_scaling::{thread_scaling, ThreadScaling};
