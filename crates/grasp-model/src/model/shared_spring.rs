//! A spring that several fingers' cores share, as the model uses it (`hands`, `servos`): its
//! load coordinates `W = U' f` (N, N m) as a linear map of the fingers' element forces `f`,
//! and its compliance `S` over them, so that its complementary energy `1/2 W' S W` is added to
//! the grasp program's (model.md, "The grasp program"; springs in series, Johnson, *Contact
//! Mechanics*, 4.2).
//!
//! - A **hand** carries its fingers' cores rigidly: a motion `(d, phi)` of its base (world
//!   frame, about its origin `h`) moves a point `p` of any of its fingers by
//!   `d + phi x (p - h)`, so by virtual work `W`'s coordinate along the unit wrench direction
//!   `u_c` is `u_c . sum (f, (p - h) x f)` over its fingers' element forces: the wrench they
//!   put on the object about `h`. The base moves by `-Q S Q' W` (`Q` the compliant
//!   directions): pushed back by what it carries.
//! - A **servo** moves its jaws equal and opposite, each by the same travel `x` along its own
//!   inward normal, so its one coordinate is the sum of its jaws' normal forces, and the
//!   jaws fall short of their commanded travel by `S W = W / k`.
//!
//! A rigid direction (no stiffness given) is no coordinate: the base does not move that way.

use nalgebra::{DMatrix, Vector3, Vector6};

use crate::model::equilibrium::{unit_wrench, MotionPlane, Wrench};
use crate::scene::shared_spring_spec::{HandSpec, ServoSpec};

/// What a shared spring's coordinates are.
#[derive(Debug, Clone, PartialEq)]
pub enum SpringKind {
    /// A hand's base: coordinates along the unit wrench directions `directions` (world frame,
    /// force then moment, about `origin_m`).
    Hand {
        /// The point the stiffness acts about, m (world).
        origin_m: Vector3<f64>,
        /// One unit direction per coordinate: `[x, y, z, rot x, rot y, rot z]` components.
        directions: Vec<Wrench>,
    },
    /// A servo's jaws: one coordinate, the sum of their normal forces.
    Servo,
}

/// One shared spring as the model uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct SharedSpring {
    /// Its name in the scene.
    pub(crate) name: String,
    /// The model indices of the fingers it carries.
    pub(crate) fingers: Vec<usize>,
    /// Hand or servo.
    pub(crate) kind: SpringKind,
    /// `S`, the compliance over the coordinates (m/N, rad/(N m), m/(N m)).
    pub(crate) compliance: DMatrix<f64>,
    /// What a sensitivity may differentiate: each stiffness the spec gives.
    pub(crate) parameters: Vec<SpringParameter>,
}

/// A stiffness of a shared spring that a sensitivity differentiates with respect to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpringParameter {
    /// A hand's `translational_n_per_m` (N/m).
    HandTranslational,
    /// A hand's `rotational_nm_per_rad` (N m/rad).
    HandRotational,
    /// A common factor on a hand's `matrix` (dimensionless, 1 as given).
    HandScale,
    /// A servo's `stiffness_n_per_m` (N/m).
    Servo,
}

impl SpringParameter {
    /// Short name: `k_hand_t`, `k_hand_r`, `k_hand_scale`, `k_servo`.
    pub fn name(self) -> &'static str {
        match self {
            SpringParameter::HandTranslational => "k_hand_t",
            SpringParameter::HandRotational => "k_hand_r",
            SpringParameter::HandScale => "k_hand_scale",
            SpringParameter::Servo => "k_servo",
        }
    }
}

impl SharedSpring {
    /// The hand of `spec` carrying the fingers `fingers` (model indices); in a planar scene
    /// (`plane`) its base moves only in the plane. Its compliance is the inverse of the
    /// stiffness's block over the directions that move (validation checked it positive
    /// definite, so every such block is too).
    pub fn hand(spec: &HandSpec, fingers: Vec<usize>, plane: Option<&MotionPlane>) -> Self {
        let k = spec.stiffness();
        let directions = compliant_directions(k.compliant, plane);
        let km = nalgebra::Matrix6::from_fn(|r, c| k.matrix[r][c]);
        let block = DMatrix::from_fn(directions.len(), directions.len(), |r, c| {
            directions[r].dot(&(km * directions[c]))
        });
        let compliance = block
            .clone()
            .cholesky()
            .map(|c| c.inverse())
            .unwrap_or_else(|| DMatrix::zeros(block.nrows(), block.ncols()));
        let [x, y, z] = spec.origin_m;
        let parameters = match (
            spec.matrix,
            spec.translational_n_per_m,
            spec.rotational_nm_per_rad,
        ) {
            (Some(_), _, _) => vec![SpringParameter::HandScale],
            (None, t, r) => [
                t.map(|_| SpringParameter::HandTranslational),
                r.map(|_| SpringParameter::HandRotational),
            ]
            .into_iter()
            .flatten()
            .collect(),
        };
        SharedSpring {
            name: spec.name.clone(),
            parameters,
            fingers,
            kind: SpringKind::Hand {
                origin_m: Vector3::new(x, y, z),
                directions,
            },
            compliance,
        }
    }

    /// The servo of `spec` driving the jaws `fingers` (model indices).
    pub fn servo(spec: &ServoSpec, fingers: Vec<usize>) -> Self {
        SharedSpring {
            name: spec.name.clone(),
            fingers,
            kind: SpringKind::Servo,
            compliance: DMatrix::from_element(1, 1, 1.0 / spec.stiffness_n_per_m),
            parameters: vec![SpringParameter::Servo],
        }
    }

    /// Its name in the scene.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The model indices of its fingers.
    pub fn fingers(&self) -> &[usize] {
        &self.fingers
    }

    /// Hand or servo.
    pub fn kind(&self) -> &SpringKind {
        &self.kind
    }

    /// Its load coordinates (6 at most for a hand, 1 for a servo).
    pub fn coordinates(&self) -> usize {
        self.compliance.nrows()
    }

    /// `S` over the coordinates.
    pub fn compliance(&self) -> &DMatrix<f64> {
        &self.compliance
    }

    /// True when coordinate `c` is a moment (N m; its row is scaled by the length unit).
    pub fn is_moment(&self, c: usize) -> bool {
        match &self.kind {
            SpringKind::Hand { directions, .. } => directions[c].fixed_rows::<3>(3).norm() > 0.0,
            SpringKind::Servo => false,
        }
    }

    /// The load on each coordinate (first [`SharedSpring::coordinates`] entries; N per N, or
    /// N m per N) of a unit force on the object along `dir` at `point` (world, m) from one of
    /// its fingers; `normal` tells whether `dir` is that finger's inward normal.
    pub fn unit_load(
        &self,
        dir: &Vector3<f64>,
        point: &Vector3<f64>,
        normal: bool,
    ) -> Vector6<f64> {
        match &self.kind {
            SpringKind::Hand {
                origin_m,
                directions,
            } => {
                let w = unit_wrench(dir, point, origin_m);
                let mut out = Vector6::zeros();
                for (c, u) in directions.iter().enumerate() {
                    out[c] = u.dot(&w);
                }
                out
            }
            SpringKind::Servo => {
                let mut out = Vector6::zeros();
                out[0] = if normal { 1.0 } else { 0.0 };
                out
            }
        }
    }

    /// The stiffnesses a sensitivity may differentiate.
    pub fn stiffness_parameters(&self) -> &[SpringParameter] {
        &self.parameters
    }

    /// The change of the spring's retreat `S w` under the loads `w` (N, N m) per unit of
    /// `parameter` (m and rad per N/m, per N m/rad, or per unit factor): `dS = -S dK S` with
    /// `dK` the identity on the parameter's coordinates, or `K` itself for a matrix's scale
    /// (`dS = -S`): the derivative of an inverse.
    pub fn retreat_per_stiffness(&self, w: &[f64], parameter: SpringParameter) -> Vec<f64> {
        let retreat = &self.compliance * nalgebra::DVector::from_column_slice(w);
        let changed = match parameter {
            SpringParameter::HandScale => return retreat.iter().map(|r| -r).collect(),
            SpringParameter::HandTranslational => {
                retreat.map_with_location(|c, _, r| if self.is_moment(c) { 0.0 } else { r })
            }
            SpringParameter::HandRotational => {
                retreat.map_with_location(|c, _, r| if self.is_moment(c) { r } else { 0.0 })
            }
            SpringParameter::Servo => retreat,
        };
        (-(&self.compliance * changed)).iter().copied().collect()
    }

    /// The spring's displacement under the loads `w` on its coordinates (N, N m): `-S w`,
    /// the base pushed back (a hand's, along its directions) or the jaws' travel lost (a
    /// servo's, m; negative: short of the command).
    pub fn displacement(&self, w: &[f64]) -> Vec<f64> {
        let w = nalgebra::DVector::from_column_slice(w);
        (-(&self.compliance * w)).iter().copied().collect()
    }
}

/// The unit wrench directions a hand's base moves along: the compliant world axes, or in a
/// planar scene the plane's two axes (when translations are compliant) and its normal (when
/// rotations are).
fn compliant_directions(compliant: [bool; 6], plane: Option<&MotionPlane>) -> Vec<Wrench> {
    let axis = |c: usize| {
        let mut u = Wrench::zeros();
        u[c] = 1.0;
        u
    };
    let Some(p) = plane else {
        return (0..6).filter(|&c| compliant[c]).map(axis).collect();
    };
    let force = |v: Vector3<f64>| Wrench::new(v.x, v.y, v.z, 0.0, 0.0, 0.0);
    let moment = |v: Vector3<f64>| Wrench::new(0.0, 0.0, 0.0, v.x, v.y, v.z);
    let mut out = Vec::new();
    if compliant[0] {
        out.extend([force(p.e1), force(p.e2)]);
    }
    if compliant[3] {
        out.push(moment(p.normal));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hand(translational: Option<f64>, rotational: Option<f64>) -> HandSpec {
        HandSpec {
            name: "arm".into(),
            fingers: vec!["a".into()],
            origin_m: [0.0, 0.0, 0.1],
            translational_n_per_m: translational,
            rotational_nm_per_rad: rotational,
            matrix: None,
        }
    }

    #[test]
    fn a_hands_load_is_the_wrench_about_its_origin_along_its_compliant_axes() {
        let s = SharedSpring::hand(&hand(Some(2000.0), Some(5.0)), vec![0], None);
        assert_eq!(s.coordinates(), 6);
        // A unit force along x at (0, 0, 0) about (0, 0, 0.1): moment (p - h) x f = (0, -0.1, 0).
        let w = s.unit_load(&Vector3::x(), &Vector3::zeros(), true);
        assert_eq!(w, Vector6::new(1.0, 0.0, 0.0, 0.0, -0.1, 0.0));
        assert!((s.compliance()[(0, 0)] - 1.0 / 2000.0).abs() < 1e-18);
        assert!((s.compliance()[(4, 4)] - 1.0 / 5.0).abs() < 1e-15);
        assert!(s.is_moment(4) && !s.is_moment(2));
        let rigid_in_rotation = SharedSpring::hand(&hand(Some(2000.0), None), vec![0], None);
        assert_eq!(rigid_in_rotation.coordinates(), 3);
    }

    #[test]
    fn a_servos_load_is_its_jaws_normal_forces() {
        let spec = ServoSpec {
            name: "jaws".into(),
            fingers: vec!["a".into(), "b".into()],
            stiffness_n_per_m: 4000.0,
        };
        let s = SharedSpring::servo(&spec, vec![0, 1]);
        assert_eq!(s.unit_load(&Vector3::z(), &Vector3::x(), true)[0], 1.0);
        assert_eq!(s.unit_load(&Vector3::x(), &Vector3::x(), false)[0], 0.0);
        assert_eq!(s.displacement(&[2.0]), vec![-2.0 / 4000.0]);
    }
}
