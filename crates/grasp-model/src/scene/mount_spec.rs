//! `fingers[i].mount` as written: the stiffness behind a finger's rigid core, a spring from the
//! core to its commanded pose (a servo's position, a finger link, a drive), and the preload it
//! pushes with at that pose.
//!
//! The stiffness is given in the contact frame, components in the order `t1, t2, n` for the
//! translations (m) and the rotations about `t1, t2, n` (rad) about the contact point: either
//! by direction (`normal_n_per_m`, `tangential_n_per_m`, `rotational_nm_per_rad`; a direction
//! left out is rigid) or as a full symmetric positive definite `matrix` (N/m, N/rad, N m/rad),
//! or by its `compliance`, the inverse of such a matrix, which may be singular: a core that
//! moves along fewer than six directions, rigid across them (a jaw on one hinge: `J J' / K_q`
//! with `J` the contact's motion per radian of the joint and `K_q` its stiffness, the
//! "compliant form" of `K = J^-T K_q J^-1`).
//! The commanded position along the normal is the finger's control: `{"approach_m": x}` is the
//! jaw's position from first touch (negative: opened), `"held"` is `x = 0`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// `fingers[i].mount`: the spring between the finger's rigid core and its commanded pose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MountSpec {
    /// Stiffness along the normal, N/m, in `[1e-6, 1e15]`; omitted: rigid along the normal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_n_per_m: Option<f64>,
    /// Stiffness along each tangent (`t1` and `t2` alike), N/m, in `[1e-6, 1e15]`; omitted:
    /// rigid tangentially.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential_n_per_m: Option<f64>,
    /// Stiffness against rotation about each axis (`t1`, `t2`, `n` alike) through the contact
    /// point, N m/rad, in `[1e-9, 1e12]`; omitted: rigid in rotation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotational_nm_per_rad: Option<f64>,
    /// The full symmetric positive definite stiffness, rows and columns `[t1, t2, n, rot t1,
    /// rot t2, rot n]` (N/m between translations, N/rad between a translation and a rotation,
    /// N m/rad between rotations), instead of the three numbers above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[[f64; 6]; 6]>,
    /// The full symmetric positive semidefinite compliance, rows and columns `[t1, t2, n, rot
    /// t1, rot t2, rot n]` (m/N between translations, 1/N between a translation and a rotation,
    /// rad/(N m) between rotations), instead of a stiffness: singular where the core is rigid
    /// (a jaw on one hinge: `J J' / K_q`, `J` the contact's motion and the pad's turn per
    /// radian, `K_q` the joint's stiffness, N m/rad). Entries at most 1e6.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compliance: Option<[[f64; 6]; 6]>,
    /// The normal force the spring pushes with when the core sits at its commanded pose, N: 0
    /// or in `[1e-15, 1e7]`; default 0. Needs a normal stiffness (or a compliance that moves
    /// the core along the normal); not for a force-controlled finger (its normal load is
    /// prescribed).
    #[serde(default)]
    pub preload_n: f64,
}

impl MountSpec {
    /// The stiffness as a matrix in the contact frame (`[t1, t2, n, rot t1, rot t2, rot n]`),
    /// with `None` for a rigid direction of the per-direction form (its row and column are
    /// then absent: the core does not move that way).
    pub fn stiffness(&self) -> MountStiffness {
        if let Some(m) = self.matrix {
            return MountStiffness {
                matrix: m,
                compliant: [true; 6],
            };
        }
        let t = self.tangential_n_per_m;
        let r = self.rotational_nm_per_rad;
        let diagonal = [t, t, self.normal_n_per_m, r, r, r];
        let mut matrix = [[0.0; 6]; 6];
        let mut compliant = [false; 6];
        for (c, k) in diagonal.iter().enumerate() {
            if let Some(k) = k {
                matrix[c][c] = *k;
                compliant[c] = true;
            }
        }
        MountStiffness { matrix, compliant }
    }
}

/// A mount's stiffness in the contact frame, as [`MountSpec::stiffness`] reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountStiffness {
    /// The stiffness, `[t1, t2, n, rot t1, rot t2, rot n]` (N/m, N/rad, N m/rad).
    pub matrix: [[f64; 6]; 6],
    /// Per component, true when the core moves that way (false: rigid; its row and column of
    /// `matrix` are ignored).
    pub compliant: [bool; 6],
}
