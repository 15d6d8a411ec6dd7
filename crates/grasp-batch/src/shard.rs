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
    /// - Slurm: `SLURM_ARRAY_TASK_ID` minus `SLURM_ARRAY_TASK_MIN` (0 if unset) of
    ///   `SLURM_ARRAY_TASK_COUNT`;
    /// - Kubernetes Indexed Job: `JOB_COMPLETION_INDEX` of `GRASP_SHARD_COUNT` (set it to the
    ///   Job's `completions`; Kubernetes does not pass the count itself).
    pub fn from_env(get: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>, BatchError> {
        let num = |name: &str| -> Result<Option<usize>, BatchError> {
            match get(name) {
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
        };
        let check = |index: usize, count: usize, what: &str| {
            if count >= 1 && index < count {
                Ok(Some(Shard { index, count }))
            } else {
                Err(BatchError::Usage {
                    what: what.into(),
                    message: format!("task {index} of {count} is out of range"),
                })
            }
        };
        if let Some(id) = num("SLURM_ARRAY_TASK_ID")? {
            let count = num("SLURM_ARRAY_TASK_COUNT")?.ok_or_else(|| BatchError::Usage {
                what: "SLURM_ARRAY_TASK_COUNT".into(),
                message: "is not set although SLURM_ARRAY_TASK_ID is; run inside a job array \
                          (sbatch --array=0-N) or give the shard (`Shard::parse`)"
                    .into(),
            })?;
            let min = num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let index = id.checked_sub(min).ok_or_else(|| BatchError::Usage {
                what: "SLURM_ARRAY_TASK_ID".into(),
                message: format!("{id} is below SLURM_ARRAY_TASK_MIN {min}"),
            })?;
            return check(index, count, "SLURM_ARRAY_TASK_ID");
        }
        if let Some(index) = num("JOB_COMPLETION_INDEX")? {
            let count = num("GRASP_SHARD_COUNT")?.ok_or_else(|| BatchError::Usage {
                what: "GRASP_SHARD_COUNT".into(),
                message: "is not set although JOB_COMPLETION_INDEX is; set it to the Indexed \
                          Job's completions, or give the shard (`Shard::parse`)"
                    .into(),
            })?;
            return check(index, count, "JOB_COMPLETION_INDEX");
        }
        Ok(None)
    }
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
