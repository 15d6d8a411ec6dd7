//! Linear viscoelastic bodies with a constant Poisson's ratio: the relaxation law a material
//! carries, its creep function, and the coefficients of one time step.
//!
//! **Correspondence.** With `nu` constant every modulus of an isotropic body relaxes with the
//! same function, `E(t) = E_0 e(t)` and `G(t) = G_0 e(t)` (`e(0) = 1`), so by the
//! elastic-viscoelastic correspondence principle (Lee and Radok, J. Appl. Mech. 27, 1960;
//! Christensen, Theory of Viscoelasticity, 2nd ed., section 2.6) every surface compliance of the
//! body, half-space or layer, is its elastic compliance at `E_0` times the normalised creep
//! function `phi(t) = E_0 J(t)`: a traction history `F(s)` gives the displacement
//!
//! ```text
//!   u(t) = C [ F(t) + int_0^t phi'(t - s) F(s) ds ]            (Boltzmann superposition)
//! ```
//!
//! **Relaxation law** (Prony series of the shear modulus, the scene's `relaxation`):
//! `e(t) = g_inf + sum_i g_i exp(-t / tau_i)`, `g_inf = 1 - sum_i g_i > 0`.
//!
//! **Creep function.** `s phi(s) = 1 / (s e(s))` in the Laplace domain. `s e(s) = g_inf + sum_i
//! g_i s / (s + 1/tau_i)` has one zero `s_k = -1/lambda_k` between each pair of consecutive
//! poles and one between the slowest pole and 0, so `phi(t) = phi_inf - sum_k w_k exp(-t /
//! lambda_k)` with `phi_inf = 1 / g_inf`, the retardation times `lambda_k` (each above its
//! `tau`) and `w_k = lambda_k / R'(s_k)` (`R = s e(s)`), `phi(0) = 1`.
//!
//! **Time step** (internal variables, exact for tractions linear within the step): with
//! `z_k(t) = int_0^t (1/lambda_k) exp(-(t - s)/lambda_k) F(s) ds`, `u = C [phi_inf F - sum_k w_k
//! (F - z_k)]`, i.e. `u = C [F + sum_k w_k z_k]` since `phi_inf = 1 + sum_k w_k`. Over a step of
//! length `dt`, with `E_k = exp(-dt/lambda_k)` and `A_k = (lambda_k/dt)(1 - E_k)`:
//!
//! ```text
//!   z_k(t + dt) = E_k z_k(t) + (A_k - E_k) F(t) + (1 - A_k) F(t + dt)
//!   u(t + dt)   = alpha C F(t + dt) + C h,    alpha = 1 + sum_k w_k (1 - A_k),
//!                                            h     = sum_k w_k (E_k z_k(t) + (A_k - E_k) F(t))
//! ```
//!
//! so a step is the elastic program with the compliance `alpha C` and the history displacement
//! `C h` added to the gaps. `dt -> 0` gives `alpha = 1` (the instantaneous response); `dt >>
//! lambda` gives `alpha = phi_inf` (the relaxed one).

use crate::scene::scene_format::RelaxationSpec;

/// One term `g exp(-t / tau)` of a normalised relaxation law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PronyTerm {
    /// The fraction `g` of the instantaneous modulus that relaxes with this time, in `(0, 1)`.
    pub fraction: f64,
    /// Relaxation time `tau`, s (> 0).
    pub time_s: f64,
}

/// A normalised relaxation law `e(t) = 1 - sum_i g_i (1 - exp(-t / tau_i))`.
#[derive(Debug, Clone, PartialEq)]
pub struct RelaxationLaw {
    /// The terms, by increasing time; equal times merged; zero fractions dropped.
    pub terms: Vec<PronyTerm>,
}

impl RelaxationLaw {
    /// The law a material's `relaxation` gives for its instantaneous modulus
    /// `youngs_modulus_pa` (a standard linear solid's long-term modulus is a fraction
    /// `g = 1 - E_inf / E_0`). `None` when nothing relaxes (no terms, or only zero fractions):
    /// the body is elastic, exactly as without the field.
    pub fn of(spec: &RelaxationSpec, youngs_modulus_pa: f64) -> Option<Self> {
        let mut terms: Vec<PronyTerm> = match spec {
            RelaxationSpec::Prony(list) => list
                .iter()
                .map(|t| PronyTerm {
                    fraction: t.fraction,
                    time_s: t.time_s,
                })
                .collect(),
            RelaxationSpec::StandardLinearSolid(s) => vec![PronyTerm {
                fraction: 1.0 - s.long_term_modulus / youngs_modulus_pa,
                time_s: s.time_s,
            }],
        };
        terms.retain(|t| t.fraction > 0.0);
        terms.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
        let mut merged: Vec<PronyTerm> = Vec::with_capacity(terms.len());
        for t in terms {
            match merged.last_mut() {
                Some(last) if last.time_s == t.time_s => last.fraction += t.fraction,
                _ => merged.push(t),
            }
        }
        (!merged.is_empty()).then_some(RelaxationLaw { terms: merged })
    }

    /// The long-term fraction `g_inf = 1 - sum_i g_i` (the relaxed modulus over the
    /// instantaneous one).
    pub fn long_term_fraction(&self) -> f64 {
        1.0 - self.terms.iter().map(|t| t.fraction).sum::<f64>()
    }

    /// `e(t)`: the relaxation modulus over the instantaneous one at `t_s` seconds (the tests'
    /// check of the creep function by the Volterra equation).
    #[cfg(test)]
    pub fn relaxation(&self, t_s: f64) -> f64 {
        self.long_term_fraction()
            + self
                .terms
                .iter()
                .map(|t| t.fraction * (-t_s / t.time_s).exp())
                .sum::<f64>()
    }

    /// `R(s) = s e(s) = g_inf + sum_i g_i s / (s + 1/tau_i)` and `R'(s)`.
    fn laplace(&self, s: f64) -> (f64, f64) {
        let mut r = self.long_term_fraction();
        let mut d = 0.0;
        for t in &self.terms {
            let p = 1.0 / t.time_s;
            r += t.fraction * s / (s + p);
            d += t.fraction * p / ((s + p) * (s + p));
        }
        (r, d)
    }

    /// The creep function of this law (module docs): the zeros of `R` by bisection between
    /// its poles, each to round-off.
    pub fn creep(&self) -> CreepFunction {
        let poles: Vec<f64> = self.terms.iter().map(|t| -1.0 / t.time_s).collect();
        // Brackets (poles ascending: fastest first): (p_1, p_2), ..., (p_N, 0).
        let mut terms = Vec::with_capacity(poles.len());
        for (i, &lo) in poles.iter().enumerate() {
            let hi = poles.get(i + 1).copied().unwrap_or(0.0);
            let s = self.zero_between(lo, hi);
            let (_, d) = self.laplace(s);
            let lambda = -1.0 / s;
            terms.push(CreepTerm {
                weight: lambda / d,
                time_s: lambda,
            });
        }
        CreepFunction {
            long_term: 1.0 / self.long_term_fraction(),
            terms,
        }
    }

    /// The zero of `R` in `(lo, hi)`: `R' > 0`, so `R` rises from `-inf` just above the pole
    /// `lo` to a positive value (or `+inf` at the next pole) at `hi`; bisection until the
    /// midpoint is an endpoint (full precision).
    fn zero_between(&self, lo: f64, hi: f64) -> f64 {
        let (mut a, mut b) = (lo, hi);
        loop {
            let mid = 0.5 * (a + b);
            if !(mid > a && mid < b) {
                return mid;
            }
            if self.laplace(mid).0 < 0.0 {
                a = mid;
            } else {
                b = mid;
            }
        }
    }
}

/// One term `w exp(-t / lambda)` of a normalised creep function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepTerm {
    /// Weight `w` (> 0).
    pub weight: f64,
    /// Retardation time `lambda`, s.
    pub time_s: f64,
}

/// A normalised creep function `phi(t) = E_0 J(t) = phi_inf - sum_k w_k exp(-t / lambda_k)`,
/// `phi(0) = 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct CreepFunction {
    /// `phi_inf = E_0 / E_inf`, the relaxed compliance over the instantaneous one.
    pub long_term: f64,
    /// The terms, by increasing retardation time.
    pub terms: Vec<CreepTerm>,
}

/// The coefficients of one time step (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct StepCoefficients {
    /// `alpha`: the compliance of the step over the instantaneous one.
    pub alpha: f64,
    /// Per creep term, `E_k = exp(-dt / lambda_k)`.
    pub decay: Vec<f64>,
    /// Per creep term, `A_k = (lambda_k / dt)(1 - E_k)`.
    pub average: Vec<f64>,
}

impl CreepFunction {
    #[cfg(test)]
    /// `phi(t)` at `t_s` seconds.
    pub fn at(&self, t_s: f64) -> f64 {
        self.long_term
            - self
                .terms
                .iter()
                .map(|t| t.weight * (-t_s / t.time_s).exp())
                .sum::<f64>()
    }

    /// The coefficients of a step of `dt_s` seconds (`f64::INFINITY`: the fully relaxed
    /// response, `alpha = phi_inf`). `1 - A_k` is taken from its series where `dt << lambda`
    /// (no cancellation).
    pub fn step(&self, dt_s: f64) -> StepCoefficients {
        let mut decay = Vec::with_capacity(self.terms.len());
        let mut average = Vec::with_capacity(self.terms.len());
        let mut alpha = 1.0;
        for t in &self.terms {
            let x = dt_s / t.time_s;
            let (e, one_minus_a) = if x.is_infinite() {
                (0.0, 1.0)
            } else if x < 1e-4 {
                ((-x).exp(), x / 2.0 - x * x / 6.0 + x * x * x / 24.0)
            } else {
                ((-x).exp(), 1.0 + (-x).exp_m1() / x)
            };
            decay.push(e);
            average.push(1.0 - one_minus_a);
            alpha += t.weight * one_minus_a;
        }
        StepCoefficients {
            alpha,
            decay,
            average,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::scene_format::{PronyTermSpec, StandardLinearSolidSpec};

    fn law(terms: &[(f64, f64)]) -> RelaxationLaw {
        let spec = RelaxationSpec::Prony(
            terms
                .iter()
                .map(|&(fraction, time_s)| PronyTermSpec { fraction, time_s })
                .collect(),
        );
        RelaxationLaw::of(&spec, 1e6).unwrap()
    }

    /// A standard linear solid's creep function in closed form: `lambda = tau E_0 / E_inf`,
    /// `phi(t) = E_0/E_inf - (E_0/E_inf - 1) exp(-t/lambda)` (Findley, Lai and Onaran, Creep
    /// and Relaxation of Nonlinear Viscoelastic Materials, section 5.3). Tolerance 1e-14.
    #[test]
    fn standard_linear_solid_creep_is_the_closed_form() {
        let (e0, einf, tau) = (3e6, 1e6, 2.0);
        let spec = RelaxationSpec::StandardLinearSolid(StandardLinearSolidSpec {
            long_term_modulus: einf,
            time_s: tau,
        });
        let c = RelaxationLaw::of(&spec, e0).unwrap().creep();
        assert_eq!(c.terms.len(), 1);
        let lambda = tau * e0 / einf;
        assert!((c.terms[0].time_s - lambda).abs() <= 1e-14 * lambda);
        assert!((c.long_term - e0 / einf).abs() <= 1e-14);
        assert!((c.terms[0].weight - (e0 / einf - 1.0)).abs() <= 1e-13);
        assert!((c.at(0.0) - 1.0).abs() <= 1e-14);
    }

    /// Creep and relaxation are inverse (`int_0^t e(t - s) dphi(s) = 1` for all `t`, the
    /// defining Volterra equation), checked for a three-term law by direct quadrature of the
    /// convolution (composite Simpson on `[0, 1]` and `[1, t]`, 200,000 panels each, a
    /// computation independent of the zeros and residues; its error, `(h / lambda)^4 / 180` at
    /// the fastest retardation time, stays below 1e-10): within 1e-8 over five decades of time.
    #[test]
    fn creep_inverts_relaxation() {
        let l = law(&[(0.3, 0.01), (0.25, 1.0), (0.2, 100.0)]);
        let c = l.creep();
        let simpson = |f: &dyn Fn(f64) -> f64, a: f64, b: f64| {
            let n = 200_000;
            let h = (b - a) / n as f64;
            let mut sum = f(a) + f(b);
            for i in 1..n {
                sum += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            sum * h / 3.0
        };
        for t in [1e-3, 0.05, 1.0, 20.0, 300.0] {
            // int_0^t e(t - s) phi'(s) ds + e(t) phi(0) = 1.
            let dphi = |s: f64| {
                c.terms
                    .iter()
                    .map(|k| k.weight / k.time_s * (-s / k.time_s).exp())
                    .sum::<f64>()
            };
            let f = |s: f64| l.relaxation(t - s) * dphi(s);
            let split = t.min(1.0);
            let integral = simpson(&f, 0.0, split) + simpson(&f, split, t);
            let total = integral + l.relaxation(t) * c.at(0.0);
            assert!((total - 1.0).abs() <= 1e-8, "t {t}: {total}");
        }
    }

    /// The step's limits: `dt -> 0` is the instantaneous compliance, `dt >> lambda` the
    /// relaxed one (to `lambda / dt`), to 1e-12; a constant traction held over many steps creeps like `phi(t)`
    /// exactly (the scheme is exact for tractions linear within a step).
    #[test]
    fn step_limits_and_exact_creep_under_a_constant_traction() {
        let c = law(&[(0.4, 0.5), (0.3, 30.0)]).creep();
        assert!((c.step(1e-12).alpha - 1.0).abs() <= 1e-12);
        // `1 - A = 1 - lambda/dt` for `dt >> lambda`: 1e-13 of the weights at dt = 1e15 s.
        assert!((c.step(1e15).alpha - c.long_term).abs() <= 1e-12);
        assert!((c.step(f64::INFINITY).alpha - c.long_term).abs() <= 1e-15);
        // u(t) for F = 1 applied at t = 0: u_0 = 1, then steps of 0.37 s.
        let dt = 0.37;
        let k = c.step(dt);
        let mut z = vec![0.0; c.terms.len()];
        for n in 1..=200 {
            let h: f64 = (0..z.len())
                .map(|j| c.terms[j].weight * (k.decay[j] * z[j] + (k.average[j] - k.decay[j])))
                .sum();
            let u = k.alpha + h;
            for (j, zj) in z.iter_mut().enumerate() {
                *zj = k.decay[j] * *zj + (k.average[j] - k.decay[j]) + (1.0 - k.average[j]);
            }
            let t = n as f64 * dt;
            assert!((u - c.at(t)).abs() <= 1e-12, "t {t}: {u} vs {}", c.at(t));
        }
    }
}
