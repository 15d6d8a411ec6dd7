//! The size of a drawn scene, the same in every sink: the box around the contact points and the
//! centre of mass, and the force arrows' scale (one for every drawing of forces).

use grasp_model::GraspModel;

/// The box around the contact points and the centre of mass, `(low, high)` corners, m.
pub fn contact_bounds(g: &GraspModel) -> (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) {
    let c = g.center_of_mass_m();
    g.fingers().iter().fold((c, c), |(lo, hi), f| {
        (lo.inf(&f.frame().origin_m), hi.sup(&f.frame().origin_m))
    })
}

/// The scene's size (diagonal of `contact_bounds`, m, at least 1 mm) and the force arrows'
/// scale ([`arrow_scale_m_per_n`] of that size, m per N), the same in every sink and in the
/// package's drawings of other force sets.
pub fn drawing_scale(g: &GraspModel) -> (f64, f64) {
    let (lo, hi) = contact_bounds(g);
    let size = (hi - lo).norm().max(1e-3);
    (size, arrow_scale_m_per_n(size, g.scales().load_n))
}

/// The fraction of a drawing's size that an arrow of the load scale spans.
pub const ARROW_FRACTION: f64 = 0.3;

/// The force arrows' scale, m per N, of a drawing `size_m` across: the load scale
/// (`load_scale_n`, N) drawn as [`ARROW_FRACTION`] of the size. The one scale of every drawing
/// of forces: the sinks' arrows and the CLI's force diagram.
pub fn arrow_scale_m_per_n(size_m: f64, load_scale_n: f64) -> f64 {
    ARROW_FRACTION * size_m / load_scale_n
}
