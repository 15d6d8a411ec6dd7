//! Fingers whose force curves coincide (a symmetric pair: one curve hidden behind the other),
//! found from the steps as they come, for the note every plot of them carries (the SVG's
//! force history and the Rerun recording's plot legends).

/// Relative tolerance: curves agree at every step to this fraction of the largest force.
const SAME_RELATIVE: f64 = 1e-9;

/// The largest difference between each pair of fingers' normal and friction forces so far.
#[derive(Debug, Clone)]
pub struct IdenticalCurves {
    names: Vec<String>,
    /// `diff[a * n + b]`, N, for `a < b`.
    diff: Vec<f64>,
    /// The largest force of any finger so far, N.
    fmax: f64,
    steps: usize,
}

impl IdenticalCurves {
    /// No steps yet, for these fingers (scene order).
    pub fn new(names: &[String]) -> Self {
        let n = names.len();
        IdenticalCurves {
            names: names.to_vec(),
            diff: vec![0.0; n * n],
            fmax: 0.0,
            steps: 0,
        }
    }

    /// Adds a step's `[normal, |friction|]` per finger, N (0 for a finger without forces).
    pub fn push(&mut self, forces: &[[f64; 2]]) {
        let n = self.names.len();
        for a in 0..n {
            self.fmax = self.fmax.max(forces[a][0]).max(forces[a][1]);
            for b in a + 1..n {
                let d = (forces[a][0] - forces[b][0])
                    .abs()
                    .max((forces[a][1] - forces[b][1]).abs());
                self.diff[a * n + b] = self.diff[a * n + b].max(d);
            }
        }
        self.steps += 1;
    }

    /// Adds a solved step: each finger's normal and friction force in `solution` (0 for a finger
    /// it does not hold), N.
    pub fn push_solution(&mut self, solution: &grasp_model::Solution) {
        let forces: Vec<[f64; 2]> = self
            .names
            .iter()
            .map(|n| {
                solution
                    .finger(n)
                    .map_or([0.0; 2], |f| [f.normal_force_n, f.tangential_magnitude_n])
            })
            .collect();
        self.push(&forces);
    }

    /// The groups of two or more fingers with the same curves, by name, scene order.
    pub fn groups(&self) -> Vec<Vec<String>> {
        let n = self.names.len();
        let same = |a: usize, b: usize| self.diff[a * n + b] <= SAME_RELATIVE * self.fmax;
        let mut grouped = vec![false; n];
        let mut groups = Vec::new();
        for a in 0..n {
            if grouped[a] || self.steps == 0 {
                continue;
            }
            let members: Vec<usize> = (a..n)
                .filter(|&b| !grouped[b] && (b == a || same(a, b)))
                .collect();
            if members.len() > 1 {
                members.iter().for_each(|&b| grouped[b] = true);
                groups.push(members.iter().map(|&b| self.names[b].clone()).collect());
            }
        }
        groups
    }

    /// "f1 = f2, f3 = f4: identical curves", or None when every finger's curves are its own.
    pub fn note(&self) -> Option<String> {
        let groups = self.groups();
        (!groups.is_empty()).then(|| {
            let named: Vec<String> = groups.iter().map(|g| g.join(" = ")).collect();
            format!("{}: identical curves", named.join(", "))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: &[&str]) -> Vec<String> {
        n.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_symmetric_pair_is_noted_and_a_different_finger_is_not() {
        let mut c = IdenticalCurves::new(&names(&["f1", "f2", "f3"]));
        c.push(&[[1.0, 0.5], [1.0, 0.5], [2.0, 0.1]]);
        c.push(&[[3.0, 0.2], [3.0, 0.2], [2.5, 0.1]]);
        assert_eq!(c.groups(), vec![names(&["f1", "f2"])]);
        assert_eq!(c.note().as_deref(), Some("f1 = f2: identical curves"));
    }

    #[test]
    fn curves_that_part_at_one_step_are_not_identical() {
        let mut c = IdenticalCurves::new(&names(&["f1", "f2"]));
        c.push(&[[1.0, 0.5], [1.0, 0.5]]);
        c.push(&[[1.0, 0.5], [1.0, 0.4]]);
        assert!(c.groups().is_empty());
        assert_eq!(c.note(), None);
        assert_eq!(IdenticalCurves::new(&names(&["f1", "f2"])).note(), None);
    }
}
