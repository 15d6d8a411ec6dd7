//! Checks of the patches against the shape: a patch hanging over the edge of a flat face
//! (box faces, cylinder caps), past the end of a cylinder's side or over a sharp edge of a
//! mesh, and patches of two
//! fingers that overlap. Warnings, not errors: the solve still runs, the elements beyond an
//! edge are simply not on the object.

use nalgebra::Vector3;
use serde_json::Value;

use crate::geometry::contact_frame::ContactFrame;
use crate::geometry::mesh_surface::MeshSurface;
use crate::geometry::primitive_surface::Primitive;
use crate::geometry::shape::{LocalShape, Shape};

/// Overhangs and overlaps below this fraction of the patch's size are round-off of the
/// placement, not geometry.
const ROUND_OFF_FRACTION: f64 = 1e-9;

/// A finger's patch from its JSON: frame (world), half sides along `t1`, `t2` (m), name.
/// A finger's patch as written: its frame, its half sides along `t1`, `t2` (m) and the
/// finger's name.
struct WrittenPatch {
    frame: ContactFrame,
    half_m: [f64; 2],
    name: String,
}

fn patch_of(f: &Value) -> Option<WrittenPatch> {
    let v = |key: &str| -> Option<Vector3<f64>> {
        let a: [f64; 3] = serde_json::from_value(f.get(key)?.clone()).ok()?;
        a.iter().all(|x| x.is_finite()).then(|| Vector3::from(a))
    };
    let (c, n) = (v("contact_point")?, v("normal")?);
    if n.norm() == 0.0 {
        return None;
    }
    let size: [f64; 2] = serde_json::from_value(f.pointer("/patch/size")?.clone()).ok()?;
    let name = f.get("name")?.as_str()?.to_string();
    Some(WrittenPatch {
        frame: ContactFrame::new(c, n, v("tangent"), None),
        half_m: [size[0] / 2.0, size[1] / 2.0],
        name,
    })
}

/// The four corners of a patch, world.
fn corners(frame: &ContactFrame, half: [f64; 2]) -> [Vector3<f64>; 4] {
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(a, b)| frame.point(a * half[0], b * half[1]))
}

/// How far the patch of finger `f` reaches past the face it lies on, m (0 when inside), for
/// box faces, cylinder caps and cylinder sides, and the smooth regions of a mesh (bounded by
/// its sharp edges, [`mesh_overhang_m`]); `None` for other shapes.
fn overhang_m(frame: &ContactFrame, half: [f64; 2], shape: &Shape) -> Option<f64> {
    let local = |p: &Vector3<f64>| {
        shape
            .rotation
            .inverse_transform_vector(&(p - shape.position_m))
    };
    let prim = match &shape.local {
        LocalShape::Primitive(prim) => prim,
        LocalShape::Mesh(m) => {
            let axes = [frame.t1, frame.t2].map(|t| shape.rotation.inverse_transform_vector(&t));
            return Some(mesh_overhang_m(m, &local(&frame.origin_m), axes, half));
        }
    };
    let n = shape.rotation.inverse_transform_vector(&frame.normal);
    let cs = corners(frame, half).map(|c| local(&c));
    let worst = |f: &dyn Fn(&Vector3<f64>) -> f64| cs.iter().map(f).fold(0.0_f64, f64::max);
    match *prim {
        Primitive::Box { half_m } => {
            let k = (0..3).max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))?;
            Some(worst(&|c| {
                (0..3)
                    .filter(|&i| i != k)
                    .map(|i| c[i].abs() - half_m[i])
                    .fold(0.0, f64::max)
            }))
        }
        Primitive::Cylinder {
            radius_m,
            half_length_m,
        } => Some(if n.z.abs() > 0.9 {
            worst(&|c| c.xy().norm() - radius_m)
        } else {
            worst(&|c| c.z.abs() - half_length_m)
        }),
        _ => None,
    }
}

/// How far a patch centred on `c` (local frame of the mesh) with axes `[t1, t2]` and half
/// sides `half` reaches past the sharp edges bounding the smooth region it lies on, m: in the
/// patch's plane, each such edge that crosses the rectangle is a line, and the patch's
/// overhang is the largest distance of a corner beyond it (away from the centre). For a face
/// of a box this is the primitive box's overhang.
fn mesh_overhang_m(
    m: &MeshSurface,
    c: &Vector3<f64>,
    [t1, t2]: [Vector3<f64>; 2],
    half: [f64; 2],
) -> f64 {
    let reach = half[0].hypot(half[1]);
    let in_plane = |p: &Vector3<f64>| [(p - c).dot(&t1), (p - c).dot(&t2)];
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(a, b)| [a * half[0], b * half[1]]);
    let mut over: f64 = 0.0;
    for [a, b] in m.region_edges_near(c, reach) {
        let (a, b) = (in_plane(&a), in_plane(&b));
        if !segment_meets_rectangle(a, b, half) {
            continue;
        }
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = d[0].hypot(d[1]);
        if len == 0.0 {
            continue;
        }
        // Unit normal of the edge's line pointing away from the patch centre.
        let mut out = [d[1] / len, -d[0] / len];
        if out[0] * a[0] + out[1] * a[1] < 0.0 {
            out = [-out[0], -out[1]];
        }
        for k in &corners {
            over = over.max((k[0] - a[0]) * out[0] + (k[1] - a[1]) * out[1]);
        }
    }
    over
}

/// True when the segment `a b` (plane coordinates) meets the rectangle `|x| <= half[0]`,
/// `|y| <= half[1]` (Liang-Barsky clipping).
fn segment_meets_rectangle(a: [f64; 2], b: [f64; 2], half: [f64; 2]) -> bool {
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for i in 0..2 {
        let d = b[i] - a[i];
        for (p, q) in [(-d, a[i] + half[i]), (d, half[i] - a[i])] {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    lo = lo.max(t);
                } else {
                    hi = hi.min(t);
                }
            }
        }
    }
    lo <= hi
}

/// The warning for a patch that hangs over an edge of the shape, if it does.
pub fn overhang_warning(f: &Value, shape: &Shape) -> Option<String> {
    let WrittenPatch {
        frame,
        half_m: half,
        name,
    } = patch_of(f)?;
    let over = overhang_m(&frame, half, shape)?;
    let tol = ROUND_OFF_FRACTION * half[0].max(half[1]);
    (over > tol).then(|| {
        format!(
            "finger {name}: the patch hangs {:.3} mm over the edge of the face it lies on; elements beyond the edge are not on the object (make the patch smaller or move the finger)",
            1e3 * over
        )
    })
}

/// Warnings for every pair of fingers whose patches overlap (same side of the object,
/// rectangles intersecting in the first finger's tangent plane: separating axis test).
pub fn overlap_warnings(fingers: &Value) -> Vec<String> {
    let patches: Vec<_> = fingers
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(patch_of)
        .collect();
    let mut out = Vec::new();
    for (i, a) in patches.iter().enumerate() {
        for b in &patches[i + 1..] {
            if overlap(a, b) {
                out.push(format!(
                    "fingers {} and {}: their patches overlap; each is modelled as if the other were not there (move them apart or make the patches smaller)",
                    a.name, b.name
                ));
            }
        }
    }
    out
}

fn overlap(a: &WrittenPatch, b: &WrittenPatch) -> bool {
    let (fa, ha) = (&a.frame, a.half_m);
    let (fb, hb) = (&b.frame, b.half_m);
    if fa.normal.dot(&fb.normal) < 0.5 {
        return false;
    }
    let reach = ha[0].max(ha[1]) + hb[0].max(hb[1]);
    if fa.normal.dot(&(fb.origin_m - fa.origin_m)).abs() > reach {
        return false;
    }
    let (ca, cb) = (corners(fa, ha), corners(fb, hb));
    let axes = [fa.t1, fa.t2, fb.t1, fb.t2];
    axes.iter().all(|ax| {
        let span = |cs: &[Vector3<f64>; 4]| {
            cs.iter()
                .map(|c| c.dot(ax))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                })
        };
        let ((a0, a1), (b0, b1)) = (span(&ca), span(&cb));
        let tol = ROUND_OFF_FRACTION * reach;
        a0 < b1 - tol && b0 < a1 - tol
    })
}
