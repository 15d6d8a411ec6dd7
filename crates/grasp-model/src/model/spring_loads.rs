//! What a model's fingers do to its shared springs ([`crate::model::shared_spring`]) and the
//! springs to them: the load `W = U' f` each spring carries from the element forces `f`
//! (N, N m), and the retreat `U S W` (m) its motion adds to the displacement of every element
//! of its fingers (the gradient of its complementary energy `1/2 W' S W`; springs in series,
//! Johnson, *Contact Mechanics*, 4.2).

use nalgebra::{DVector, Vector6};

use crate::model::equilibrium::{unit_wrench, Wrench};
use crate::model::grasp_model::GraspModel;
use crate::model::shared_spring::{SharedSpring, SpringKind};

/// Calls `each(j, load)` for every unknown `j` (program layout) of `spring`'s fingers in
/// `model`, with the load on the spring's coordinates of a unit force in it (N per N, N m
/// per N; first [`SharedSpring::coordinates`] entries).
pub fn for_each_unit_load(
    model: &GraspModel,
    spring: &SharedSpring,
    mut each: impl FnMut(usize, &Vector6<f64>),
) {
    for &i in spring.fingers() {
        let f = &model.fingers[i];
        let ne = f.patch.len();
        for j in 0..f.n_unknowns() {
            let (k, c) = (j % ne, j / ne);
            let load = spring.unit_load(&f.direction(c), &f.element_point(k), c == 0);
            each(f.offset + j, &load);
        }
    }
}

/// The load on each of `model`'s shared springs (N, N m per coordinate) from the element
/// forces `x_n` (N, program layout).
pub fn spring_loads(model: &GraspModel, x_n: &[f64]) -> Vec<Vec<f64>> {
    model
        .springs
        .iter()
        .map(|s| {
            let mut w = vec![0.0; s.coordinates()];
            for_each_unit_load(model, s, |j, load| {
                for (c, wc) in w.iter_mut().enumerate() {
                    *wc += load[c] * x_n[j];
                }
            });
            w
        })
        .collect()
}

/// Adds to `displacement_m` (m, program layout of the fingers' unknowns) every shared spring's
/// retreat `U S W` under the element forces `x_n` (N).
pub fn add_spring_retreat(model: &GraspModel, x_n: &[f64], displacement_m: &mut [f64]) {
    for (s, w) in model.springs.iter().zip(spring_loads(model, x_n)) {
        let retreat = s.compliance() * DVector::from_vec(w);
        for_each_unit_load(model, s, |j, load| {
            displacement_m[j] += (0..s.coordinates())
                .map(|c| load[c] * retreat[c])
                .sum::<f64>();
        });
    }
}

/// The whole wrench (N, N m, world frame, about the hand's origin) that the element forces
/// `x_n` (N) of a hand's fingers put on the object, every direction included (the hand
/// carries its opposite); `None` for a servo.
pub fn hand_wrench(model: &GraspModel, spring: &SharedSpring, x_n: &[f64]) -> Option<Wrench> {
    let SpringKind::Hand { origin_m, .. } = spring.kind() else {
        return None;
    };
    let mut w = Wrench::zeros();
    for &i in spring.fingers() {
        let f = &model.fingers[i];
        let ne = f.patch.len();
        for j in (0..f.n_unknowns()).filter(|&j| x_n[f.offset + j] != 0.0) {
            let (k, c) = (j % ne, j / ne);
            w += unit_wrench(&f.direction(c), &f.element_point(k), origin_m) * x_n[f.offset + j];
        }
    }
    Some(w)
}

/// Subtracts from the displacement offsets `offset_m` (m, program layout of the fingers'
/// unknowns) each commanded hand pose's motion of its fingers' surfaces: a base moved by
/// `(d, phi)` (m, rad, world frame, about its origin `h`) moves a point `p` of its fingers by
/// `d + phi x (p - h)`, toward the object along each unknown's direction by the virtual work
/// of that motion with the unknown's unit wrench about `h` (as an approach closes a gap).
/// `poses` pairs a hand's index among the model's springs with its pose; servos are skipped.
pub fn add_hand_poses(model: &GraspModel, poses: &[(usize, [f64; 6])], offset_m: &mut [f64]) {
    for &(j, pose) in poses {
        let Some(spring) = model.springs.get(j) else {
            continue;
        };
        let SpringKind::Hand { origin_m, .. } = spring.kind() else {
            continue;
        };
        let motion = Wrench::from_column_slice(&pose);
        for &i in spring.fingers() {
            let f = &model.fingers[i];
            let ne = f.patch.len();
            for k in 0..f.n_unknowns() {
                let w = unit_wrench(&f.direction(k / ne), &f.element_point(k % ne), origin_m);
                offset_m[f.offset + k] -= w.dot(&motion);
            }
        }
    }
}
