//! The checks of one field of a scene, each reporting what is wrong at its JSON path with the
//! fix: numbers in their physical ranges, forces, points, directions, materials and their
//! relaxation laws, radii of curvature, friction laws. The validation pass
//! ([`crate::scene::scene_validation`]) applies them field by field.

use std::ops::RangeInclusive;

use crate::error::SceneError;
use crate::problem_list::ProblemList;
use crate::scene::limits::*;
use crate::scene::scene_format::{
    ElasticLawParams, FrictionSpec, MaterialSpec, RelaxationSpec, Vec3,
};
use crate::scene::vector_math::{dot, norm};

/// The problems the checks of a scene's fields found (at most
/// [`crate::problem_list::MAX_LISTED_PROBLEMS`] listed, the rest counted).
#[derive(Default)]
pub struct FieldChecks(ProblemList);

impl FieldChecks {
    /// Adds the problem at `path`.
    pub fn push(&mut self, path: &str, message: String, fix: &str) {
        self.0.add(path, message, fix);
    }

    /// A finite value inside `[lo, hi]`; `what` is the unit.
    pub fn range(
        &mut self,
        path: &str,
        x: f64,
        range: RangeInclusive<f64>,
        unit: &str,
        fix: &str,
    ) -> bool {
        if x.is_finite() && range.contains(&x) {
            return true;
        }
        let (lo, hi) = range.into_inner();
        let u = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        self.push(
            path,
            format!("is {}{u}, outside [{lo:e}, {hi:e}]{u}", number(x)),
            fix,
        );
        false
    }

    /// A force magnitude: 0 or in `[MIN_NONZERO_FORCE_N, MAX_FORCE_N]`.
    pub fn force(&mut self, path: &str, x: f64, fix: &str) -> bool {
        if force_in_range(x) {
            return true;
        }
        self.push(
            path,
            format!(
                "is {} N, neither 0 nor in [{MIN_NONZERO_FORCE_N:e}, {MAX_FORCE_N:e}] N",
                number(x)
            ),
            &format!("{fix}: 0 or between {MIN_NONZERO_FORCE_N:e} and {MAX_FORCE_N:e} N"),
        );
        false
    }

    /// A force component: its magnitude is a force (see [`FieldChecks::force`]).
    pub fn signed_force(&mut self, path: &str, x: f64) -> bool {
        self.force(path, x.abs(), "give the component in newtons")
    }

    /// A point with every coordinate in `[-MAX_COORDINATE_M, MAX_COORDINATE_M]`.
    pub fn point(&mut self, path: &str, x: &Vec3) -> bool {
        let fix = format!("give coordinates in metres, |x| <= {MAX_COORDINATE_M:e} m");
        let b = -MAX_COORDINATE_M..=MAX_COORDINATE_M;
        let mut ok = true;
        for (k, c) in x.iter().enumerate() {
            // Every coordinate is checked (and reported), not only up to the first bad one.
            ok &= self.range(&format!("{path}[{k}]"), *c, b.clone(), "m", &fix);
        }
        ok
    }

    /// Three finite components.
    pub fn finite3(&mut self, path: &str, x: &Vec3) -> bool {
        if x.iter().all(|c| c.is_finite()) {
            return true;
        }
        self.push(
            path,
            "has a non-finite component".into(),
            "give three finite numbers",
        );
        false
    }

    /// A direction: finite and nonzero, and of a length whose square neither overflows nor
    /// underflows (a scene read from a file is normalised on load, see
    /// [`Scene::normalize_directions`](crate::scene::scene_format::Scene::normalize_directions); a scene built in code must keep its directions so).
    pub fn direction(&mut self, path: &str, x: &Vec3, fix: &str) -> bool {
        if !self.finite3(path, x) {
            return false;
        }
        let n2 = dot(x, x);
        if n2 == 0.0 {
            self.push(path, "has zero length".into(), fix);
            return false;
        }
        if !(n2.is_finite() && n2 >= f64::MIN_POSITIVE) {
            self.push(
                path,
                format!("has a length ({:e}) whose square is out of range", norm(x)),
                "give a direction with components between 1e-150 and 1e150, e.g. a unit vector",
            );
            return false;
        }
        true
    }

    /// A material: an elastic one's modulus, Poisson's ratio, relaxation law and layer
    /// thickness in their ranges (a rigid one has nothing to check).
    pub fn material(&mut self, path: &str, m: &MaterialSpec) {
        if let MaterialSpec::Elastic(e) = m {
            if !(e.youngs_modulus.is_finite() && e.youngs_modulus > 0.0) {
                self.push(
                    &format!("{path}.youngs_modulus"),
                    format!("is {} Pa", number(e.youngs_modulus)),
                    "give Young's modulus in pascals, > 0 (or write \"rigid\" for the material)",
                );
            } else if !MODULUS_RANGE_PA.contains(&e.youngs_modulus) {
                self.push(
                    &format!("{path}.youngs_modulus"),
                    format!(
                        "is {:e} Pa, outside the physical range [{:e}, {:e}] Pa",
                        e.youngs_modulus,
                        MODULUS_RANGE_PA.start(),
                        MODULUS_RANGE_PA.end()
                    ),
                    "give Young's modulus in pascals (1 MPa = 1e6 Pa), or \"rigid\"",
                );
            }
            if !(e.poisson_ratio.is_finite() && (0.0..0.5).contains(&e.poisson_ratio)) {
                self.push(
                    &format!("{path}.poisson_ratio"),
                    format!("is {}", number(e.poisson_ratio)),
                    "give Poisson's ratio in [0, 0.5) (rubber is about 0.49)",
                );
            }
            if let Some(r) = &e.relaxation {
                self.relaxation(&format!("{path}.relaxation"), r, e.youngs_modulus);
            }
            if let Some(h) = e.layer_thickness_m {
                if e.poisson_ratio > MAX_LAYER_POISSON_RATIO && e.poisson_ratio < 0.5 {
                    self.push(
                        &format!("{path}.poisson_ratio"),
                        format!(
                            "is {} for a bonded layer, nearer 0.5 than 1e-9",
                            number(e.poisson_ratio)
                        ),
                        "give at most 0.499999999 (the layer is then incompressible for any \
                         patch), or omit layer_thickness_m for a half-space",
                    );
                }
                self.range(
                    &format!("{path}.layer_thickness_m"),
                    h,
                    LAYER_THICKNESS_RANGE_M,
                    "m",
                    "give the thickness of the elastic layer on its rigid core in metres (1 mm = \
                     0.001), or omit layer_thickness_m for an elastic half-space",
                );
            }
        }
    }

    /// A relaxation law: times in range, fractions in `[0, 1)` summing below 1 (a long-term
    /// modulus remains), a standard linear solid's long-term modulus in `(0, E_0]`.
    pub fn relaxation(&mut self, path: &str, r: &RelaxationSpec, youngs_modulus: f64) {
        let time_fix = "give the relaxation time in seconds (1 ms = 0.001)";
        match r {
            RelaxationSpec::Prony(terms) => {
                if terms.len() > MAX_PRONY_TERMS {
                    self.push(
                        path,
                        format!("has {} terms, more than {MAX_PRONY_TERMS}", terms.len()),
                        "fit the law with fewer terms (one a decade of time is plenty)",
                    );
                    return;
                }
                let mut sum = 0.0;
                for (i, t) in terms.iter().enumerate() {
                    let p = format!("{path}[{i}]");
                    if !(t.fraction.is_finite() && (0.0..1.0).contains(&t.fraction)) {
                        self.push(
                            &format!("{p}.fraction"),
                            format!("is {}", number(t.fraction)),
                            "give the fraction of the instantaneous modulus that relaxes with \
                             this time, in [0, 1)",
                        );
                    } else {
                        sum += t.fraction;
                    }
                    self.range(
                        &format!("{p}.time_s"),
                        t.time_s,
                        RELAXATION_TIME_RANGE_S,
                        "s",
                        time_fix,
                    );
                }
                if sum >= 1.0 {
                    self.push(
                        path,
                        format!("has fractions summing to {}", number(sum)),
                        "make the fractions sum below 1: the modulus left after full relaxation \
                         is (1 - their sum) times youngs_modulus, and must stay above zero",
                    );
                }
            }
            RelaxationSpec::StandardLinearSolid(sls) => {
                let e = sls.long_term_modulus;
                if !(e.is_finite() && e > 0.0 && e <= youngs_modulus) {
                    self.push(
                        &format!("{path}.long_term_modulus"),
                        format!("is {} Pa", number(e)),
                        "give the modulus after full relaxation in pascals, above 0 and at most \
                         youngs_modulus (the instantaneous modulus)",
                    );
                }
                self.range(
                    &format!("{path}.time_s"),
                    sls.time_s,
                    RELAXATION_TIME_RANGE_S,
                    "s",
                    time_fix,
                );
            }
        }
    }

    /// A pad's edge (or rim) radius `r`, m: finite, at least 0 (a sharp edge) and at most half
    /// the pad's `side` (its smaller side, or a disc's diameter).
    pub fn edge_radius(&mut self, path: &str, r: f64, side: f64) {
        if !(r.is_finite() && r >= 0.0 && r <= 0.5 * side) {
            self.push(
                path,
                format!("is {} m", number(r)),
                &format!(
                    "give the radius of the pad's rounded edge in metres, from 0 (sharp) to half \
                     the pad's smaller side ({} m)",
                    number(0.5 * side)
                ),
            );
        }
    }

    /// A radius of curvature: positive, in range, and at least half the patch.
    pub fn radius(&mut self, path: &str, r: f64, half_patch: f64) {
        if !(r.is_finite() && r > 0.0) {
            self.push(
                path,
                format!("is {} m", number(r)),
                "give the radius of curvature in metres, > 0, or null for flat",
            );
            return;
        }
        let fix = "give the radius in metres, or null for a flat surface";
        if self.range(path, r, LENGTH_RANGE_M, "m", fix) && half_patch.is_finite() && half_patch > r
        {
            self.push(
                path,
                format!(
                    "is {} m, smaller than half the patch ({} m)",
                    number(r),
                    number(half_patch)
                ),
                "shrink patch.size below the diameter, or check the radius (the gap is the \
                 parabolic approximation of the surface)",
            );
        }
    }

    /// Checks a friction law (thesis section 2.6).
    pub fn friction(&mut self, path: &str, spec: &FrictionSpec, object_rigid: bool) {
        match spec {
            FrictionSpec::Coefficient(c) => {
                self.coefficient(&format!("{path}.mu"), c.mu);
            }
            FrictionSpec::Table(t) => self.friction_table(&format!("{path}.table"), &t.table),
            FrictionSpec::Elastic(e) => {
                self.elastic_law(&format!("{path}.elastic"), &e.elastic, object_rigid)
            }
        }
    }

    /// A friction coefficient: 0, or in `[MIN_NONZERO_FRICTION_COEFFICIENT,
    /// MAX_FRICTION_COEFFICIENT]`.
    pub fn coefficient(&mut self, path: &str, mu: f64) -> bool {
        let b = (MIN_NONZERO_FRICTION_COEFFICIENT, MAX_FRICTION_COEFFICIENT);
        if mu == 0.0 || (b.0..=b.1).contains(&mu) {
            return true;
        }
        self.push(
            path,
            format!("is {}, neither 0 nor in [{:e}, {:e}]", number(mu), b.0, b.1),
            &format!(
                "give a friction coefficient between {:e} and {:e}, or 0 for a frictionless \
                 finger",
                b.0, b.1
            ),
        );
        false
    }

    /// A friction table: at least one point, loads in range and strictly increasing,
    /// coefficients in range.
    // `!(a > b)` is meant: a NaN load must fail the ordering check too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    pub fn friction_table(&mut self, path: &str, table: &[[f64; 2]]) {
        if table.is_empty() {
            self.push(
                path,
                "is empty".into(),
                "list at least one [P_N, mu] point (one point is a constant mu)",
            );
        }
        for (j, pt) in table.iter().enumerate() {
            self.force(
                &format!("{path}[{j}][0]"),
                pt[0],
                "give the finger's normal load in newtons",
            );
            self.coefficient(&format!("{path}[{j}][1]"), pt[1]);
            if j > 0 && !(pt[0] > table[j - 1][0]) {
                self.push(
                    &format!("{path}[{j}][0]"),
                    format!(
                        "is {} N, not above the previous load {} N",
                        number(pt[0]),
                        number(table[j - 1][0])
                    ),
                    "sort the points by strictly increasing load",
                );
            }
        }
    }

    /// The elastic friction law of thesis eq. (40): its lengths in range, the finger's radius
    /// below the object's, an elastic object.
    pub fn elastic_law(&mut self, path: &str, q: &ElasticLawParams, object_rigid: bool) {
        for (name, val) in [
            ("finger_radius", q.finger_radius),
            ("object_radius", q.object_radius),
            ("contact_length", q.contact_length),
        ] {
            if !(val.is_finite() && val > 0.0) {
                self.push(
                    &format!("{path}.{name}"),
                    format!("is {} m", number(val)),
                    "give a length in metres, finite and > 0",
                );
            } else {
                self.range(
                    &format!("{path}.{name}"),
                    val,
                    LENGTH_RANGE_M,
                    "m",
                    "give the length in metres",
                );
            }
        }
        if q.finger_radius.is_finite()
            && q.object_radius.is_finite()
            && q.finger_radius >= q.object_radius
        {
            self.push(
                &format!("{path}.object_radius"),
                format!(
                    "is {} m, not larger than finger_radius {} m",
                    number(q.object_radius),
                    number(q.finger_radius)
                ),
                "thesis eq. (40) needs R1 < R2 (finger radius below the object's); \
                 use a table or a constant mu otherwise",
            );
        }
        if object_rigid {
            self.push(
                path,
                "needs an elastic object (eq. 40 uses the object's shear modulus)".into(),
                "give object.material elastic constants, or use a table or constant mu",
            );
        }
    }

    /// Every problem, the first [`crate::problem_list::MAX_LISTED_PROBLEMS`] listed and the
    /// rest counted.
    pub fn finish(self) -> Result<(), SceneError> {
        self.0.finish().map_err(SceneError::Invalid)
    }
}

/// A number as a reader wants it: plain when moderate, in exponent form otherwise.
pub fn number(x: f64) -> String {
    crate::number_text::readable(x)
}
