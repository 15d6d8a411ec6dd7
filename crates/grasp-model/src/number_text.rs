//! Numbers as messages show them. Rust's `{}` writes every digit of an `f64` (`1e308` becomes
//! a 309-digit number), so a message that quotes a value the user gave writes it with
//! [`readable`] or [`Readable`]: plain when moderate, in exponent form otherwise, and the
//! shortest text that reads back as the same number in both.

use std::fmt;

/// Magnitudes written plainly: from 1e-4 (inclusive) up to 1e6 (exclusive), and 0.
const PLAIN_RANGE: std::ops::Range<f64> = 1e-4..1e6;

/// `x` as a reader wants it: `0.05`, `250`, `-3.5`, `1e308`, `2e-16`, `NaN`, `inf`; the
/// shortest text that parses back to `x`.
pub fn readable(x: f64) -> String {
    Readable(x).to_string()
}

/// A number shown as [`readable`] shows it, for use in `format!` arguments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Readable(pub f64);

impl fmt::Display for Readable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() || PLAIN_RANGE.contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extreme_numbers_take_exponent_form_and_read_back_exactly() {
        for (x, text) in [
            (1e308, "1e308"),
            (-1e308, "-1e308"),
            (2e-16, "2e-16"),
            (5e-324, "5e-324"),
            (1e6, "1e6"),
            (123456.5, "123456.5"),
            (0.05, "0.05"),
            (1e-4, "0.0001"),
            (0.0, "0"),
            (-0.0, "-0"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(readable(x), text);
            if x.is_finite() {
                assert_eq!(text.parse::<f64>().unwrap(), x, "{text} reads back");
            }
        }
        assert!(readable(f64::MAX).len() < 30, "{}", readable(f64::MAX));
    }
}
