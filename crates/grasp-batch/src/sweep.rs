//! Parameter sweeps: a grid of variants of one scene, `--vary PATH=START:END:COUNT` (COUNT
//! values evenly spaced, both ends included) or `--vary PATH=V1,V2,...`, one axis per `--vary`,
//! the last varying fastest. `PATH` is dotted with indices: `object.weight`,
//! `fingers[0].friction.mu`, `fingers[*].friction.mu` (every finger).

use serde_json::{json, Value};

use crate::error::BatchError;

/// One axis of the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The path as written.
    pub path: String,
    /// Its values.
    pub values: Vec<f64>,
}

fn err(spec: &str, message: impl Into<String>) -> BatchError {
    BatchError::Sweep {
        spec: spec.into(),
        message: message.into(),
    }
}

impl Axis {
    /// Parses `PATH=START:END:COUNT` or `PATH=V1,V2,...`.
    pub fn parse(spec: &str) -> Result<Axis, BatchError> {
        let (path, values) = spec
            .split_once('=')
            .ok_or_else(|| err(spec, "write PATH=START:END:COUNT or PATH=V1,V2,..."))?;
        let num = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| err(spec, format!("`{s}` is not a finite number")))
        };
        let values = if values.contains(':') {
            let parts: Vec<&str> = values.split(':').collect();
            let [a, b, n] = parts[..] else {
                return Err(err(spec, "a range is START:END:COUNT, e.g. 0.2:1.0:9"));
            };
            let (a, b) = (num(a)?, num(b)?);
            let n: usize = n
                .trim()
                .parse()
                .ok()
                .filter(|n| (1..=100_000).contains(n))
                .ok_or_else(|| err(spec, "COUNT is a whole number from 1 to 100000"))?;
            (0..n)
                .map(|k| match n {
                    1 => a,
                    _ => a + (b - a) * k as f64 / (n - 1) as f64,
                })
                .collect()
        } else {
            values.split(',').map(num).collect::<Result<Vec<_>, _>>()?
        };
        Ok(Axis {
            path: path.trim().to_string(),
            values,
        })
    }
}

/// One step of a path.
enum Step<'a> {
    Key(&'a str),
    Index(usize),
    Every,
}

fn steps(path: &str) -> Option<Vec<Step<'_>>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
        if !key.is_empty() {
            out.push(Step::Key(key));
        }
        while let Some(r) = rest.strip_prefix('[') {
            let (inside, after) = r.split_once(']')?;
            out.push(match inside {
                "*" => Step::Every,
                i => Step::Index(i.parse().ok()?),
            });
            rest = after;
        }
        if !rest.is_empty() {
            return None;
        }
    }
    (!out.is_empty()).then_some(out)
}

/// Sets every number the path reaches to `value`; false if the path reaches nothing or a value
/// that is not a number.
fn set(v: &mut Value, path: &[Step<'_>], value: f64) -> bool {
    let Some((first, rest)) = path.split_first() else {
        return match v {
            Value::Number(_) => {
                *v = json!(value);
                true
            }
            _ => false,
        };
    };
    match (first, v) {
        (Step::Key(k), Value::Object(m)) => m.get_mut(*k).is_some_and(|c| set(c, rest, value)),
        (Step::Index(i), Value::Array(a)) => a.get_mut(*i).is_some_and(|c| set(c, rest, value)),
        (Step::Every, Value::Array(a)) => {
            !a.is_empty() && a.iter_mut().all(|c| set(c, rest, value))
        }
        _ => false,
    }
}

/// The variants of `scene` (JSON) over the grid of `axes`: `(id, vary, scene)` with ids
/// `<stem>-<k>` (k from 0, zero-padded), the last axis varying fastest.
pub fn expand(
    scene: &Value,
    stem: &str,
    axes: &[Axis],
) -> Result<Vec<(String, Value, Value)>, BatchError> {
    let parsed: Vec<Vec<Step<'_>>> = axes
        .iter()
        .map(|a| {
            steps(&a.path).ok_or_else(|| {
                err(
                    &a.path,
                    "write a dotted path such as fingers[*].friction.mu or object.weight",
                )
            })
        })
        .collect::<Result<_, _>>()?;
    // In f64: a product of counts that overflows usize must not wrap to a small grid.
    let total = axes.iter().map(|a| a.values.len() as f64).product::<f64>();
    if total > 1e6 {
        return Err(err(
            &axes[0].path,
            format!("the grid has {total:.3e} variants; at most 1000000"),
        ));
    }
    let total = total as usize;
    let width = total.saturating_sub(1).to_string().len();
    let mut out = Vec::with_capacity(total);
    for k in 0..total {
        let mut v = scene.clone();
        let mut vary = serde_json::Map::new();
        let mut rest = k;
        for (axis, path) in axes.iter().zip(&parsed).rev() {
            let x = axis.values[rest % axis.values.len()];
            rest /= axis.values.len();
            if !set(&mut v, path, x) {
                return Err(err(
                    &axis.path,
                    "reaches no number in the scene; check the path against the scene file",
                ));
            }
            vary.insert(axis.path.clone(), json!(x));
        }
        out.push((format!("{stem}-{k:0width$}"), Value::Object(vary), v));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_lists_and_paths() {
        let a = Axis::parse("fingers[*].friction.mu=0.2:1.0:5").unwrap();
        assert_eq!(a.values, [0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
        assert_eq!(Axis::parse("object.weight=1,2").unwrap().values, [1.0, 2.0]);
        for bad in ["x", "a=1:2", "a=1:2:0", "a=q"] {
            assert!(Axis::parse(bad).is_err(), "{bad}");
        }
        let scene = json!({"object": {"weight": 1.0},
                           "fingers": [{"friction": {"mu": 0.1}}, {"friction": {"mu": 0.1}}]});
        let axes = [
            Axis::parse("fingers[*].friction.mu=0.2,0.4").unwrap(),
            Axis::parse("object.weight=1:3:3").unwrap(),
        ];
        let v = expand(&scene, "s", &axes).unwrap();
        assert_eq!(v.len(), 6);
        assert_eq!(v[4].0, "s-4");
        assert_eq!(v[4].2["fingers"][1]["friction"]["mu"], json!(0.4));
        assert_eq!(v[4].2["object"]["weight"], json!(2.0));
        let bad = [Axis::parse("fingers[5].friction.mu=1").unwrap()];
        assert!(expand(&scene, "s", &bad).is_err());
    }
}
