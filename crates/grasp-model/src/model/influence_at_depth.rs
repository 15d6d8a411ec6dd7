//! Influence coefficients at depth: the force per unit area that crosses the plane at depth
//! `z` inside a pad (an elastic half-space) under a unit force spread uniformly over one
//! rectangular element of its surface, exact (Boussinesq and Cerruti integrated over the
//! rectangle: Love 1929; Johnson, *Contact Mechanics*, sections 3.2, 3.3 and 3.6), and the
//! area shared by an element and a taxel (the read-out at zero depth).
//!
//! Pad coordinates: `x` along `t1`, `y` along `t2`, `z` into the pad (along `-n`). A unit
//! force on the object `(F, G1, G2)` (along `n`, `t1`, `t2`) loads the pad with a pressure
//! `F` and a shear `-G`; the reading at a point of the plane `z` is the traction the pad
//! below the plane exerts on the part above it, `(-sigma_zz, tau_zx, tau_zy)`, written along
//! `(n, t1, t2)`: at `z -> 0` it is the surface traction `(F, G1, G2)` per unit area. Only
//! these three stresses are needed and, for a half-space, none depends on Poisson's ratio or
//! the modulus: Boussinesq's `sigma_z = -3 P z^3 / (2 pi rho^5)`,
//! `tau_zx = -3 P x z^2 / (2 pi rho^5)` (Johnson eq. 3.20) and Cerruti's
//! `sigma_z = -3 Q x z^2 / (2 pi rho^5)`, `tau_zx = -3 Q x^2 z / (2 pi rho^5)`,
//! `tau_zy = -3 Q x y z / (2 pi rho^5)` (Johnson eq. 3.22), `rho^2 = x^2 + y^2 + z^2`. In the
//! reading's signs the point kernels form the symmetric matrix
//! `(3 / (2 pi rho^5)) [[z^3, -x z^2, -y z^2], [-x z^2, x^2 z, x y z], [-y z^2, x y z, y^2 z]]`.

use std::f64::consts::PI;

/// Each point kernel's integral over `[0, X] x [0, Y]` at depth `z` (its corner function, the
/// `1 / (2 pi)` left out), with `R = sqrt(X^2 + Y^2 + z^2)`:
///
/// - `nn`: `atan(X Y / (z R)) + X Y z / R (1 / (X^2 + z^2) + 1 / (Y^2 + z^2))` (Love 1929;
///   Holl 1940's corner formula; model.md "Normal stress at depth under a uniform rectangle"),
/// - `nx`: `-z^2 Y / ((X^2 + z^2) R)`, `ny`: `-z^2 X / ((Y^2 + z^2) R)`,
/// - `xx`: `atan(X Y / (z R)) - X Y z / ((X^2 + z^2) R)`, `yy` likewise with `Y^2`,
/// - `xy`: `z / R`,
///
/// each checked by differentiation (`d^2 f / dX dY` is the kernel `3 (.) / rho^5`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct CornerValues {
    nn: f64,
    nx: f64,
    ny: f64,
    xx: f64,
    yy: f64,
    xy: f64,
}

impl CornerValues {
    /// The corner functions at `(x, y)` (m) and depth `z > 0` (m).
    fn at(x: f64, y: f64, z: f64) -> CornerValues {
        let (x2, y2, z2) = (x * x, y * y, z * z);
        let r = (x2 + y2 + z2).sqrt();
        let angle = (x * y / (z * r)).atan();
        let (ax, ay) = (x2 + z2, y2 + z2);
        let xyz_r = x * y * z / r;
        CornerValues {
            nn: angle + xyz_r * (1.0 / ax + 1.0 / ay),
            nx: -z2 * y / (ax * r),
            ny: -z2 * x / (ay * r),
            xx: angle - xyz_r / ax,
            yy: angle - xyz_r / ay,
            xy: z / r,
        }
    }

    fn add(&mut self, c: CornerValues, sign: f64) {
        self.nn += sign * c.nn;
        self.nx += sign * c.nx;
        self.ny += sign * c.ny;
        self.xx += sign * c.xx;
        self.yy += sign * c.yy;
        self.xy += sign * c.xy;
    }
}

/// An element's rectangle relative to a field point: the field point minus the element's
/// centre, and the element's sides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementOffset {
    /// Field point minus element centre, along `t1` and `t2`, m.
    pub offset_m: [f64; 2],
    /// Element sides `[hx, hy]`, m.
    pub side_m: [f64; 2],
}

/// The reading per unit area at depth `depth_m > 0` under a unit force (1 N) spread uniformly
/// over one element: a 3 x 3 matrix, 1/m^2, rows the reading `(n, t1, t2)` (the traction that
/// crosses the plane, signed as the element forces), columns the element's force
/// `(F, G1, G2)`. Love 1929's uniformly loaded rectangle (normal column; Johnson section 3.6)
/// and Cerruti's point force integrated over the rectangle (tangential columns; Johnson
/// section 3.3), each the corner sum `f(X2, Y2) - f(X1, Y2) - f(X2, Y1) + f(X1, Y1)` of the
/// corner functions of the module's kernels over `X in [x - hx/2, x + hx/2]` etc., divided by
/// `2 pi` and by the element's area.
pub fn reading_per_area_at_depth(element: &ElementOffset, depth_m: f64) -> [[f64; 3]; 3] {
    let [dx, dy] = element.offset_m;
    let [hx, hy] = [element.side_m[0] / 2.0, element.side_m[1] / 2.0];
    let mut s = CornerValues::default();
    for (x, sx) in [(dx + hx, 1.0), (dx - hx, -1.0)] {
        for (y, sy) in [(dy + hy, 1.0), (dy - hy, -1.0)] {
            s.add(CornerValues::at(x, y, depth_m), sx * sy);
        }
    }
    let k = 1.0 / (2.0 * PI * element.side_m[0] * element.side_m[1]);
    [
        [k * s.nn, -k * s.nx, -k * s.ny],
        [-k * s.nx, k * s.xx, k * s.xy],
        [-k * s.ny, k * s.xy, k * s.yy],
    ]
}

/// A square taxel on the patch: centre, half side and the angle of its sides to `t1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotatedSquare {
    /// Centre along `t1`, `t2`, m.
    pub centre_m: [f64; 2],
    /// Half the side, m.
    pub half_side_m: f64,
    /// Angle of its first side to `t1`, rad (counter-clockwise from `t1` toward `t2`).
    pub angle_rad: f64,
}

impl RotatedSquare {
    /// The square's corners, counter-clockwise, m.
    pub fn corners_m(&self) -> Vec<[f64; 2]> {
        let (s, c) = self.angle_rad.sin_cos();
        let h = self.half_side_m;
        [[-h, -h], [h, -h], [h, h], [-h, h]]
            .iter()
            .map(|[u, v]| {
                [
                    self.centre_m[0] + u * c - v * s,
                    self.centre_m[1] + u * s + v * c,
                ]
            })
            .collect()
    }
}

/// The area, m^2, that an axis-aligned rectangle `[lo[0], hi[0]] x [lo[1], hi[1]]` (m) shares
/// with the convex polygon `corners` (counter-clockwise, m): the polygon clipped by the
/// rectangle's four sides (Sutherland-Hodgman), then the shoelace formula. Exact up to
/// round-off; the read-out at zero depth bins each element's uniform traction by it.
pub fn overlap_area_m2(lo: [f64; 2], hi: [f64; 2], corners: &[[f64; 2]]) -> f64 {
    let mut poly = corners.to_vec();
    for axis in 0..2 {
        poly = clip(&poly, axis, lo[axis], 1.0);
        poly = clip(&poly, axis, hi[axis], -1.0);
    }
    let n = poly.len();
    let twice: f64 = (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    (twice / 2.0).abs()
}

/// `poly` clipped to the half-plane `side * (p[axis] - at) >= 0`.
fn clip(poly: &[[f64; 2]], axis: usize, at: f64, side: f64) -> Vec<[f64; 2]> {
    let inside = |p: &[f64; 2]| side * (p[axis] - at) >= 0.0;
    let mut out = Vec::with_capacity(poly.len() + 2);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if inside(&a) {
            out.push(a);
        }
        if inside(&a) != inside(&b) {
            let t = (at - a[axis]) / (b[axis] - a[axis]);
            let mut p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            p[axis] = at;
            out.push(p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The whole plane at any depth carries the element's force exactly (model.md): a
    /// rectangle far larger than the depth, seen from its centre, takes all of it. The
    /// normal part misses `O((z/L)^3)` of it, the shear `O(z/L)` (Cerruti's `tau_zx` falls
    /// off as `z / r^3`, Boussinesq's `sigma_z` as `z^3 / r^5`): at `L/z = 5e5`, 3e-6.
    #[test]
    fn a_large_rectangle_carries_the_load() {
        let side = 1e6;
        let e = ElementOffset {
            offset_m: [0.0, 0.0],
            side_m: [side, side],
        };
        let k = reading_per_area_at_depth(&e, 1.0);
        let area = side * side;
        assert!((k[0][0] * area - 1.0).abs() < 1e-9, "{}", k[0][0] * area);
        assert!((k[1][1] * area - 1.0).abs() < 1e-5, "{}", k[1][1] * area);
        assert!((k[2][2] * area - 1.0).abs() < 1e-5, "{}", k[2][2] * area);
        assert!(k[0][1].abs() * area < 1e-12 && k[1][2].abs() * area < 1e-12);
    }

    #[test]
    fn overlap_of_a_turned_square_is_its_area_inside() {
        let sq = RotatedSquare {
            centre_m: [0.0, 0.0],
            half_side_m: 1.0,
            angle_rad: std::f64::consts::FRAC_PI_4,
        };
        let whole = overlap_area_m2([-2.0, -2.0], [2.0, 2.0], &sq.corners_m());
        assert!((whole - 4.0).abs() < 1e-14);
        // The right half-plane takes half of it.
        let half = overlap_area_m2([0.0, -2.0], [2.0, 2.0], &sq.corners_m());
        assert!((half - 2.0).abs() < 1e-14);
    }
}
