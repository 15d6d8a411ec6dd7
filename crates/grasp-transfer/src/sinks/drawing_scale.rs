//! The size of a drawn scene, the same in every sink: the box around the contact points and the
//! centre of mass, and the force arrows' scale.

use grasp_model::GraspModel;

/// The box around the contact points and the centre of mass, `(low, high)` corners, m.
pub fn contact_bounds(g: &GraspModel) -> (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) {
    let c = g.center_of_mass_m();
    g.fingers().iter().fold((c, c), |(lo, hi), f| {
        (lo.inf(&f.frame().origin_m), hi.sup(&f.frame().origin_m))
    })
}

/// The scene's size (diagonal of [`contact_bounds`], m, at least 1 mm) and the force arrows'
/// scale (m per N: the load scale drawn as 0.3 of the size), the same in every sink.
pub fn drawing_scale(g: &GraspModel) -> (f64, f64) {
    let (lo, hi) = contact_bounds(g);
    let size = (hi - lo).norm().max(1e-3);
    (size, 0.3 * size / g.scales().load_n)
}
