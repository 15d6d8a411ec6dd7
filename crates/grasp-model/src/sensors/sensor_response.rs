//! A sensor's response applied to its ideal readings (`fingers[i].sensor.<kind>.response`):
//! at point `k`, component `c` of read-out (draw) `d`,
//!
//! `y = quantise(clip(g_k x + sigma n_kcd))`, `g_k = 1 + gain_std z_k`,
//!
//! with `z_k` and `n_kcd` standard normal deviates drawn from the seed: `z_k` once per point
//! (the same at every read-out: a calibration error), `n_kcd` anew per component and read-out
//! (a hand-off's step `d` is its draw; one solve is draw 0), each sensor (a finger's kind) on
//! its own streams. The deviates come from a counter-based generator (SplitMix64 of the seed,
//! the stream, the point, the component and the draw, turned normal by Box-Muller), so a reading does not depend on the order or the
//! threads that compute it, and the same seed gives the same readings every time.

use crate::scene::response_spec::ResponseSpec;

/// Stream of the gains (the noise has its own).
const GAIN_STREAM: u64 = 1;

/// Stream of the noise.
const NOISE_STREAM: u64 = 2;

/// SplitMix64's finaliser: a well-mixed 64-bit value of `x`.
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// A uniform deviate in `(0, 1)` for the key `(seed, stream, a, b, c)`.
fn uniform(key: [u64; 5]) -> f64 {
    let h = key.iter().fold(0u64, |h, k| mix(h ^ mix(*k)));
    // 53 random bits, offset by half a step: never 0, never 1.
    ((h >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// A standard normal deviate for the key `(seed, stream, a, b, c)` (Box-Muller).
pub fn normal_deviate(seed: u64, stream: u64, a: u64, b: u64, c: u64) -> f64 {
    let u1 = uniform([seed, stream, a, b, c]);
    let u2 = uniform([seed, stream, a, b, c ^ 0x5555_5555_5555_5555]);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// `r`'s response applied to the readings `values` (row-major, one `[f64; N]` a point) of
/// read-out `draw` of sensor `sensor` (its own streams: a finger's kind, so that two sensors of
/// one seed draw independent gains and noise), in place. A gain below 0 reads as 0 (a dead
/// point); a reading too large for its quantum to count (`|y / q| >= 2^52`) is not rounded;
/// a saturated reading stays within the range after rounding.
pub fn apply_response<const N: usize>(
    r: &ResponseSpec,
    values: &mut [[f64; N]],
    sensor: u64,
    draw: u64,
) {
    let (gains, noises) = (GAIN_STREAM ^ (sensor << 8), NOISE_STREAM ^ (sensor << 8));
    for (k, point) in values.iter_mut().enumerate() {
        let k = k as u64;
        for (c, x) in point.iter_mut().enumerate() {
            let mut y = *x;
            if r.gain_std > 0.0 {
                y *= (1.0 + r.gain_std * normal_deviate(r.seed, gains, k, 0, 0)).max(0.0);
            }
            if r.noise_std > 0.0 {
                y += r.noise_std * normal_deviate(r.seed, noises, k, c as u64, draw);
            }
            *x = saturate_and_quantise(r, y);
        }
    }
}

/// `y` clipped to the saturation range, rounded to the quantum, and clipped again (a step
/// past the range's end is not read).
fn saturate_and_quantise(r: &ResponseSpec, mut y: f64) -> f64 {
    if let Some([low, high]) = r.saturation {
        y = y.clamp(low, high);
    }
    if let Some(q) = r.quantum {
        let steps = y / q;
        if steps.is_finite() && steps.abs() < (1u64 << 52) as f64 {
            y = q * steps.round();
        }
    }
    if let Some([low, high]) = r.saturation {
        y = y.clamp(low, high);
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    fn response() -> ResponseSpec {
        ResponseSpec {
            gain_std: 0.0,
            noise_std: 0.0,
            saturation: None,
            quantum: None,
            seed: 7,
        }
    }

    #[test]
    fn no_departure_leaves_the_readings_bit_for_bit() {
        let mut v = vec![[1.25, -3.5e-7, 0.0], [f64::MIN_POSITIVE, 2.0, -0.0]];
        let ideal = v.clone();
        apply_response(&response(), &mut v, 0, 3);
        assert_eq!(v, ideal);
    }

    #[test]
    fn rounding_stays_in_range_and_huge_readings_are_kept() {
        let r = ResponseSpec {
            saturation: Some([-0.5, 0.53]),
            quantum: Some(0.05),
            ..response()
        };
        let mut v = vec![[0.6]];
        apply_response(&r, &mut v, 0, 0);
        assert_eq!(v, vec![[0.53]], "0.55 would be past the range");
        let r = ResponseSpec {
            quantum: Some(1e-300),
            ..response()
        };
        let mut v = vec![[2e8]];
        apply_response(&r, &mut v, 0, 0);
        assert_eq!(v, vec![[2e8]]);
    }

    #[test]
    fn saturation_clips_and_quantisation_rounds() {
        let r = ResponseSpec {
            saturation: Some([-1.0, 2.0]),
            quantum: Some(0.25),
            ..response()
        };
        let mut v = vec![[3.0, -7.0, 0.3], [0.124, 0.126, 1.9]];
        apply_response(&r, &mut v, 0, 0);
        assert_eq!(v, vec![[2.0, -1.0, 0.25], [0.0, 0.25, 2.0]]);
    }

    #[test]
    fn the_deviates_are_standard_normal() {
        // 200,000 deviates: the mean within 4 standard errors (4 / sqrt(n) = 0.009) of 0, the
        // variance within 4 of its standard errors (4 sqrt(2 / n) = 0.013) of 1, and the share
        // beyond 2 within 0.003 of the normal's 0.0455.
        let n = 200_000u64;
        let x: Vec<f64> = (0..n)
            .map(|k| normal_deviate(11, NOISE_STREAM, k, 1, 2))
            .collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        let tail = x.iter().filter(|v| v.abs() > 2.0).count() as f64 / n as f64;
        assert!(mean.abs() < 0.009, "{mean}");
        assert!((var - 1.0).abs() < 0.013, "{var}");
        assert!((tail - 0.0455).abs() < 0.003, "{tail}");
    }

    #[test]
    fn gains_stay_and_noise_changes_from_draw_to_draw() {
        let r = ResponseSpec {
            gain_std: 0.1,
            ..response()
        };
        let ideal = vec![[1.0; 3]; 50];
        let (mut a, mut b) = (ideal.clone(), ideal.clone());
        apply_response(&r, &mut a, 0, 0);
        apply_response(&r, &mut b, 0, 1);
        assert_eq!(a, b, "the gains are the sensor's, not the read-out's");
        assert!(a.iter().any(|p| (p[0] - 1.0).abs() > 0.01));
        let r = ResponseSpec {
            noise_std: 0.1,
            ..response()
        };
        let (mut c, mut d, mut e) = (ideal.clone(), ideal.clone(), ideal.clone());
        apply_response(&r, &mut c, 0, 0);
        apply_response(&r, &mut d, 0, 1);
        apply_response(&r, &mut e, 0, 0);
        assert_ne!(c, d, "each read-out draws its own noise");
        assert_eq!(c, e, "the same seed and draw give the same noise");
        let mut other = ideal.clone();
        apply_response(&r, &mut other, 1, 0);
        assert_ne!(
            c, other,
            "another sensor of the same seed draws its own noise"
        );
    }
}
