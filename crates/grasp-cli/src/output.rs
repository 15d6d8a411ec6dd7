//! Output files of a command: the project's one output policy (`grasp_io::OutputSet`:
//! targets checked before any work, each locked for the run, written to exclusive temporary
//! files moved into place on success, never replacing an input or, without `--force`, an
//! existing file), with the CLI's two additions:
//!
//! - a missing output folder is created, and said ("created folder out/");
//! - SIGINT, SIGTERM and SIGHUP remove the temporary and lock files and end the run with
//!   128 + the signal (130, 143, 129), leaving the targets untouched.
//!
//! Every file the command read (scenes, meshes, schedules and their CSV profiles, direction
//! files, batch inputs: [`crate::limits::inputs_read`]) is checked again just before an output
//! is moved into place, so inputs learned during the run are never overwritten either.

use std::fs::File;
use std::path::Path;

use anyhow::{Context, Result};
use grasp_io::{OutputRules, OutputSet, PendingOutput, RunInputs};

use crate::limits;

/// Installs a handler of SIGINT, SIGTERM and SIGHUP that removes this process's temporary and
/// lock files and exits with 128 + the signal number.
pub fn install_signal_cleanup() -> Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
        .context("cannot install the SIGINT/SIGTERM/SIGHUP handler")?;
    let watch = move || {
        if let Some(sig) = signals.forever().next() {
            remove_pending_and_exit(128 + sig, |n| {
                Some(format!(
                    "interrupted: {n} temporary output file(s) removed; existing files are \
                     untouched"
                ))
            });
        }
    };
    // Started fallibly: a process too small for the thread's stack (an address-space limit)
    // is told so instead of panicking.
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(watch)
        .context("cannot start the thread that watches for SIGINT/SIGTERM/SIGHUP")?;
    Ok(())
}

/// Removes this process's temporary and lock files, prints `note(how many temporary outputs)`
/// (if any) on standard error and ends the process with `code`; the registry stays locked, so
/// no temporary file is created or moved into place after this.
pub fn remove_pending_and_exit(code: i32, note: impl FnOnce(usize) -> Option<String>) -> ! {
    let removed = grasp_io::remove_all_for_exit();
    if let Some(text) = note(removed) {
        eprintln!("{text}");
    }
    std::process::exit(code);
}

/// `--force`, one flag group of every command that writes files (a command writing one file,
/// `--out`, says [`FORCE_OUT_HELP`] instead: `#[command(mut_arg("force", ...))]`).
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct ForceArg {
    /// Overwrite output files that already exist.
    #[arg(long)]
    pub force: bool,
}

/// `--force`'s help in a command whose one output is `--out`.
pub const FORCE_OUT_HELP: &str = "Overwrite OUT if it exists";

/// The outputs of a command, checked and locked until dropped.
pub struct Outputs(OutputSet);

/// Checks and locks the `targets` of a command whose named inputs are `inputs` (see the
/// module documentation); says which folders it created.
pub fn claim(targets: &[&Path], inputs: &[&Path], force: bool) -> Result<Outputs> {
    let mut known = RunInputs::of_paths(inputs);
    known.extend(&limits::inputs_read());
    let rules = OutputRules {
        force,
        create_folders: true,
    };
    let set = OutputSet::claim(targets, &known, rules)?;
    let created = set.created_folders();
    for f in created {
        // The deepest folders made (their parents go without saying).
        if !created.iter().any(|g| g.parent() == Some(f.as_path())) {
            println!("created folder {}/", f.display());
        }
    }
    Ok(Outputs(set))
}

impl Outputs {
    /// The claimed outputs, for a library that opens its files itself
    /// ([`grasp_transfer::OutputFiles`]).
    pub fn set(&self) -> &OutputSet {
        &self.0
    }

    /// A new temporary file for `target`.
    pub fn create(&self, target: &Path) -> Result<PendingOutput> {
        Ok(self.0.create(target)?)
    }

    /// Refuses an output that is one of the files read so far (call it once the inputs are
    /// read, before a long run; [`Outputs::commit`] checks again).
    pub fn refuse_inputs_read(&self) -> Result<()> {
        Ok(self.0.refuse_inputs(&limits::inputs_read())?)
    }

    /// Moves the outputs into place, none of them being an input read meanwhile.
    pub fn commit(&self, pending: Vec<PendingOutput>) -> Result<()> {
        self.refuse_inputs_read()?;
        Ok(self.0.commit(pending)?)
    }

    /// Writes `bytes` to `target` through a temporary file moved into place.
    pub fn write(&self, target: &Path, bytes: &[u8]) -> Result<()> {
        let mut pending = self.create(target)?;
        pending.write_all(bytes)?;
        self.commit(vec![pending])
    }

    /// `target` opened for appending in place (a resumed batch), under its lock.
    pub fn open_append(&self, target: &Path) -> Result<File> {
        self.refuse_inputs_read()?;
        Ok(self.0.open_append(target)?)
    }
}
