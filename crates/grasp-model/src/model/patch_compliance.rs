//! The compliance of one finger's patch, m/N, in the form a solve uses: a dense matrix (every
//! entry stored, factorised directly) or the matrix-free FFT operator
//! ([`super::compliance_operator`]), and the rule that picks one.
//!
//! Both discretise the same operator (the exact rectangle integrals of
//! [`super::influence`]); they differ in cost. Dense: `(3N)^2` numbers per finger, products
//! `O(N^2)`, one Cholesky factor per contact pattern. FFT: `O(N)` numbers, products
//! `O(N log N)`, reduced systems solved by conjugate gradients.

use std::sync::Arc;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use super::compliance_operator::ComplianceOperator;
use super::contact_pair::ContactPair;
use super::finger_mount::FingerMount;
use super::influence::{patch_compliance, GridSpec, KernelTable};
use crate::error::OutOfMemory;
use crate::scene::memory_budget::finger_unknowns;
use crate::scene::scene_format::{FingerSpec, Scene};

/// Which form of the patch compliance a model builds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ComplianceChoice {
    /// Dense up to [`AUTO_FFT_ABOVE_UNKNOWNS`] unknowns per patch, FFT above.
    #[default]
    Auto,
    /// The dense matrix (every solver, every analysis).
    Dense,
    /// The FFT operator (the native solver; no sensitivities).
    Fft,
}

impl std::str::FromStr for ComplianceChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(ComplianceChoice::Auto),
            "dense" => Ok(ComplianceChoice::Dense),
            "fft" => Ok(ComplianceChoice::Fft),
            other => Err(format!(
                "unknown compliance `{other}`; choose auto, dense or fft"
            )),
        }
    }
}

impl std::fmt::Display for ComplianceChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ComplianceChoice::Auto => "auto",
            ComplianceChoice::Dense => "dense",
            ComplianceChoice::Fft => "fft",
        })
    }
}

use crate::scene::limits::AUTO_FFT_ABOVE_UNKNOWNS;

/// True when a patch of `unknowns` unknowns (elements times `1 + n_tangential`) takes the FFT
/// operator under `choice` (the automatic choice: above [`AUTO_FFT_ABOVE_UNKNOWNS`]).
pub fn uses_fft(choice: ComplianceChoice, unknowns: usize) -> bool {
    match choice {
        ComplianceChoice::Auto => unknowns > AUTO_FFT_ABOVE_UNKNOWNS,
        ComplianceChoice::Dense => false,
        ComplianceChoice::Fft => true,
    }
}

/// True when `finger`'s patch compliance takes the FFT operator under `choice` (`uses_fft`
/// of its unknowns).
pub fn takes_fft(scene: &Scene, finger: &FingerSpec, choice: ComplianceChoice) -> bool {
    let unknowns = usize::try_from(finger_unknowns(scene, finger)).unwrap_or(usize::MAX);
    uses_fft(choice, unknowns)
}

/// Which form the patch compliances of a solved model took.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompliancePath {
    /// Every patch dense.
    #[default]
    Dense,
    /// Every patch the FFT operator.
    Fft,
    /// Some of each.
    Mixed,
}

impl CompliancePath {
    /// The path of a model whose patches are `fft` (true: the FFT operator).
    pub fn of(mut fft: impl Iterator<Item = bool> + Clone) -> Self {
        match (fft.clone().any(|f| f), fft.all(|f| f)) {
            (false, _) => CompliancePath::Dense,
            (true, true) => CompliancePath::Fft,
            (true, false) => CompliancePath::Mixed,
        }
    }
}

impl std::fmt::Display for CompliancePath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CompliancePath::Dense => "dense",
            CompliancePath::Fft => "FFT",
            CompliancePath::Mixed => "dense and FFT",
        })
    }
}

/// Most unknowns of an FFT patch whose matrix is written out when a solver needs entries
/// ([`PatchCompliance::matrix`]): 3,072 (75 MB, and as many operator products); larger FFT
/// patches are solved by the native solver's Newton iteration alone.
pub const MATERIALISED_UNKNOWNS: usize = 3 * 1024;

/// One finger's patch compliance, shared (never copied) by the model, its restrictions and
/// the solvers. With a mount behind the finger ([`FingerMount`]) it is the patch's plus the
/// core's retreat `B' S B`: added into the dense matrix, applied beside the FFT operator.
#[derive(Debug, Clone)]
pub enum PatchCompliance {
    /// Column-major `n x n`, `n = (1 + n_tangential) N`.
    Dense(Arc<DMatrix<f64>>),
    /// The FFT operator, and the finger's mount when it has one.
    Fft {
        /// The patch's operator.
        op: Arc<ComplianceOperator>,
        /// The mount whose `B' S B` is added to every product.
        mount: Option<Arc<FingerMount>>,
    },
}

/// The shape of one finger's patch compliance: its grid, its tangential unknowns per element and
/// its form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplianceForm {
    /// The patch's grid.
    pub grid: GridSpec,
    /// Tangential unknowns per element: 0 (frictionless), 1 (planar) or 2.
    pub n_tangential: usize,
    /// True for the FFT operator, false for the dense matrix.
    pub fft: bool,
}

impl PatchCompliance {
    /// The compliance of `grid` for the contact's bodies `pair` with `n_tangential`
    /// tangential components, in the form `choice` gives (model.md, patch compliance; Johnson
    /// 3.22c, 3.86a-c, and [`super::elastic_layer`] for a layered body).
    pub fn build(
        grid: &GridSpec,
        pair: &ContactPair,
        n_tangential: usize,
        fft: bool,
    ) -> Result<Self, OutOfMemory> {
        let table = pair.kernel_table(grid)?;
        Self::from_table(&table, n_tangential, fft)
    }

    /// The compliance of the offsets' entries `table` with `n_tangential` tangential
    /// components: the FFT operator when `fft`, else the dense matrix; [`OutOfMemory`] when
    /// the operator's spectra cannot be allocated (a dense matrix is bounded by validation).
    pub fn from_table(
        table: &KernelTable,
        n_tangential: usize,
        fft: bool,
    ) -> Result<Self, OutOfMemory> {
        Ok(match fft {
            true => PatchCompliance::Fft {
                op: Arc::new(ComplianceOperator::new(table, n_tangential)?),
                mount: None,
            },
            false => PatchCompliance::Dense(Arc::new(patch_compliance(table, n_tangential))),
        })
    }

    /// The compliance with `mount`'s retreat `B' S B` added (the springs in series of
    /// [`FingerMount`]): a new dense matrix, or the operator with the mount beside it.
    pub fn with_mount(self, mount: &Arc<FingerMount>) -> Self {
        match self {
            PatchCompliance::Dense(c) => {
                let mut c = Arc::unwrap_or_clone(c);
                mount.add_to_matrix(&mut c);
                PatchCompliance::Dense(Arc::new(c))
            }
            PatchCompliance::Fft { op, .. } => PatchCompliance::Fft {
                op,
                mount: Some(Arc::clone(mount)),
            },
        }
    }

    /// Frees the FFT operator's work buffers ([`ComplianceOperator::release_work`]).
    pub fn release_work(&self) {
        if let PatchCompliance::Fft { op, .. } = self {
            op.release_work();
        }
    }

    /// True for the FFT operator.
    pub fn is_fft(&self) -> bool {
        matches!(self, PatchCompliance::Fft { .. })
    }

    /// The matrix: the stored one, or the operator's written out column by column (one
    /// product each) when it has at most [`MATERIALISED_UNKNOWNS`] unknowns, for the solvers
    /// that need entries (Clarabel, the interior-point method); `None` above.
    pub fn matrix(&self) -> Option<Arc<DMatrix<f64>>> {
        match self {
            PatchCompliance::Dense(c) => Some(Arc::clone(c)),
            PatchCompliance::Fft { op, mount } if op.len() <= MATERIALISED_UNKNOWNS => {
                Some(match mount {
                    None => op.matrix(),
                    Some(m) => {
                        let mut c = (*op.matrix()).clone();
                        m.add_to_matrix(&mut c);
                        Arc::new(c)
                    }
                })
            }
            PatchCompliance::Fft { .. } => None,
        }
    }

    /// `out = C v` (m/N times N: metres).
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        match self {
            PatchCompliance::Dense(c) => {
                out.copy_from_slice((&**c * nalgebra::DVector::from_column_slice(v)).as_slice())
            }
            PatchCompliance::Fft { op, mount } => {
                op.apply(v, out);
                if let Some(m) = mount {
                    m.add_product(v, 1.0, out);
                }
            }
        }
    }

    /// The largest diagonal entry, m/N.
    pub fn max_diagonal(&self) -> f64 {
        match self {
            PatchCompliance::Dense(c) => c.diagonal().iter().copied().fold(0.0, f64::max),
            PatchCompliance::Fft { op, mount } => (0..op.len())
                .step_by(op.elements().max(1))
                .map(|j| {
                    let mut d = op.diagonal(j / op.elements().max(1));
                    if let Some(m) = mount {
                        d += (j..j + op.elements())
                            .map(|i| m.diagonal(i))
                            .fold(0.0, f64::max);
                    }
                    d
                })
                .fold(0.0, f64::max),
        }
    }

    /// An upper bound of the largest absolute row sum `||C||_inf`, m/N (exact for the dense
    /// matrix; for the operator the sum of every kernel's absolute values over all offsets,
    /// which bounds every row's sum): Gershgorin's bound on the largest eigenvalue.
    pub fn row_sum_bound(&self) -> f64 {
        match self {
            // C is symmetric: column sums are row sums.
            PatchCompliance::Dense(c) => c
                .as_slice()
                .chunks_exact(c.nrows().max(1))
                .map(|col| col.iter().map(|v| v.abs()).sum::<f64>())
                .fold(0.0_f64, f64::max),
            PatchCompliance::Fft { op, mount } => {
                op.row_sum_bound() + mount.as_ref().map_or(0.0, |m| m.row_sum_bound())
            }
        }
    }
}
