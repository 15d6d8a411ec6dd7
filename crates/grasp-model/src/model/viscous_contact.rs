//! The viscoelastic bodies of one contact: each body's own compliance (at its instantaneous
//! modulus) and creep function, and the pair's compliance over a time step.
//!
//! The pair's compliance is the sum over its two bodies (model.md); a viscoelastic body's
//! compliance over a step of `dt` is its elastic one times the step factor `alpha(dt)` of its
//! creep function ([`super::viscoelasticity`]: Lee and Radok's correspondence with a constant
//! Poisson's ratio). So the step's offsets' entries are the pair's plus `(alpha_b - 1)` times
//! each viscoelastic body's own, and the history displacement is `C_b h_b` with the body's own
//! compliance `C_b`.

use std::sync::Arc;

use super::contact_pair::ContactPair;
use super::influence::KernelTable;
use super::layer_kernels::Side;
use super::patch_compliance::{ComplianceForm, PatchCompliance};
use super::viscoelasticity::{CreepFunction, RelaxationLaw};
use crate::error::OutOfMemory;
use crate::scene::scene_format::RelaxationSpec;

/// One viscoelastic body of a contact.
#[derive(Debug, Clone)]
pub struct ViscousBody {
    /// Its creep function, normalised by its instantaneous modulus.
    pub creep: CreepFunction,
    /// Its own compliance at its instantaneous modulus (m/N, the finger's unknown layout).
    pub compliance_m_per_n: PatchCompliance,
    /// Its own offsets' entries (for the step's compliance).
    table: Arc<KernelTable>,
}

/// The relaxation laws of a contact's two bodies, as written (`None`: an elastic body).
#[derive(Debug, Clone, Copy, Default)]
pub struct BodyLaws<'a> {
    /// The fingertip's law.
    pub finger: Option<&'a RelaxationSpec>,
    /// The object's law.
    pub object: Option<&'a RelaxationSpec>,
}

impl BodyLaws<'_> {
    /// True when neither body relaxes.
    pub fn are_elastic(&self) -> bool {
        self.finger.is_none() && self.object.is_none()
    }
}

/// The viscoelastic bodies of one contact, with the pair's offsets' entries.
#[derive(Debug, Clone)]
pub struct ViscousContact {
    /// The bodies that relax (one or two).
    pub bodies: Vec<ViscousBody>,
    /// The pair's offsets' entries at the instantaneous moduli.
    pair_table: Arc<KernelTable>,
    n_tangential: usize,
    fft: bool,
}

impl ViscousContact {
    /// The viscoelastic bodies of `pair` (`None` when neither relaxes): `laws` are the bodies'
    /// relaxation laws as written, `pair_table` the pair's entries, `form` the grid and form of
    /// the pair's compliance (the bodies' take the same).
    pub fn new(
        pair: &ContactPair,
        pair_table: &Arc<KernelTable>,
        form: ComplianceForm,
        laws: BodyLaws,
    ) -> Result<Option<Self>, OutOfMemory> {
        let ComplianceForm {
            grid,
            n_tangential,
            fft,
        } = form;
        let BodyLaws { finger, object } = laws;
        let modulus = |m: &super::material::Material| match *m {
            super::material::Material::Elastic {
                youngs_modulus_pa, ..
            } => Some(youngs_modulus_pa),
            super::material::Material::Rigid => None,
        };
        let mut bodies = Vec::new();
        for (spec, side, material) in [
            (finger, Side::Finger, &pair.finger_material),
            (object, Side::Object, &pair.object_material),
        ] {
            let Some(law) = spec
                .zip(modulus(material))
                .and_then(|(s, e0)| RelaxationLaw::of(s, e0))
            else {
                continue;
            };
            let table = pair.body_table(&grid, side)?;
            bodies.push(ViscousBody {
                creep: law.creep(),
                compliance_m_per_n: PatchCompliance::from_table(&table, n_tangential, fft)?,
                table: Arc::new(table),
            });
        }
        Ok((!bodies.is_empty()).then(|| ViscousContact {
            bodies,
            pair_table: Arc::clone(pair_table),
            n_tangential,
            fft,
        }))
    }

    /// The pair's compliance over a step of `dt_s` seconds (`f64::INFINITY`: fully relaxed):
    /// the pair's entries plus `(alpha_b(dt) - 1)` times each viscoelastic body's.
    pub fn step_compliance(&self, dt_s: f64) -> Result<PatchCompliance, OutOfMemory> {
        let mut table = (*self.pair_table).clone();
        for b in &self.bodies {
            table.add_scaled(b.creep.step(dt_s).alpha - 1.0, &b.table);
        }
        PatchCompliance::from_table(&table, self.n_tangential, self.fft)
    }
}
