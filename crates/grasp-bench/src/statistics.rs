//! Folding repeated samples: median and spread of a case, and the growth exponent of time
//! against unknowns over a series of cases.

/// Median and spread of `values` (any order): `(median, min, max)`; `None` when empty.
pub fn median_and_range(values: &[f64]) -> Option<(f64, f64, f64)> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    Some((median, v[0], v[n - 1]))
}

/// Growth exponent `k` of `time ~ unknowns^k`: the least-squares slope of `ln time` against
/// `ln unknowns` over `(unknowns, time_s)` points; `None` with fewer than two distinct sizes
/// or any non-positive value.
pub fn growth_exponent(points: &[(f64, f64)]) -> Option<f64> {
    if points.iter().any(|&(n, t)| !(n > 0.0 && t > 0.0)) {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(n, t)| (n.ln(), t.ln())).collect();
    let m = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / m, b + y / m));
    let sxx: f64 = logs.iter().map(|&(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|&(x, y)| (x - mx) * (y - my)).sum();
    (sxx > 1e-12).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median_and_range(&[3.0, 1.0, 2.0]), Some((2.0, 1.0, 3.0)));
        assert_eq!(
            median_and_range(&[4.0, 1.0, 2.0, 3.0]),
            Some((2.5, 1.0, 4.0))
        );
        assert_eq!(median_and_range(&[]), None);
    }

    #[test]
    fn growth_exponent_recovers_a_power_law() {
        // t = 3 n^2.5 exactly: the fitted slope is 2.5 to rounding.
        let pts: Vec<(f64, f64)> = [10.0, 40.0, 90.0, 300.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(2.5)))
            .collect();
        let k = growth_exponent(&pts).unwrap();
        assert!((k - 2.5).abs() < 1e-12, "{k}");
        assert_eq!(growth_exponent(&[(10.0, 1.0)]), None);
        assert_eq!(growth_exponent(&[(10.0, 1.0), (10.0, 2.0)]), None);
    }
}
