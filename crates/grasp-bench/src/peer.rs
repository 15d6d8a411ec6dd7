//! The peer measurement: an FFT boundary-element library (tamaas, from PyPI)
//! solving the same frictionless Hertz grid as a `hertz_<n>x<n>_fft` case, in the same bench
//! run. `scripts/peer-hertz.py` is compiled in and fed to the peer's Python on standard
//! input (so the bench runs anywhere, like its bundled scenes); the problem's numbers are read
//! from the case's scene and passed as arguments, so both codes solve the same problem. The
//! script prints one JSON line ([`PeerRecord`]).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use grasp_model::hertz_parameters;

use crate::case::Prepared;
use crate::scratch_folder::ScratchFolder;

/// The peer's script, `scripts/peer-hertz.py`.
pub const PEER_SCRIPT: &str = include_str!("../../../scripts/peer-hertz.py");

/// The script's exit code when numpy or the peer's package is missing.
const EXIT_MISSING: i32 = 3;

/// Whether the peer runs beside the Hertz FFT cases ([`crate::PEER_CASES`]), and with which
/// Python.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Peer {
    /// This Python (with the peer's package) runs the peer's script.
    Python(PathBuf),
    /// No peer, and why (said under the table).
    Absent(String),
}

/// The frictionless problem the peer solves: a square patch of `grid` x `grid` elements
/// centred on the contact point, a sphere of radius `radius_m` on a flat, or (a textured
/// patch) the gap map `gap_m` of our model with the tilt our solution gives the object.
#[derive(Debug, Clone, PartialEq)]
pub struct PeerProblem {
    /// Elements per side.
    pub grid: usize,
    /// Sphere radius, m.
    pub radius_m: f64,
    /// Combined modulus E* of the two bodies, Pa.
    pub e_star_pa: f64,
    /// Total normal load, N.
    pub load_n: f64,
    /// Patch width, m.
    pub width_m: f64,
    /// A textured patch's gap map, m (element `k = i grid + j`), tilted as our solution
    /// tilts the object; `None` for the sphere.
    pub gap_m: Option<Vec<f64>>,
    /// Our answer on a textured patch: its peak pressure (Pa) and its elements in contact.
    pub ours: Option<(f64, usize)>,
}

/// What the peer's script reports (its JSON line).
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
pub struct PeerRecord {
    /// The peer's package name.
    pub peer: String,
    /// Its installed version.
    pub version: String,
    /// Elements per side.
    pub grid: usize,
    /// Median of the timed runs (setup and solve), s.
    pub median_s: f64,
    /// Fastest timed run, s.
    pub min_s: f64,
    /// Slowest timed run, s.
    pub max_s: f64,
    /// Timed runs.
    pub runs: usize,
    /// The peer's tolerance (its own relative measure).
    pub tolerance: f64,
    /// Largest element pressure against Hertz's p0, relative, signed (`None` for a gap map).
    pub p0_error: Option<f64>,
    /// Radius of the contact area's circle against Hertz's a, relative, signed (`None` for a
    /// gap map).
    pub contact_radius_error: Option<f64>,
    /// Total pressure times element area against the load, relative, signed (`None` for a
    /// gap map).
    pub load_error: Option<f64>,
    /// The peer's largest element pressure, Pa.
    pub p_max_pa: f64,
    /// The peer's elements in contact (positive pressure).
    pub contact_elements: usize,
}

/// Why the peer was not measured.
#[derive(Debug, thiserror::Error)]
pub enum PeerError {
    /// The case is not a single-finger Hertz case on a square patch.
    #[error("bench case {case}: no peer problem: {message}")]
    Problem {
        /// The case's name.
        case: String,
        /// Why the case has no peer problem.
        message: String,
    },
    /// No such Python, or the peer's package is not installed for it.
    #[error("the peer is not installed for {}: {message}", python.display())]
    Missing {
        /// The Python asked for.
        python: PathBuf,
        /// What the attempt to run it said.
        message: String,
    },
    /// The peer ran and failed, or printed no record.
    #[error("the peer failed with {}: {message}", python.display())]
    Failed {
        /// The Python that ran the peer.
        python: PathBuf,
        /// What it printed, or what was missing from its output.
        message: String,
    },
}

impl PeerProblem {
    /// The problem of a prepared Hertz case: its scene's finger, patch and load.
    pub fn of(prepared: &Prepared) -> Result<PeerProblem, PeerError> {
        let err = |message: String| PeerError::Problem {
            case: prepared.case.name.to_string(),
            message,
        };
        let scene = &prepared.scene;
        let (radius_m, e_star_pa) = hertz_parameters(scene).map_err(err)?;
        let patch = &scene.fingers[0].patch;
        if patch.grid[0] != patch.grid[1] || patch.size[0] != patch.size[1] {
            return Err(err(format!(
                "the patch is {:?} elements over {:?} m; the peer takes a square grid",
                patch.grid, patch.size
            )));
        }
        let mut problem = PeerProblem {
            grid: patch.grid[0],
            radius_m,
            e_star_pa,
            load_n: scene.object.weight,
            width_m: patch.size[0],
            gap_m: None,
            ours: None,
        };
        if scene.fingers[0].texture.is_some() {
            problem.add_tilted_gap(prepared).map_err(err)?;
        }
        Ok(problem)
    }

    /// A textured patch: our model's gap map, tilted by the object's rotation `theta` in our
    /// solution (the object's point `p` moves `theta x (p - c)` about its centre of mass `c`,
    /// which opens the gap along the normal `n` by `theta . ((p - c) x n)`), and our answer's
    /// peak pressure and contact elements.
    fn add_tilted_gap(&mut self, prepared: &Prepared) -> Result<(), String> {
        let model = grasp_model::GraspModel::from_loaded_with(
            &prepared.scene,
            grasp_model::ComplianceChoice::Auto,
        )
        .map_err(|e| e.to_string())?;
        let solved = grasp_model::GraspSolver::new(model.clone(), prepared.solve_options())
            .solve(&grasp_model::StepInputs::of_scene(&model))
            .map_err(|e| e.to_string())?;
        let (Some(rigid), Some(ours)) = (&solved.rigid_displacement, solved.fingers.first()) else {
            return Err(format!(
                "our solve did not give forces ({:?})",
                solved.status
            ));
        };
        let theta = rigid.rotation_rad;
        let (finger, com) = (&model.fingers()[0], model.center_of_mass_m());
        let n = finger.frame().normal;
        let gap = (0..finger.patch().len())
            .map(|k| {
                let r = (finger.element_point(k) - com).cross(&n);
                finger.patch().gap_m[k] + (0..3).map(|c| theta[c] * r[c]).sum::<f64>()
            })
            .collect();
        self.gap_m = Some(gap);
        let contact = ours
            .elements
            .iter()
            .filter(|e| e.normal_force_n > 0.0)
            .count();
        self.ours = Some((ours.peak_pressure_pa, contact));
        Ok(())
    }

    /// The script's arguments for this problem and `repeats` timed runs.
    fn arguments(&self, repeats: usize, gap_file: Option<&Path>) -> Vec<String> {
        let mut args = vec!["-".to_string()];
        for (flag, value) in [
            ("--grid", self.grid.to_string()),
            ("--repeats", repeats.to_string()),
            ("--radius", format!("{:e}", self.radius_m)),
            ("--e-star", format!("{:e}", self.e_star_pa)),
            ("--load", format!("{:e}", self.load_n)),
            ("--width", format!("{:e}", self.width_m)),
        ] {
            args.push(flag.into());
            args.push(value);
        }
        if let Some(path) = gap_file {
            args.push("--gap".into());
            args.push(path.display().to_string());
        }
        args
    }

    /// Runs the peer's script with `python` (`repeats` timed runs after an untimed one) and
    /// reads its record.
    pub fn measure(&self, python: &Path, repeats: usize) -> Result<PeerRecord, PeerError> {
        let missing = |message: String| PeerError::Missing {
            python: python.to_path_buf(),
            message,
        };
        let failed = |message: String| PeerError::Failed {
            python: python.to_path_buf(),
            message,
        };
        // A gap map goes to the peer in a file of our scratch folder (removed with it).
        let scratch = match &self.gap_m {
            Some(_) => Some(ScratchFolder::create().map_err(|e| failed(e.to_string()))?),
            None => None,
        };
        let gap_file = scratch.as_ref().map(|s| s.path().join("gap.f64"));
        if let (Some(path), Some(gap)) = (&gap_file, &self.gap_m) {
            let bytes: Vec<u8> = gap.iter().flat_map(|v| v.to_le_bytes()).collect();
            std::fs::write(path, bytes).map_err(|e| failed(e.to_string()))?;
        }
        let mut child = Command::new(python)
            .args(self.arguments(repeats, gap_file.as_deref()))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| missing(e.to_string()))?;
        if let Some(mut stdin) = child.stdin.take() {
            // A Python that exits before reading (a broken interpreter) closes the pipe: its
            // exit status and message below say why, not this write's broken pipe.
            let _ = stdin.write_all(PEER_SCRIPT.as_bytes());
        }
        let out = child
            .wait_with_output()
            .map_err(|e| failed(e.to_string()))?;
        let stderr = String::from_utf8_lossy(&out.stderr).trim().to_string();
        match out.status.code() {
            Some(0) => {}
            Some(EXIT_MISSING) => return Err(missing(stderr)),
            _ => return Err(failed(format!("{}: {stderr}", out.status))),
        }
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout.lines().last().unwrap_or_default();
        let record: PeerRecord = serde_json::from_str(line)
            .map_err(|e| failed(format!("unreadable record {line:?}: {e}")))?;
        if record.grid != self.grid {
            return Err(failed(format!(
                "the record is for grid {}, not {}",
                record.grid, self.grid
            )));
        }
        Ok(record)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::FFT_CASES;

    #[test]
    fn the_peer_problem_is_the_scene_s() {
        let prepared = FFT_CASES[0]
            .prepare(grasp_model::SolverChoice::Native)
            .expect("prepare");
        let p = PeerProblem::of(&prepared).expect("a Hertz case");
        assert_eq!(p.grid, 128);
        assert_eq!(p.radius_m, 0.01);
        assert_eq!(p.load_n, 10.0);
        assert_eq!(p.width_m, 0.000212);
        // Steel on steel: E* = E / (2 (1 - nu^2)).
        assert!((p.e_star_pa / (210e9 / (2.0 * 0.91)) - 1.0).abs() < 1e-12);
        assert_eq!(p.gap_m, None);
        let args = p.arguments(4, None);
        assert_eq!(&args[..5], &["-", "--grid", "128", "--repeats", "4"]);
    }

    #[test]
    fn a_missing_python_is_reported_as_missing() {
        let prepared = FFT_CASES[0]
            .prepare(grasp_model::SolverChoice::Native)
            .expect("prepare");
        let p = PeerProblem::of(&prepared).expect("a Hertz case");
        let e = p
            .measure(Path::new("/nonexistent/python"), 1)
            .expect_err("no such Python");
        assert!(matches!(e, PeerError::Missing { .. }), "{e}");
    }
}
