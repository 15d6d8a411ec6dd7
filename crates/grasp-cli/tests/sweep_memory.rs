//! `grasp sweep` makes its variants one at a time: writing 100,000 variants
//! of the Hertz scene (about 50 MB of JSONL) stays under 100 MiB of peak memory, where holding
//! them (each variant a JSON value of a few kB, and its line) took several hundred MB. The
//! peak is the kernel's maximum resident set of the finished child (`getrusage`); this file
//! holds this one test, so no other child of the test process counts.

mod common;

use std::io::BufRead;

use common::{example, grasp, text, tmp};

/// Peak resident memory of the largest finished child of this process, bytes.
fn children_peak_bytes() -> u64 {
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(
        unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) },
        0
    );
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn a_large_sweep_is_written_in_bounded_memory() {
    let d = tmp("sweep", "memory");
    let out = d.join("big.jsonl");
    let o = grasp(&[
        "sweep",
        &example("hertz_sphere_on_flat.json"),
        "--vary",
        "object.weight=1:100:1000",
        "--vary",
        "fingers[0].friction.mu=0.1:0.9:100",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let peak = children_peak_bytes();
    let file = std::fs::File::open(&out).unwrap();
    let mut n = 0usize;
    let mut last = String::new();
    for line in std::io::BufReader::new(file).lines() {
        last = line.unwrap();
        n += 1;
    }
    assert_eq!(n, 100_000);
    assert!(
        last.starts_with(r#"{"id":"hertz_sphere_on_flat-99999""#),
        "{last}"
    );
    let size = std::fs::metadata(&out).unwrap().len();
    println!("100000 variants, {size} bytes written, peak memory {peak} bytes");
    assert!(
        peak < 100 << 20,
        "peak {peak} bytes for a file of {size} bytes"
    );
    std::fs::remove_file(&out).unwrap();
}
