//! Exact initial gaps from the real surfaces: at each element centre, the distance along the
//! contact normal between the fingertip's surface and the object's (model.md, "Facts for gaps
//! from real surfaces"; Johnson 5.1: the half-space compliance stays, only the gap changes).
//!
//! - The object's surface is found by a ray from above the element's point of the contact's
//!   tangent plane along the inward normal ([`crate::geometry::shape::Shape::ray_hit`]): its
//!   depth below the plane, measured from the depth at the contact point itself.
//! - The fingertip's is its exact profile above the plane: a sphere `R - sqrt(R^2 - r^2)`
//!   (Sneddon 1965), a cylinder across its axis, a flat pad rounded along a quarter circle of
//!   its edge radius (Ciavarella, Hills and Monno 1998; a disc pad: Ciavarella 1999).
//! - An element that meets no object surface (beyond an edge, off a mesh, past a thin part's
//!   silhouette) or lies beyond the tip's surface (past a pad's rim) can carry nothing: it is
//!   off the surface, given a gap no approach closes.

use rayon::prelude::*;

use crate::geometry::contact_frame::ContactFrame;
use crate::geometry::shape::Shape;
use crate::scene::scene_format::FingerSpec;
use crate::scene::scene_geometry::SharedShape;
use crate::scene::shape_spec::TipSpec;

/// Elements per patch from which the object's ray casts run on all cores.
const PARALLEL_RAYS: usize = 4_096;

/// An off-surface element's gap, in patch diagonals: far beyond any approach the small-strain
/// model admits (an approach is a fraction of the contact size), so it never closes, and
/// finite, so the program's data stay finite.
const OFF_SURFACE_GAP_DIAGONALS: f64 = 10.0;

/// The fingertip's exact surface near the contact, in the contact frame.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum TipProfile {
    /// A flat tip with no edge (the scene gives none): height 0 everywhere.
    Unbounded,
    /// A sphere of radius `r`, m.
    Sphere { radius_m: f64 },
    /// A cylinder of radius `r`, m, its axis along `t1` (`along_t1`) or `t2`.
    Cylinder { radius_m: f64, along_t1: bool },
    /// A rectangular pad: the flat part's half sides, m, and the edges' radius, m.
    Pad { flat_half_m: [f64; 2], edge_m: f64 },
    /// A disc pad: the flat part's radius, m, and the rim's radius, m.
    Disc { flat_radius_m: f64, edge_m: f64 },
    /// A solid posed in the world (`tip.shape`, a mesh say), met by rays cast from the
    /// object's side of the tangent plane.
    Solid(SharedShape),
}

impl TipProfile {
    /// The profile of finger `f` (frame `frame`: a cylinder's axis along `t1` or `t2`); `solid`
    /// its posed `tip.shape`, when it has one.
    pub(crate) fn of(f: &FingerSpec, frame: &ContactFrame, solid: Option<&SharedShape>) -> Self {
        if let Some(s) = solid {
            return TipProfile::Solid(s.clone());
        }
        if let Some(r) = f.tip_radius {
            return TipProfile::Sphere { radius_m: r };
        }
        let Some(tip) = &f.tip else {
            return TipProfile::Unbounded;
        };
        Self::of_tip(tip, frame)
    }

    fn of_tip(tip: &TipSpec, frame: &ContactFrame) -> TipProfile {
        if let Some(s) = &tip.sphere {
            return TipProfile::Sphere { radius_m: s.radius };
        }
        if let Some(c) = &tip.cylinder {
            let a = nalgebra::Vector3::from(c.axis).normalize();
            let along_t1 = a.dot(&frame.t1).abs() >= a.dot(&frame.t2).abs();
            return TipProfile::Cylinder {
                radius_m: c.radius,
                along_t1,
            };
        }
        if let Some(p) = &tip.flat {
            let half = |k: usize| 0.5 * p.size[k] - p.edge_radius;
            return TipProfile::Pad {
                flat_half_m: [half(0), half(1)],
                edge_m: p.edge_radius,
            };
        }
        match &tip.disc {
            Some(d) => TipProfile::Disc {
                flat_radius_m: 0.5 * d.diameter - d.edge_radius,
                edge_m: d.edge_radius,
            },
            None => TipProfile::Unbounded,
        }
    }

    /// The tip's height above the tangent plane at `(x, y)` (m, along `t1`, `t2`), away from
    /// the object; `None` beyond its surface. A solid tip's is found by a ray from `reach_m`
    /// below the plane, on the object's side (`Err` when the tip crosses the plane deeper),
    /// measured from its height at the contact point.
    fn surface_height_m(
        &self,
        frame: &ContactFrame,
        [x, y]: [f64; 2],
        reach_m: f64,
    ) -> Result<Option<f64>, String> {
        let TipProfile::Solid(solid) = self else {
            return Ok(self.height_m(x, y));
        };
        let tip_side = ContactFrame {
            normal: -frame.normal,
            ..*frame
        };
        let at = |c: [f64; 2]| surface_depth_m(&solid.0, &tip_side, c, reach_m, "fingertip's");
        let centre = at([0.0, 0.0])?.ok_or_else(|| {
            "the fingertip's surface does not pass over the contact point".to_string()
        })?;
        Ok(at([x, y])?.map(|h| h - centre))
    }

    /// The height of an analytic tip (see [`Self::surface_height_m`]); a solid's is found by
    /// rays.
    pub(crate) fn height_m(&self, x: f64, y: f64) -> Option<f64> {
        match *self {
            TipProfile::Solid(_) => None,
            TipProfile::Unbounded => Some(0.0),
            TipProfile::Sphere { radius_m } => circle_height(radius_m, x.hypot(y)),
            TipProfile::Cylinder { radius_m, along_t1 } => {
                circle_height(radius_m, if along_t1 { y } else { x })
            }
            TipProfile::Pad {
                flat_half_m,
                edge_m,
            } => {
                let dx = (x.abs() - flat_half_m[0]).max(0.0);
                let dy = (y.abs() - flat_half_m[1]).max(0.0);
                rim_height(edge_m, dx.hypot(dy))
            }
            TipProfile::Disc {
                flat_radius_m,
                edge_m,
            } => rim_height(edge_m, (x.hypot(y) - flat_radius_m).max(0.0)),
        }
    }
}

/// Height of a circle of radius `r` at distance `d` from its lowest point's axis:
/// `r - sqrt(r^2 - d^2)`, written as `d^2 / (r + sqrt(r^2 - d^2))` (no cancellation near the
/// axis); `None` beyond the circle.
fn circle_height(r: f64, d: f64) -> Option<f64> {
    let s = r * r - d * d;
    (s >= 0.0).then(|| d * d / (r + s.sqrt()))
}

/// Height of a rounded rim of radius `r` at distance `d` beyond the flat part (0 on the flat);
/// `None` beyond the rim (`d > r`; a sharp rim, `r = 0`, ends at the flat's edge).
fn rim_height(r: f64, d: f64) -> Option<f64> {
    if d == 0.0 {
        Some(0.0)
    } else {
        circle_height(r, d)
    }
}

/// The exact gaps of a patch.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ExactGaps {
    /// Smooth gap per element, m (off-surface elements: a gap no approach closes).
    pub gap_m: Vec<f64>,
    /// Per element, true when it faces no surface of the object or of the tip.
    pub off_surface: Vec<bool>,
    /// Per element, true when it lies past the object's edge (its ray meets no object surface).
    pub off_object: Vec<bool>,
    /// How far the fingertip's first touch lies below the contact point's gap, m (positive:
    /// the surfaces meet elsewhere first, and the gaps were shifted to start from there).
    pub first_touch_shift_m: f64,
}

/// The exact gaps at `centres_m` (patch coordinates, m) of a finger with tip `tip` at frame
/// `frame` on `shape`; `reach_m` is the height above the tangent plane the rays start from
/// (at least the patch's half diagonal). `Err` says why the object has no surface under the
/// contact point or rises through the tangent plane above the reach.
pub(crate) fn exact_gaps(
    shape: &Shape,
    frame: &ContactFrame,
    tip: &TipProfile,
    centres_m: &[[f64; 2]],
    reach_m: f64,
) -> Result<ExactGaps, String> {
    let depth_at_contact = object_depth_m(shape, frame, [0.0, 0.0], reach_m)?.ok_or_else(|| {
        "no surface of the object lies under the contact point along the normal".to_string()
    })?;
    let one = |c: &[f64; 2]| -> Result<(Option<f64>, bool), String> {
        let depth = object_depth_m(shape, frame, *c, reach_m)?;
        let tip = tip.surface_height_m(frame, *c, reach_m)?;
        let gap = depth.zip(tip).map(|(d, h)| d - depth_at_contact + h);
        Ok((gap, depth.is_none()))
    };
    let found: Vec<(Option<f64>, bool)> = if centres_m.len() >= PARALLEL_RAYS {
        centres_m.par_iter().map(one).collect::<Result<_, _>>()?
    } else {
        centres_m.iter().map(one).collect::<Result<_, _>>()?
    };
    let (gaps, off_object): (Vec<Option<f64>>, Vec<bool>) = found.into_iter().unzip();
    Ok(settle(gaps, off_object, reach_m))
}

/// Off-surface elements get a gap no approach closes; if the surfaces meet first away from
/// the contact point (a gap below zero), every gap is shifted to start from there.
fn settle(gaps: Vec<Option<f64>>, off_object: Vec<bool>, reach_m: f64) -> ExactGaps {
    let lowest = gaps.iter().flatten().fold(f64::INFINITY, |m, g| m.min(*g));
    let shift = if lowest < 0.0 { -lowest } else { 0.0 };
    let highest = gaps.iter().flatten().fold(0.0_f64, |m, g| m.max(*g)) + shift;
    let off_gap = OFF_SURFACE_GAP_DIAGONALS * (2.0 * reach_m).max(highest);
    ExactGaps {
        off_surface: gaps.iter().map(Option::is_none).collect(),
        off_object,
        gap_m: gaps
            .iter()
            .map(|g| g.map_or(off_gap, |g| g + shift))
            .collect(),
        first_touch_shift_m: shift,
    }
}

/// Depth (m) of the object's surface below the tangent plane at `(x, y)`, along the inward
/// normal, found by a ray from `reach_m` above the plane; `None` when the ray meets no surface
/// facing it. A ray that slips between a closed mesh's triangles is cast again beside itself
/// by [`Shape::ray_hit`]; on an open mesh a hit on a face turned away (the far side of the
/// sheet) counts as no surface here.
fn object_depth_m(
    shape: &Shape,
    frame: &ContactFrame,
    at: [f64; 2],
    reach_m: f64,
) -> Result<Option<f64>, String> {
    surface_depth_m(shape, frame, at, reach_m, "object's")
}

/// [`object_depth_m`] for any surface: `whose` names it in the error.
fn surface_depth_m(
    shape: &Shape,
    frame: &ContactFrame,
    [x, y]: [f64; 2],
    reach_m: f64,
    whose: &str,
) -> Result<Option<f64>, String> {
    let origin = frame.point(x, y) - frame.normal * reach_m;
    match shape.ray_hit(&origin, &frame.normal) {
        Ok(hit) => Ok(hit
            .filter(|s| s.outward_normal.dot(&frame.normal) < 0.0)
            .map(|s| (s.point_m - origin).dot(&frame.normal) - reach_m)),
        Err(_) => Err(format!(
            "the {whose} surface crosses the contact's tangent plane by more than {:.3e} m at \
             ({:.3e}, {:.3e}) m of the patch: the two bodies would meet there before the \
             contact point",
            reach_m, x, y
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The circle's height in its stable form equals `r - sqrt(r^2 - d^2)` and ends at `r`.
    #[test]
    fn circle_heights_are_the_circle() {
        for d in [0.0, 1e-6, 0.3, 0.99, 1.0] {
            let h = circle_height(1.0, d).unwrap();
            assert!((h - (1.0 - (1.0 - d * d).sqrt())).abs() <= 1e-15, "{d}");
        }
        assert_eq!(circle_height(1.0, 1.0 + 1e-12), None);
    }

    /// A pad is flat on its flat part, rises along the rim's quarter circle, ends at the rim.
    #[test]
    fn a_rounded_pad_is_flat_then_round_then_gone() {
        let pad = TipProfile::Pad {
            flat_half_m: [2e-3, 5e-3],
            edge_m: 1e-3,
        };
        assert_eq!(pad.height_m(1.9e-3, -4.9e-3), Some(0.0));
        let h = pad.height_m(2.5e-3, 0.0).unwrap();
        assert!((h - (1e-3 - (1e-6f64 - 0.25e-6).sqrt())).abs() <= 1e-18);
        assert_eq!(pad.height_m(3.01e-3, 0.0), None);
        let sharp = TipProfile::Pad {
            flat_half_m: [2e-3, 2e-3],
            edge_m: 0.0,
        };
        assert_eq!(sharp.height_m(2e-3, 2e-3), Some(0.0));
        assert_eq!(sharp.height_m(2.0001e-3, 0.0), None);
    }
}
