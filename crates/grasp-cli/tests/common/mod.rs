//! Helpers shared by the binary's integration tests: run `grasp`, find a bundled example, make
//! a fresh scratch folder, read a run's whole output, make a FIFO, find the `rerun` checker.
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

/// Makes a FIFO (named pipe) at `path` with `mkfifo`, replacing what is there: a test case, never
/// skipped (a failure here fails the test).
pub fn fifo(path: &Path) {
    let _ = std::fs::remove_file(path);
    let made = Command::new("mkfifo").arg(path).status();
    assert!(
        made.as_ref().is_ok_and(|s| s.success()),
        "mkfifo {}: {made:?}",
        path.display()
    );
}

/// The `rerun` CLI of the checker install (`GRASP_RERUN_CLI`, set by scripts/test.sh), or
/// `None` when the external checks are skipped knowingly (`GRASP_SKIP_EXTERNAL_CHECKS=1`, not
/// allowed together with `GRASP_REQUIRE_CHECKERS=1`); a failing test otherwise.
pub fn rerun_cli() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("GRASP_RERUN_CLI") {
        return Some(PathBuf::from(p));
    }
    let require = std::env::var("GRASP_REQUIRE_CHECKERS").as_deref() == Ok("1");
    if !require && std::env::var("GRASP_SKIP_EXTERNAL_CHECKS").as_deref() == Ok("1") {
        eprintln!("GRASP_SKIP_EXTERNAL_CHECKS=1: external rerun checks skipped");
        return None;
    }
    panic!(
        "GRASP_RERUN_CLI is not set: run the tests with scripts/test.sh (it installs \
         rerun-sdk==0.36.3), or set GRASP_SKIP_EXTERNAL_CHECKS=1 (without \
         GRASP_REQUIRE_CHECKERS=1) to skip the external checks knowingly"
    );
}
