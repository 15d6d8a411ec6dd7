//! Directions of disturbance: unit vectors of the scaled wrench space
//! ([`WrenchDirection`]), the axis directions, directions spread around the coordinate planes
//! (a polar plot's) and quasi-uniformly over the sphere.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::model::equilibrium::MotionPlane;
use crate::model::grasp_model::GraspModel;

/// A random direction sample shorter than this (a near-zero Gaussian vector) is drawn again
/// rather than normalised.
const MIN_SAMPLE_NORM: f64 = 1e-9;

/// A direction of disturbance: a unit vector of the scaled wrench space.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WrenchDirection {
    /// Force part (world frame, dimensionless).
    pub force: [f64; 3],
    /// Torque part (world frame, dimensionless; times `s L` gives N m).
    pub torque: [f64; 3],
}

impl WrenchDirection {
    /// The direction of a wrench `force_n` (N) plus `torque_nm` (N m) at length `length_m`:
    /// `(f, t / L)` normalised; `None` for a zero or non-finite wrench.
    pub fn of_wrench(force_n: [f64; 3], torque_nm: [f64; 3], length_m: f64) -> Option<Self> {
        let t = torque_nm.map(|v| v / length_m);
        let norm = force_n.iter().chain(&t).map(|v| v * v).sum::<f64>().sqrt();
        (norm.is_finite() && norm > 0.0).then(|| WrenchDirection {
            force: force_n.map(|v| v / norm),
            torque: t.map(|v| v / norm),
        })
    }
}

/// The 12 axis directions in 3-D (force `+-x, +-y, +-z`, then torque), the 6 in-plane ones of
/// a planar scene (force `+-e1, +-e2`, torque `+-p`).
pub fn axis_directions(model: &GraspModel) -> Vec<WrenchDirection> {
    let axes: Vec<Vector3<f64>> = match model.plane() {
        None => vec![Vector3::x(), Vector3::y(), Vector3::z()],
        Some(p) => vec![p.e1, p.e2],
    };
    let torques: Vec<Vector3<f64>> = match model.plane() {
        None => vec![Vector3::x(), Vector3::y(), Vector3::z()],
        Some(p) => vec![p.normal],
    };
    let arr = |v: Vector3<f64>| [v.x, v.y, v.z];
    let mut out = Vec::new();
    for a in axes {
        for sign in [1.0, -1.0] {
            out.push(WrenchDirection {
                force: arr(a * sign),
                torque: [0.0; 3],
            });
        }
    }
    for a in torques {
        for sign in [1.0, -1.0] {
            out.push(WrenchDirection {
                force: [0.0; 3],
                torque: arr(a * sign),
            });
        }
    }
    out
}

/// Force directions spread evenly around each coordinate plane, `per_plane` per plane (3-D: the
/// `xy`, `yz` and `zx` planes, the axes listed once; planar: the plane of motion), then the
/// couple axes (both signs): the directions a polar plot of the margins draws.
pub fn plane_directions(model: &GraspModel, per_plane: usize) -> Vec<WrenchDirection> {
    let planes: Vec<(Vector3<f64>, Vector3<f64>)> = match model.plane() {
        None => vec![
            (Vector3::x(), Vector3::y()),
            (Vector3::y(), Vector3::z()),
            (Vector3::z(), Vector3::x()),
        ],
        Some(p) => vec![(p.e1, p.e2)],
    };
    let mut out: Vec<WrenchDirection> = Vec::new();
    for (a, b) in planes {
        for k in 0..per_plane {
            let angle = std::f64::consts::TAU * k as f64 / per_plane as f64;
            let mut f = a * angle.cos() + b * angle.sin();
            f.iter_mut().for_each(|c| {
                if c.abs() < 1e-15 {
                    *c = 0.0;
                }
            });
            let d = WrenchDirection {
                force: [f.x, f.y, f.z],
                torque: [0.0; 3],
            };
            let same =
                |o: &WrenchDirection| (0..3).all(|c| (o.force[c] - d.force[c]).abs() < 1e-12);
            if !out.iter().any(same) {
                out.push(d);
            }
        }
    }
    let torques = axis_directions(model)
        .into_iter()
        .filter(|d| d.torque.iter().any(|c| *c != 0.0));
    out.extend(torques);
    out
}

/// `n` directions: the axis directions first, then combined ones spread quasi-uniformly over
/// the unit sphere of the scaled wrench space (3 dimensions planar, 6 in 3-D): the additive
/// recurrence of the generalised golden ratio (Roberts' `R_d` sequence) mapped to Gaussians by
/// Box-Muller and normalised. Deterministic.
pub fn spread_directions(model: &GraspModel, n: usize) -> Vec<WrenchDirection> {
    let mut out = axis_directions(model);
    if n <= out.len() {
        out.truncate(n);
        return out;
    }
    let basis: Vec<[f64; 6]> = match model.plane() {
        None => (0..6)
            .map(|i| {
                let mut b = [0.0; 6];
                b[i] = 1.0;
                b
            })
            .collect(),
        Some(MotionPlane { e1, e2, normal: p }) => vec![
            [e1.x, e1.y, e1.z, 0.0, 0.0, 0.0],
            [e2.x, e2.y, e2.z, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, p.x, p.y, p.z],
        ],
    };
    let dim = basis.len();
    // phi_d: the positive root of x^(d+1) = x + 1 (Roberts 2018).
    let mut phi: f64 = 2.0;
    for _ in 0..50 {
        phi = (1.0 + phi).powf(1.0 / (dim as f64 + 1.0));
    }
    let alpha: Vec<f64> = (1..=2 * dim)
        .map(|j| phi.powi(-(j as i32)).fract())
        .collect();
    let mut k = 1usize;
    while out.len() < n {
        let u: Vec<f64> = alpha.iter().map(|a| (0.5 + a * k as f64).fract()).collect();
        k += 1;
        let g: Vec<f64> = (0..dim)
            .map(|i| {
                let (u1, u2) = (u[2 * i].max(1e-12), u[2 * i + 1]);
                (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            })
            .collect();
        let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm < MIN_SAMPLE_NORM {
            continue;
        }
        let mut w = [0.0; 6];
        for (gi, b) in g.iter().zip(&basis) {
            for c in 0..6 {
                w[c] += gi / norm * b[c];
            }
        }
        out.push(WrenchDirection {
            force: [w[0], w[1], w[2]],
            torque: [w[3], w[4], w[5]],
        });
    }
    out
}
