//! Quadrature and interpolation rules of the layered kernels ([`super::layer_kernels`]):
//! Gauss-Legendre nodes and weights, and Chebyshev interpolation on an interval.
//!
//! Gauss-Legendre: the nodes are the roots of the Legendre polynomial `P_n`, found by Newton's
//! method from Tricomi's initial guess `cos(pi (i - 1/4) / (n + 1/2))`, with weights
//! `2 / ((1 - x^2) P_n'(x)^2)` (Abramowitz and Stegun 25.4.29). Chebyshev: values at the
//! first-kind points `cos(pi (j + 1/2) / n)` turned into the coefficients of `sum c_k T_k` by the
//! discrete cosine sum, evaluated by Clenshaw's recurrence (Trefethen, Approximation Theory and
//! Approximation Practice, chapters 3 and 4: for a function analytic inside the Bernstein ellipse
//! of parameter `rho` the error falls like `rho^-n`).

use std::f64::consts::PI;

/// The `n`-point Gauss-Legendre rule on `[-1, 1]`: nodes ascending and their weights. Exact for
/// polynomials of degree `2 n - 1`.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            dp = d;
            let step = p / d;
            x -= step;
            if step.abs() <= 1e-16 {
                break;
            }
        }
        let (_, d) = legendre(n, x);
        dp = if d.is_finite() { d } else { dp };
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        nodes[i] = -x;
        nodes[n - 1 - i] = x;
        weights[i] = w;
        weights[n - 1 - i] = w;
    }
    (nodes, weights)
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence (Abramowitz and Stegun 22.7.10).
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

/// The first-kind Chebyshev points of `[-1, 1]`, `x_j = cos(pi (j + 1/2) / n)`.
pub fn chebyshev_points(n: usize) -> Vec<f64> {
    (0..n)
        .map(|j| (PI * (j as f64 + 0.5) / n as f64).cos())
        .collect()
}

/// The coefficients `c_k` of `sum_k c_k T_k(x)` interpolating `values` taken at
/// [`chebyshev_points`] (the discrete cosine sum; `c_0` halved).
pub fn chebyshev_coefficients(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    (0..n)
        .map(|k| {
            let s: f64 = values
                .iter()
                .enumerate()
                .map(|(j, v)| v * (PI * k as f64 * (j as f64 + 0.5) / n as f64).cos())
                .sum();
            s * if k == 0 { 1.0 } else { 2.0 } / n as f64
        })
        .collect()
}

/// `T_0(x) .. T_{n-1}(x)` by the recurrence `T_{k+1} = 2 x T_k - T_{k-1}`, into `out`.
pub fn chebyshev_basis(x: f64, out: &mut [f64]) {
    let mut prev = 1.0;
    let mut cur = x;
    for (k, slot) in out.iter_mut().enumerate() {
        *slot = match k {
            0 => 1.0,
            1 => x,
            _ => {
                let next = 2.0 * x * cur - prev;
                prev = cur;
                cur = next;
                next
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule integrates `x^k` exactly up to degree `2n - 1` (to round-off, 1e-14), and the
    /// weights sum to 2.
    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in [1, 2, 3, 5, 8, 12, 16, 24] {
            let (x, w) = gauss_legendre(n);
            for k in 0..2 * n {
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                let want = if k % 2 == 0 {
                    2.0 / (k as f64 + 1.0)
                } else {
                    0.0
                };
                assert!((got - want).abs() <= 1e-14, "n {n}, x^{k}: {got} vs {want}");
            }
        }
    }

    /// Interpolating `exp(x)` (entire) at 14 points is exact to round-off; the basis
    /// reproduces `cos(k acos x)`.
    #[test]
    fn chebyshev_interpolation_of_an_entire_function() {
        let n = 14;
        let values: Vec<f64> = chebyshev_points(n).iter().map(|x| x.exp()).collect();
        let c = chebyshev_coefficients(&values);
        let mut t = vec![0.0; n];
        for i in 0..=40 {
            let x = -1.0 + i as f64 / 20.0;
            chebyshev_basis(x, &mut t);
            let got: f64 = c.iter().zip(&t).map(|(c, t)| c * t).sum();
            assert!((got - x.exp()).abs() <= 1e-14, "at {x}: {got}");
            for (k, tk) in t.iter().enumerate() {
                assert!((tk - (k as f64 * x.acos()).cos()).abs() <= 1e-13);
            }
        }
    }
}
