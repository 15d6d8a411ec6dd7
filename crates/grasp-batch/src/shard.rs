//! Shards: a batch split over the tasks of a job array, task `I` of `N` taking every `N`-th scene
//! from the `I`-th (0-based), so a Slurm job array or a Kubernetes Indexed Job runs the same
//! command unchanged and `grasp batch --merge` joins the outputs.

use crate::error::BatchError;
use crate::option_names;

/// Task `index` of `count` (0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This task, `0..count`.
    pub index: usize,
    /// Number of tasks, >= 1.
    pub count: usize,
}

impl Shard {
    /// The whole batch.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// True when scene `i` (0-based position in the input) belongs to this shard.
    pub fn takes(&self, i: usize) -> bool {
        i % self.count == self.index
    }

    /// Parses `I/N` (0 <= I < N).
    pub fn parse(text: &str) -> Result<Shard, BatchError> {
        let usage = |message: String| BatchError::Usage {
            what: format!("`{}`", option_names::SHARD),
            message,
        };
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| usage(format!("`{text}` is not I/N; write e.g. 0/4 (task 0 of 4)")))?;
        let parse = |s: &str| s.trim().parse::<usize>().ok();
        match (parse(i), parse(n)) {
            (Some(index), Some(count)) if count >= 1 && index < count => Ok(Shard { index, count }),
            _ => Err(usage(format!(
                "`{text}`: give I/N with whole numbers 0 <= I < N, e.g. 0/4"
            ))),
        }
    }

    /// The shard the environment of a job array gives, if any:
    /// - Slurm: task `(SLURM_ARRAY_TASK_ID - MIN) / STEP` of `SLURM_ARRAY_TASK_COUNT`, with
    ///   `SLURM_ARRAY_TASK_MIN` (0 if unset), `_STEP` (1 if unset) and `_MAX` (checked when
    ///   set): a stepped array (`--array=0-8:2`) maps to tasks 0.. of its count; an array
    ///   whose ids are not evenly spaced (`--array=1,3,8`) cannot be mapped and is refused;
    /// - Kubernetes Indexed Job: `JOB_COMPLETION_INDEX` of `GRASP_SHARD_COUNT` (set it to the
    ///   Job's `completions`; Kubernetes does not pass the count itself).
    pub fn from_env(get: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>, BatchError> {
        let env = EnvNumbers(&get);
        if env.num("SLURM_ARRAY_TASK_ID")?.is_some() {
            return slurm_shard(&env).map(Some);
        }
        if let Some(index) = env.num("JOB_COMPLETION_INDEX")? {
            let count = env
                .num("GRASP_SHARD_COUNT")?
                .ok_or_else(|| BatchError::Usage {
                    what: "GRASP_SHARD_COUNT".into(),
                    message: "is not set although JOB_COMPLETION_INDEX is; set it to the Indexed \
                          Job's completions, or give the shard (`Shard::parse`)"
                        .into(),
                })?;
            return check(index, count, "JOB_COMPLETION_INDEX").map(Some);
        }
        Ok(None)
    }
}

/// Whole numbers from the environment.
struct EnvNumbers<'a>(&'a dyn Fn(&str) -> Option<String>);

impl EnvNumbers<'_> {
    fn num(&self, name: &str) -> Result<Option<usize>, BatchError> {
        match (self.0)(name) {
            None => Ok(None),
            Some(v) => v
                .trim()
                .parse::<usize>()
                .map(Some)
                .map_err(|_| BatchError::Usage {
                    what: name.into(),
                    message: format!("`{v}` is not a whole number"),
                }),
        }
    }
}

fn check(index: usize, count: usize, what: &str) -> Result<Shard, BatchError> {
    if count >= 1 && index < count {
        Ok(Shard { index, count })
    } else {
        Err(BatchError::Usage {
            what: what.into(),
            message: format!("task {index} of {count} is out of range"),
        })
    }
}

/// The shard of a Slurm array task (see [`Shard::from_env`]).
fn slurm_shard(env: &EnvNumbers<'_>) -> Result<Shard, BatchError> {
    let usage = |what: &str, message: String| BatchError::Usage {
        what: what.into(),
        message,
    };
    let id = env.num("SLURM_ARRAY_TASK_ID")?.unwrap_or(0);
    let count = env.num("SLURM_ARRAY_TASK_COUNT")?.ok_or_else(|| {
        usage(
            "SLURM_ARRAY_TASK_COUNT",
            "is not set although SLURM_ARRAY_TASK_ID is; run inside a job array (sbatch \
             --array=0-N) or give the shard (`Shard::parse`)"
                .into(),
        )
    })?;
    let min = env.num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
    let step = env.num("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1);
    if step == 0 || count == 0 {
        return Err(usage(
            "SLURM_ARRAY_TASK_STEP",
            format!("step {step} with {count} tasks cannot be mapped to shards"),
        ));
    }
    let last = (count - 1)
        .checked_mul(step)
        .and_then(|x| x.checked_add(min));
    let max = env.num("SLURM_ARRAY_TASK_MAX")?;
    if last.is_none() || max.is_some_and(|m| Some(m) != last) {
        return Err(usage(
            "SLURM_ARRAY_TASK_MAX",
            format!(
                "the array's task ids from {min} to {} in steps of {step} are not {count} \
                 evenly spaced ids (a list such as --array=1,3,8?); use a range, stepped or \
                 not (--array=0-N or 0-N:S), or give the shard (`Shard::parse`)",
                max.map_or("?".into(), |m| m.to_string())
            ),
        ));
    }
    let offset = id
        .checked_sub(min)
        .filter(|o| o % step == 0)
        .ok_or_else(|| {
            usage(
                "SLURM_ARRAY_TASK_ID",
                format!("{id} is not one of the array's ids {min}, {min} + {step}, ..."),
            )
        })?;
    check(offset / step, count, "SLURM_ARRAY_TASK_ID")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| vars.iter().find(|v| v.0 == k).map(|v| v.1.to_string())
    }

    #[test]
    fn shards_partition_the_input() {
        let shards: Vec<Shard> = (0..3).map(|i| Shard { index: i, count: 3 }).collect();
        for i in 0..100 {
            assert_eq!(shards.iter().filter(|s| s.takes(i)).count(), 1);
        }
    }

    #[test]
    fn parse_and_environment() {
        assert_eq!(Shard::parse("1/4").unwrap(), Shard { index: 1, count: 4 });
        for bad in ["4/4", "1", "a/b", "0/0"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
        let slurm = [
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_MIN", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        assert_eq!(
            Shard::from_env(env(&slurm)).unwrap(),
            Some(Shard { index: 2, count: 4 })
        );
        // Stepped arrays: --array=0-8:2 (ids 0, 2, 4, 6, 8), --array=3-11:4 (3, 7, 11).
        let stepped = |id: &str, min: &str, max: &str, step: &str, count: &str| {
            let vars = [
                ("SLURM_ARRAY_TASK_ID", id),
                ("SLURM_ARRAY_TASK_MIN", min),
                ("SLURM_ARRAY_TASK_MAX", max),
                ("SLURM_ARRAY_TASK_STEP", step),
                ("SLURM_ARRAY_TASK_COUNT", count),
            ];
            Shard::from_env(env(&vars))
        };
        for (id, want) in [("0", 0), ("2", 1), ("4", 2), ("6", 3), ("8", 4)] {
            assert_eq!(
                stepped(id, "0", "8", "2", "5").unwrap(),
                Some(Shard {
                    index: want,
                    count: 5
                })
            );
        }
        assert_eq!(
            stepped("11", "3", "11", "4", "3").unwrap(),
            Some(Shard { index: 2, count: 3 })
        );
        // An id off the step, a sparse list (--array=1,3,8: 3 tasks from 1 to 8), a step of 0.
        assert!(stepped("5", "0", "8", "2", "5").is_err());
        let sparse = stepped("3", "1", "8", "1", "3").unwrap_err().to_string();
        assert!(sparse.contains("evenly spaced"), "{sparse}");
        let sparse = [
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ];
        assert!(Shard::from_env(env(&sparse)).is_err());
        assert!(stepped("0", "0", "0", "0", "1").is_err());
        let k8s = [("JOB_COMPLETION_INDEX", "1"), ("GRASP_SHARD_COUNT", "2")];
        assert_eq!(
            Shard::from_env(env(&k8s)).unwrap(),
            Some(Shard { index: 1, count: 2 })
        );
        let missing = [("JOB_COMPLETION_INDEX", "1")];
        assert!(Shard::from_env(env(&missing))
            .unwrap_err()
            .to_string()
            .contains("GRASP_SHARD_COUNT"));
        assert_eq!(Shard::from_env(env(&[])).unwrap(), None);
    }
}
