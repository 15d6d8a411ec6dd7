//! A model on grids twice as coarse: the model of a grid continuation's first solve
//! (`crate::solver::grid_continuation`). Each FFT patch of at least twice
//! [`MIN_COARSE_SIDE`] elements a side (both counts even, no mount) becomes a patch of the same
//! size with half the elements a side: a coarse element is a 2 x 2 block of fine ones, at their
//! mean centre, its gap their mean gap (as the coarse program's `q`,
//! [`crate::program::coarse_program`]: a block with a child off the surface is far apart; off
//! the surface itself when all four are), its compliance the coarse grid's own (the same
//! bodies, elements twice as wide). The other fingers, the object and the scales stay as they
//! are.

use crate::error::OutOfMemory;
use crate::model::grasp_model::{FingerModel, GraspModel};
use crate::model::influence::GridSpec;
use crate::model::patch::Patch;
use crate::model::patch_compliance::PatchCompliance;
use crate::scene::limits::MIN_COARSE_SIDE;

/// A model's coarse twin and which of its fingers were coarsened.
#[derive(Debug, Clone)]
pub(crate) struct CoarseModel {
    /// The coarse model (the fine model's scales).
    pub(crate) model: GraspModel,
    /// Per finger of the fine model, its grid `[nx, ny]`.
    pub(crate) fine_grids: Vec<[usize; 2]>,
    /// Per finger, true when its grid was coarsened.
    pub(crate) coarsened: Vec<bool>,
}

/// True when `finger`'s grid is coarsened: an FFT patch, elastic, without a mount (whose
/// retreat is written over the fine elements' centres), both counts even and at least
/// `2 MIN_COARSE_SIDE`.
fn coarsens(finger: &FingerModel) -> bool {
    let g = &finger.patch.grid;
    let side = |n: usize| n.is_multiple_of(2) && n >= 2 * MIN_COARSE_SIDE;
    let plain = finger.viscous.is_none() && finger.mount.is_none();
    finger.compliance_m_per_n.is_fft() && plain && side(g.nx) && side(g.ny)
}

impl GraspModel {
    /// The coarse twin of this model (module docs): `None` unless every finger's patch is an
    /// FFT one, none is viscoelastic and some finger's grid coarsens; `Err` when a coarse
    /// compliance cannot be allocated.
    pub(crate) fn coarsened(&self) -> Result<Option<CoarseModel>, OutOfMemory> {
        let all_fft = self.fingers.iter().all(|f| f.compliance_m_per_n.is_fft());
        let coarsened: Vec<bool> = self.fingers.iter().map(coarsens).collect();
        if !all_fft || self.is_viscoelastic() || !coarsened.iter().any(|&c| c) {
            return Ok(None);
        }
        let fingers = self
            .fingers
            .iter()
            .zip(&coarsened)
            .map(|(f, &c)| match c {
                true => coarse_finger(f),
                false => Ok(f.clone()),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut model = GraspModel::from_parts(fingers, self.object.clone());
        model.scales = self.scales;
        Ok(Some(CoarseModel {
            model,
            fine_grids: self
                .fingers
                .iter()
                .map(|f| [f.patch.grid.nx, f.patch.grid.ny])
                .collect(),
            coarsened,
        }))
    }
}

/// `finger` on its coarse grid.
fn coarse_finger(finger: &FingerModel) -> Result<FingerModel, OutOfMemory> {
    let patch = coarse_patch(&finger.patch);
    let compliance =
        PatchCompliance::build(&patch.grid, &finger.contact, finger.n_tangential, true)?;
    Ok(FingerModel {
        patch,
        compliance_m_per_n: compliance,
        ..finger.clone()
    })
}

/// `fine` with 2 x 2 blocks of elements merged (module docs).
fn coarse_patch(fine: &Patch) -> Patch {
    let g = &fine.grid;
    let (nx, ny) = (g.nx / 2, g.ny / 2);
    let grid = GridSpec {
        nx,
        ny,
        hx: 2.0 * g.hx,
        hy: 2.0 * g.hy,
    };
    let mut centres_m = Vec::with_capacity(nx * ny);
    let mut gap_m = Vec::with_capacity(nx * ny);
    let mut off_surface = Vec::with_capacity(nx * ny);
    let mut off_object = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            let children = [0, 1, 2, 3].map(|c| (2 * i + c / 2) * g.ny + 2 * j + c % 2);
            let on: Vec<usize> = children
                .iter()
                .copied()
                .filter(|&k| !fine.is_off_surface(k))
                .collect();
            let mean = |v: &dyn Fn(usize) -> f64| children.iter().map(|&k| v(k)).sum::<f64>() / 4.0;
            centres_m.push([
                mean(&|k| fine.centres_m[k][0]),
                mean(&|k| fine.centres_m[k][1]),
            ]);
            gap_m.push(mean(&|k| fine.gap_m[k]));
            off_surface.push(on.is_empty());
            off_object.push(
                children
                    .iter()
                    .all(|&k| fine.off_object.get(k) == Some(&true)),
            );
        }
    }
    let any = |v: Vec<bool>| if v.iter().any(|&o| o) { v } else { Vec::new() };
    Patch {
        grid,
        centres_m,
        gap_m,
        off_surface: any(off_surface),
        off_object: any(off_object),
        curved: fine.curved,
        curvature_per_m: fine.curvature_per_m,
        textured: fine.textured,
    }
}
