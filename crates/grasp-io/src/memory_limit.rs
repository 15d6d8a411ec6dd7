//! The memory limit of a run and the one check of a scene against it, before anything is
//! allocated: the estimate of the path that will run (`grasp_model::estimate_memory_bytes_with`,
//! every patch in the form the compliance choice gives it) against the limit given or, without
//! one, [`DEFAULT_MEMORY_SHARE`] of the machine's memory. Every front end (the CLI's commands,
//! batch lines) checks here, with one message.

use std::fmt;

use grasp_model::{
    estimate_memory_bytes_with, finger_unknowns, option_names, takes_fft, ComplianceChoice,
    FingerSpec, InputProblem, LoadedScene,
};

use crate::machine_memory::{mem_total_bytes, DEFAULT_MEMORY_SHARE, FALLBACK_MEMORY_LIMIT};

/// How messages name the memory limit a caller gives, [`MemoryLimit::given`] (front ends
/// respell it: the CLI's `--max-memory`).
pub const MAX_MEMORY: &str = "MemoryLimit::given";

/// A limit on the memory a solve may plan to use, bytes, and where it came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryLimit {
    /// The limit, bytes.
    pub bytes: u64,
    /// Where it came from (for messages).
    origin: Origin,
}

/// Where a limit came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Origin {
    /// Given by the caller.
    Given,
    /// A share of the machine's memory.
    MachineShare,
    /// The fallback: the machine's memory could not be read.
    Fallback,
    /// The machine's whole memory, below the limit given.
    MachineTotal,
}

impl MemoryLimit {
    /// The limit the caller gives, bytes.
    pub fn given(bytes: u64) -> MemoryLimit {
        MemoryLimit {
            bytes,
            origin: Origin::Given,
        }
    }

    /// The default limit: [`DEFAULT_MEMORY_SHARE`] of `MemTotal`, or
    /// [`FALLBACK_MEMORY_LIMIT`] when it cannot be read.
    pub fn machine_default() -> MemoryLimit {
        match mem_total_bytes() {
            Some(total) => MemoryLimit {
                bytes: (total as f64 * DEFAULT_MEMORY_SHARE) as u64,
                origin: Origin::MachineShare,
            },
            None => MemoryLimit {
                bytes: FALLBACK_MEMORY_LIMIT,
                origin: Origin::Fallback,
            },
        }
    }

    /// The limit given, or the default without one.
    pub fn of(given: Option<u64>) -> MemoryLimit {
        given.map_or_else(MemoryLimit::machine_default, MemoryLimit::given)
    }

    /// The scene's estimated memory, bytes, or its refusal when the estimate exceeds the
    /// limit, naming its largest patch (each patch in the form `compliance` gives it: the
    /// estimate of the path that will run).
    /// A limit above the machine's memory (`--max-memory 1T` on a 23 GiB machine) is cut to
    /// it: no limit makes room the machine does not have.
    pub fn check(
        &self,
        scene: &LoadedScene,
        compliance: ComplianceChoice,
    ) -> Result<u64, MemoryError> {
        self.check_within(scene, compliance, mem_total_bytes())
    }

    /// [`Self::check`] on a machine of `machine_bytes` of memory (`None`: unknown).
    fn check_within(
        &self,
        scene: &LoadedScene,
        compliance: ComplianceChoice,
        machine_bytes: Option<u64>,
    ) -> Result<u64, MemoryError> {
        let fft = |f: &FingerSpec| takes_fft(scene, f, compliance);
        let need = estimate_memory_bytes_with(scene, fft);
        let limit = match machine_bytes {
            Some(total) if total < self.bytes => MemoryLimit {
                bytes: total,
                origin: Origin::MachineTotal,
            },
            _ => *self,
        };
        if need <= limit.bytes {
            return Ok(need);
        }
        let biggest = scene
            .fingers
            .iter()
            .enumerate()
            .max_by_key(|(_, f)| finger_unknowns(scene, f));
        let largest = biggest.map_or(String::new(), |(i, f)| {
            let n = finger_unknowns(scene, f);
            let form = match fft(f) {
                true => "the FFT operator".to_string(),
                false => format!("a dense {n} x {n} block"),
            };
            format!(
                " (largest: fingers[{i}] `{}`, grid {}x{}, {n} unknowns, {form})",
                f.name, f.patch.grid[0], f.patch.grid[1]
            )
        });
        Err(MemoryError {
            need_bytes: need,
            limit,
            largest,
            dense: compliance == ComplianceChoice::Dense,
        })
    }
}

impl fmt::Display for MemoryLimit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = human(self.bytes);
        match self.origin {
            Origin::Given => write!(f, "`{MAX_MEMORY}` {b}"),
            Origin::MachineShare => {
                write!(
                    f,
                    "the default limit {b} (a quarter of this machine's memory)"
                )
            }
            Origin::Fallback => write!(f, "the default limit {b} (/proc/meminfo unreadable)"),
            Origin::MachineTotal => write!(
                f,
                "this machine's memory {b} (MemTotal in /proc/meminfo; a larger `{MAX_MEMORY}` \
                 cannot make room)"
            ),
        }
    }
}

/// A scene whose estimated memory exceeds the limit.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}; fix: {}", self.message(), self.fix())]
pub struct MemoryError {
    /// The estimate, bytes.
    pub need_bytes: u64,
    /// The limit it exceeds.
    pub limit: MemoryLimit,
    /// The largest patch, for the message.
    largest: String,
    /// Whether every patch was asked dense (the FFT operator would need less).
    dense: bool,
}

impl MemoryError {
    /// What is wrong: `needs an estimated ... of memory (largest: ...), more than <limit>`.
    pub fn message(&self) -> String {
        format!(
            "needs an estimated {} of memory{}, more than {}",
            human(self.need_bytes),
            self.largest,
            self.limit
        )
    }

    /// What to do about it.
    pub fn fix(&self) -> String {
        let grid = match self.dense {
            true => format!("use a coarser grid or `{}` fft", option_names::COMPLIANCE),
            false => "use a coarser grid (`grasp study` shows the accuracy each grid gives)".into(),
        };
        match self.limit.origin {
            Origin::MachineTotal => format!("{grid}, or run on a machine with more memory"),
            _ => format!("{grid}, or raise `{MAX_MEMORY}`"),
        }
    }

    /// The problem of a scene it makes (at `fingers`, the patches' grids).
    pub fn problem(&self) -> InputProblem {
        InputProblem::new("fingers", self.message(), self.fix())
    }
}

/// Bytes for a reader: GiB, MiB or KiB.
pub fn human(b: u64) -> String {
    let x = b as f64;
    if x >= (1u64 << 30) as f64 {
        format!("{:.1} GiB", x / (1u64 << 30) as f64)
    } else if x >= (1u64 << 20) as f64 {
        format!("{:.1} MiB", x / (1u64 << 20) as f64)
    } else {
        format!("{:.1} KiB", x / 1024.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_limit_names_where_it_came_from() {
        assert_eq!(
            MemoryLimit::given(4 << 30).to_string(),
            format!("`{MAX_MEMORY}` 4.0 GiB")
        );
        assert!(MemoryLimit::of(None)
            .to_string()
            .starts_with("the default limit"));
        assert_eq!(human(1536), "1.5 KiB");
    }

    #[test]
    fn a_scene_over_the_limit_names_its_largest_patch_and_the_fix() {
        let text = include_str!("../../../examples/cube_a.json");
        let scene = LoadedScene::from_json_str(text).unwrap();
        let limit = MemoryLimit::given(1 << 10);
        assert!(limit.check(&scene, ComplianceChoice::Auto).is_err());
        let e = limit.check(&scene, ComplianceChoice::Dense).unwrap_err();
        assert!(e.need_bytes > 1 << 10);
        let p = e.problem();
        assert_eq!(p.path, "fingers");
        assert!(
            p.message.starts_with("needs an estimated ")
                && p.message.contains("(largest: fingers[")
                && p.message
                    .ends_with(&format!("more than `{MAX_MEMORY}` 1.0 KiB")),
            "{p}"
        );
        let fix = format!(
            "use a coarser grid or `{}` fft, or raise `{MAX_MEMORY}`",
            option_names::COMPLIANCE
        );
        assert_eq!(p.fix, fix);
        assert_eq!(e.to_string(), format!("{}; fix: {fix}", p.message));
        assert_eq!(
            MemoryLimit::given(u64::MAX).check_within(&scene, ComplianceChoice::Dense, None),
            Ok(e.need_bytes)
        );
    }

    /// A limit above the machine's memory is cut to it (8 fingers of 1024 x 1024,
    /// an estimated 49.6 GiB, were accepted on a 23 GiB machine with `--max-memory 1T`).
    #[test]
    fn no_limit_makes_room_the_machine_does_not_have() {
        let text = include_str!("../../../examples/cube_a.json");
        let scene = LoadedScene::from_json_str(text).unwrap();
        let huge = MemoryLimit::given(1 << 40);
        let e = huge
            .check_within(&scene, ComplianceChoice::Dense, Some(1 << 10))
            .unwrap_err();
        assert!(
            e.message().ends_with(&format!(
                "more than this machine's memory 1.0 KiB (MemTotal in /proc/meminfo; a larger \
                 `{MAX_MEMORY}` cannot make room)"
            )),
            "{}",
            e.message()
        );
        assert!(
            e.fix().ends_with("or run on a machine with more memory"),
            "{}",
            e.fix()
        );
        let need = huge
            .check_within(&scene, ComplianceChoice::Dense, Some(1 << 40))
            .unwrap();
        assert_eq!(need, e.need_bytes);
    }
}
