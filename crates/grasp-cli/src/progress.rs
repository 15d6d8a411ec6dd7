//! Progress bars on the runs that take minutes (indicatif): drawn on standard error only when
//! it is a terminal, with the elapsed time and an estimate of what is left; nothing when it
//! is not a terminal (a pipe, a file, a batch job's log) or with `--quiet`.

use std::sync::atomic::{AtomicBool, Ordering};

use indicatif::{ProgressBar, ProgressStyle};

/// Set by `--quiet`: no bar at all.
static QUIET: AtomicBool = AtomicBool::new(false);

/// `--quiet`: no progress bars for the rest of the run.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// A bar of `len` items counted as `what` (`steps`, `scenes`, `directions`), with `{msg}`
/// after the count for a caller's detail; hidden with `--quiet` (and by indicatif on a
/// standard error that is not a terminal).
pub fn bar(len: usize, what: &str) -> ProgressBar {
    if QUIET.load(Ordering::Relaxed) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len as u64);
    let template = format!("{{bar:40}} {{pos}}/{{len}} {what}  {{msg}} ({{elapsed}}, eta {{eta}})");
    bar.set_style(
        ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// A spinner with the elapsed time for one long piece of work that cannot count its steps (a
/// fine patch's solve, whose message `crate::solve_display` keeps up to date), `what` after
/// it; redrawn ten times a second by its own thread ([`tick_steadily`]), hidden with `--quiet`
/// (and off a terminal).
pub fn spinner(what: &str) -> ProgressBar {
    if QUIET.load(Ordering::Relaxed) {
        return ProgressBar::hidden();
    }
    let spinner = ProgressBar::new_spinner();
    spinner.set_style(
        ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    spinner.set_message(what.to_string());
    tick_steadily(&spinner);
    spinner
}

/// Redraws `bar` ten times a second from a thread of its own until it is finished or dropped,
/// when it is drawn at all. indicatif's own ticker panics when the thread cannot be started
/// (an address-space limit leaves no room for its stack: exit 101 instead of the solve's own
/// "not enough memory"); this one then leaves the bar still, redrawn only when it changes.
pub fn tick_steadily(bar: &ProgressBar) {
    if bar.is_hidden() {
        return;
    }
    let weak = bar.downgrade();
    let ticker = move || {
        while let Some(bar) = weak.upgrade().filter(|b| !b.is_finished()) {
            bar.tick();
            drop(bar);
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    };
    let _ = std::thread::Builder::new()
        .name("progress".into())
        .spawn(ticker);
}
