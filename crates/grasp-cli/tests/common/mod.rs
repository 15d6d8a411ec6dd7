//! Helpers shared by the binary's integration tests: run `grasp`, find a bundled example, make
//! a fresh scratch folder, read a run's whole output.
#![allow(dead_code)] // each test file uses its own subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `grasp` binary with `args` and waits for it.
pub fn grasp(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grasp"))
        .args(args)
        .output()
        .expect("run grasp")
}

/// Path of a bundled example file, `examples/<name>`.
pub fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .display()
        .to_string()
}

/// A fresh, empty scratch folder `grasp-<suite>-<tag>-<pid>` in the temporary folder.
pub fn tmp(suite: &str, tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-{suite}-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Standard output then standard error of a run, as text.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}
