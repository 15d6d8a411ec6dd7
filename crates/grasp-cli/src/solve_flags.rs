//! The flags choosing how a command solves its scenes, one group flattened into every solving
//! command: `--solver`, `--compliance` and the memory limit (`--max-memory`, checked against
//! the estimate of the path the solver and compliance choose).

use std::path::Path;

use anyhow::Result;
use grasp_model::{ComplianceChoice, LoadedScene, SolveOptions, SolverChoice};

use crate::limits::MemoryArg;

/// `--solver`, `--compliance` and `--max-memory`.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct SolveFlags {
    /// Solver: `auto`, `native` or `clarabel`.
    #[arg(long, default_value = "auto", value_name = "auto|native|clarabel")]
    pub solver: SolverChoice,
    /// Patch compliance: `auto` (dense up to 1,024 unknowns a patch (32x32 frictionless, 22x22 planar, 18x18 with friction in 3-D), the FFT operator above),
    /// `dense` or `fft` (matrix-free, native solver; see docs/guide/solving.md, "Fine patches").
    #[arg(long, default_value = "auto", value_name = "auto|dense|fft")]
    pub compliance: ComplianceChoice,
    #[command(flatten)]
    pub memory: MemoryArg,
}

impl SolveFlags {
    /// The default solve options with this solver and compliance.
    pub fn options(&self) -> SolveOptions {
        SolveOptions {
            solver: self.solver,
            compliance: self.compliance,
            ..SolveOptions::default()
        }
    }

    /// Refuses the scene read from `file` when the path these flags choose would need more
    /// memory than the limit.
    pub fn check_memory(&self, scene: &LoadedScene, file: &Path) -> Result<()> {
        self.memory.check(scene, file, self.compliance)
    }
}
