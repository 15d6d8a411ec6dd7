//! `cargo bench -p grasp-bench`: every case of `grasp_bench::CASES` with each solver, timed by
//! divan (10 samples of one run each; a hand-off case times the whole hand-off, so divide by
//! its steps for the per-step figure). `grasp bench` prints the same cases as one table with
//! the targets, iterations, memory and errors.

use grasp_bench::CASES;
use grasp_model::SolverChoice;

fn main() {
    divan::main();
}

const NAMES: [&str; CASES.len()] = {
    let mut names = [""; CASES.len()];
    let mut i = 0;
    while i < CASES.len() {
        names[i] = CASES[i].name;
        i += 1;
    }
    names
};

fn bench_case(bencher: divan::Bencher, name: &str, solver: SolverChoice) {
    let case = CASES
        .iter()
        .find(|c| c.name == name)
        .expect("case listed in NAMES");
    let prepared = case.prepare(solver).expect("bundled inputs load");
    bencher.bench_local(|| prepared.run(false).expect("bench case runs"));
}

#[divan::bench(args = NAMES, sample_count = 10, sample_size = 1)]
fn native(bencher: divan::Bencher, name: &str) {
    bench_case(bencher, name, SolverChoice::Native);
}

#[divan::bench(args = NAMES, sample_count = 10, sample_size = 1)]
fn clarabel(bencher: divan::Bencher, name: &str) {
    bench_case(bencher, name, SolverChoice::Clarabel);
}
