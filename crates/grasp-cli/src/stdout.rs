//! Standard output whose reader may go away: `grasp schema | head` closes the pipe after ten
//! lines, and the next write fails with a broken pipe. Rust ignores SIGPIPE, so the standard
//! `print!` would panic there (exit 101); every command prints through [`write()`] instead (the
//! crate's `print!` and `println!`, defined in `main.rs`, call it).
//!
//! A closed standard output ends the process quietly with 141, what a shell reports for a
//! program stopped by SIGPIPE, after removing the run's temporary output files (existing
//! files stay untouched, as on Ctrl-C). Any other write error ends it with 1, naming the cause.

use std::io::{ErrorKind, Write};

/// Exit code of a process whose standard output was closed: 128 + SIGPIPE (13).
pub const CLOSED_STDOUT_EXIT: i32 = 141;

/// Writes `args` to standard output, or ends the process as the module says.
pub fn write(args: std::fmt::Arguments) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args) {
        stop(&e);
    }
}

/// Writes what is still buffered (a last line without its newline), or ends the process as the
/// module says.
pub fn flush() {
    if let Err(e) = std::io::stdout().lock().flush() {
        stop(&e);
    }
}

/// Writes `args` to standard error; a closed standard error is ignored (there is nowhere left
/// to say anything).
pub fn write_err(args: std::fmt::Arguments) {
    let _ = std::io::stderr().lock().write_fmt(args);
}

fn stop(e: &std::io::Error) -> ! {
    let broken = e.kind() == ErrorKind::BrokenPipe;
    let code = if broken { CLOSED_STDOUT_EXIT } else { 1 };
    crate::output::remove_pending_and_exit(code, |removed| match (broken, removed) {
        (true, 0) => None,
        (true, n) => Some(format!(
            "standard output was closed: stopped; {n} temporary output file(s) removed, existing \
             files untouched"
        )),
        (false, n) => Some(format!(
            "error: cannot write to standard output: {e}; stopped, {n} temporary output file(s) \
             removed, existing files untouched"
        )),
    })
}
