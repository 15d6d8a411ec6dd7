//! Arithmetic of the scene's three-component vectors ([`Vec3`]): dot and cross products,
//! lengths, differences, and the unit vector computed without overflow.

use crate::scene::scene_format::Vec3;

/// `x / |x|` computed without overflow or underflow (scaled by the largest component first);
/// `None` if `x` is zero or not finite.
pub fn unit_vector(x: &Vec3) -> Option<Vec3> {
    let m = x.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(m.is_finite() && m > 0.0) || x.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let y = [x[0] / m, x[1] / m, x[2] / m];
    let n = norm(&y);
    Some([y[0] / n, y[1] / n, y[2] / n])
}

/// The Euclidean length of `x`.
pub fn norm(x: &Vec3) -> f64 {
    dot(x, x).sqrt()
}

/// The dot product of `a` and `b`.
pub fn dot(a: &Vec3, b: &Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a - b`.
pub fn sub(a: &Vec3, b: &Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a / |a|` (for a direction already checked nonzero and in range).
pub fn unit(a: &Vec3) -> Vec3 {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

/// The cross product of `a` and `b`.
pub fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
