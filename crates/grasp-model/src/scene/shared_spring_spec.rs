//! Springs that several fingers share, as written: `hands` (a base that carries its fingers'
//! cores rigidly, on the stiffness of the arm or wrist behind it) and `servos` (one drive that
//! moves its jaws equal and opposite, each along its own normal: a parallel-jaw gripper's two
//! jaws, a self-centring chuck's three).
//!
//! A hand's stiffness is given in the world frame about its `origin_m` (the wrist or tool
//! centre point), translations (m) then rotations (rad): by direction (`translational_n_per_m`,
//! `rotational_nm_per_rad`, each alike about every axis; one left out is rigid) or as a full
//! symmetric positive definite 6x6 `matrix`. A servo's stiffness is the one number that relates
//! the sum of its jaws' normal forces to the travel they share (`k` of
//! `F_1 + F_2 = k (x_commanded - x)`); its jaws' commanded positions are their own controls
//! (`approach_m` or `held`).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::scene::mount_spec::MountStiffness;

/// `hands[j]`: fingers on one base with its own stiffness to the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HandSpec {
    /// Unique name (among hands and servos), used in every report.
    pub name: String,
    /// The fingers the base carries (names from `fingers`; a finger is on at most one hand).
    pub fingers: Vec<String>,
    /// The point the stiffness acts about, and the hand's displacement is reported at (the
    /// wrist or tool centre point), m (world frame), each coordinate in `[-1e3, 1e3]`.
    pub origin_m: [f64; 3],
    /// Stiffness along each world axis alike, N/m, in `[1e-6, 1e15]`; omitted: rigid in
    /// translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translational_n_per_m: Option<f64>,
    /// Stiffness against rotation about each world axis alike through `origin_m`, N m/rad, in
    /// `[1e-9, 1e12]`; omitted: rigid in rotation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotational_nm_per_rad: Option<f64>,
    /// The full symmetric positive definite stiffness in the world frame about `origin_m`,
    /// rows and columns `[x, y, z, rot x, rot y, rot z]` (N/m, N/rad, N m/rad), instead of the
    /// two numbers above (an arm's Cartesian stiffness).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[[f64; 6]; 6]>,
}

impl HandSpec {
    /// The stiffness as a matrix (`[x, y, z, rot x, rot y, rot z]`, world frame about the
    /// origin), with the rigid directions of the per-direction form marked.
    pub fn stiffness(&self) -> MountStiffness {
        if let Some(m) = self.matrix {
            return MountStiffness {
                matrix: m,
                compliant: [true; 6],
            };
        }
        let (t, r) = (self.translational_n_per_m, self.rotational_nm_per_rad);
        let mut matrix = [[0.0; 6]; 6];
        let mut compliant = [false; 6];
        for (c, k) in [t, t, t, r, r, r].iter().enumerate() {
            if let Some(k) = k {
                matrix[c][c] = *k;
                compliant[c] = true;
            }
        }
        MountStiffness { matrix, compliant }
    }
}

/// `servos[j]`: one drive moving its jaws equal and opposite.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ServoSpec {
    /// Unique name (among hands and servos), used in every report.
    pub name: String,
    /// Its jaws (names from `fingers`, at least two; each position-controlled, `approach_m`
    /// or `held`, and on at most one servo).
    pub fingers: Vec<String>,
    /// `k` in `sum F_jaw = k (x_commanded - x)`, N/m, in `[1e-6, 1e15]`: for two jaws
    /// squeezing alike, each jaw feels `k / 2`.
    pub stiffness_n_per_m: f64,
}
