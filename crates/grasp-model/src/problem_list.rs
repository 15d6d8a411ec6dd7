//! The one collector of an input's problems: every input the project reads gathers its
//! [`InputProblem`]s here (a scene's structural and validation problems, a schedule's; a batch
//! line carries its scene's) and lists at most [`MAX_LISTED_PROBLEMS`] of them, the rest
//! counted in one last `(more)` problem.

use crate::error::InputProblem;

/// Most problems listed in one error (the rest are counted).
pub const MAX_LISTED_PROBLEMS: usize = 50;

/// The problems found in one input, the first [`MAX_LISTED_PROBLEMS`] kept and the rest
/// counted.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ProblemList {
    /// The problems kept, in the order found.
    listed: Vec<InputProblem>,
    /// Problems found beyond the listed ones.
    unlisted: usize,
}

impl ProblemList {
    /// No problem yet.
    pub fn new() -> Self {
        ProblemList::default()
    }

    /// Adds a problem (counted only, once [`MAX_LISTED_PROBLEMS`] are listed).
    pub fn push(&mut self, problem: InputProblem) {
        if self.listed.len() < MAX_LISTED_PROBLEMS {
            self.listed.push(problem);
        } else {
            self.unlisted += 1;
        }
    }

    /// Adds the problem at `path`: `message` says what is wrong, `fix` what to do.
    pub fn add(
        &mut self,
        path: impl Into<String>,
        message: impl Into<String>,
        fix: impl Into<String>,
    ) {
        self.push(InputProblem::new(path, message, fix));
    }

    /// Whether no problem was found.
    pub fn is_empty(&self) -> bool {
        self.listed.is_empty()
    }

    /// Every problem found: the listed ones, then (when some were not listed) one `(more)`
    /// problem counting the rest.
    pub fn into_problems(self) -> Vec<InputProblem> {
        let mut problems = self.listed;
        if self.unlisted > 0 {
            problems.push(InputProblem::new(
                "(more)",
                format!("{} more problem(s) not listed", self.unlisted),
                "correct the ones above and run again",
            ));
        }
        problems
    }

    /// `Ok` when no problem was found, else every problem (see [`ProblemList::into_problems`]).
    pub fn finish(self) -> Result<(), Vec<InputProblem>> {
        match self.is_empty() {
            true => Ok(()),
            false => Err(self.into_problems()),
        }
    }
}

impl Extend<InputProblem> for ProblemList {
    fn extend<I: IntoIterator<Item = InputProblem>>(&mut self, problems: I) {
        for p in problems {
            self.push(p);
        }
    }
}

impl FromIterator<InputProblem> for ProblemList {
    fn from_iter<I: IntoIterator<Item = InputProblem>>(problems: I) -> Self {
        let mut list = ProblemList::new();
        list.extend(problems);
        list
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_the_first_problems_and_counts_the_rest() {
        let mut list = ProblemList::new();
        assert_eq!(list.clone().finish(), Ok(()));
        for i in 0..MAX_LISTED_PROBLEMS + 3 {
            list.add(format!("x[{i}]"), "is bad", "fix it");
        }
        let p = list.finish().unwrap_err();
        assert_eq!(p.len(), MAX_LISTED_PROBLEMS + 1);
        assert_eq!(
            p[MAX_LISTED_PROBLEMS - 1].path,
            format!("x[{}]", MAX_LISTED_PROBLEMS - 1)
        );
        let more = &p[MAX_LISTED_PROBLEMS];
        assert_eq!(
            (more.path.as_str(), more.message.as_str()),
            ("(more)", "3 more problem(s) not listed")
        );
    }
}
