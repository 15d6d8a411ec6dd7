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

/// Most variants a sweep may have.
pub const MAX_VARIANTS: usize = 1_000_000;

/// One step of a path.
#[derive(Debug, Clone, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
    Every,
}

fn steps(path: &str) -> Option<Vec<Step>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
        if !key.is_empty() {
            out.push(Step::Key(key.to_string()));
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
fn set(v: &mut Value, path: &[Step], value: f64) -> bool {
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
        (Step::Key(k), Value::Object(m)) => m.get_mut(k).is_some_and(|c| set(c, rest, value)),
        (Step::Index(i), Value::Array(a)) => a.get_mut(*i).is_some_and(|c| set(c, rest, value)),
        (Step::Every, Value::Array(a)) => {
            !a.is_empty() && a.iter_mut().all(|c| set(c, rest, value))
        }
        _ => false,
    }
}

/// The variants of a scene (JSON) over the grid of some axes, made one at a time (a sweep of
/// [`MAX_VARIANTS`] holds one scene, not a million): variant `k` has id `<stem>-<k>` (k from
/// 0, zero-padded), the last axis varying fastest.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    scene: Value,
    stem: String,
    axes: Vec<(Axis, Vec<Step>)>,
    total: usize,
    width: usize,
}

impl Sweep {
    /// The grid of `axes` over `scene`; every path must reach a number of the scene.
    pub fn new(scene: Value, stem: &str, axes: &[Axis]) -> Result<Sweep, BatchError> {
        let mut parsed = Vec::with_capacity(axes.len());
        for a in axes {
            let path = steps(&a.path).ok_or_else(|| {
                err(
                    &a.path,
                    "write a dotted path such as fingers[*].friction.mu or object.weight",
                )
            })?;
            // Whether a path reaches a number does not depend on the value set.
            if !set(&mut scene.clone(), &path, 0.0) {
                return Err(err(
                    &a.path,
                    "reaches no number in the scene; check the path against the scene file",
                ));
            }
            parsed.push((a.clone(), path));
        }
        let total = axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
            .filter(|n| *n <= MAX_VARIANTS)
            .ok_or_else(|| {
                let n: f64 = axes.iter().map(|a| a.values.len() as f64).product();
                err(
                    axes.first().map_or("", |a| &a.path),
                    format!("the grid has {n:.0} variants; at most {MAX_VARIANTS}"),
                )
            })?;
        Ok(Sweep {
            scene,
            stem: stem.to_string(),
            axes: parsed,
            total,
            width: total.saturating_sub(1).to_string().len(),
        })
    }

    /// Number of variants.
    pub fn len(&self) -> usize {
        self.total
    }

    /// True for a grid without variants (an axis with no value).
    pub fn is_empty(&self) -> bool {
        self.total == 0
    }

    /// Variant `k`: its id, its `vary` note (path -> value) and its scene.
    pub fn variant(&self, k: usize) -> Result<(String, Value, Value), BatchError> {
        let mut v = self.scene.clone();
        let mut vary = serde_json::Map::new();
        let mut rest = k;
        for (axis, path) in self.axes.iter().rev() {
            let x = axis.values[rest % axis.values.len()];
            rest /= axis.values.len();
            if !set(&mut v, path, x) {
                return Err(err(&axis.path, "reaches no number in the scene"));
            }
            vary.insert(axis.path.clone(), json!(x));
        }
        let width = self.width;
        Ok((format!("{}-{k:0width$}", self.stem), Value::Object(vary), v))
    }

    /// Variant `k` as a line of a batch's JSONL input.
    pub fn line(&self, k: usize) -> Result<String, BatchError> {
        let (id, vary, scene) = self.variant(k)?;
        Ok(json!({"id": id, "vary": vary, "scene": scene}).to_string())
    }
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
        let sweep = Sweep::new(scene.clone(), "s", &axes).unwrap();
        assert_eq!(sweep.len(), 6);
        let v4 = sweep.variant(4).unwrap();
        assert_eq!(v4.0, "s-4");
        assert_eq!(v4.2["fingers"][1]["friction"]["mu"], json!(0.4));
        assert_eq!(v4.2["object"]["weight"], json!(2.0));
        assert_eq!(v4.1["object.weight"], json!(2.0));
        let bad = [Axis::parse("fingers[5].friction.mu=1").unwrap()];
        assert!(Sweep::new(scene.clone(), "s", &bad).is_err());
    }

    /// The documented largest grid is a count, not a million scenes held: made on demand,
    /// the first and the last variant as the grid says; one more variant is refused.
    #[test]
    fn a_million_variants_are_made_one_at_a_time() {
        let scene = json!({"object": {"weight": 1.0}, "fingers": [{"friction": {"mu": 0.1}}]});
        let axes = [
            Axis::parse("object.weight=1:1000:1000").unwrap(),
            Axis::parse("fingers[0].friction.mu=0.1:1.0:1000").unwrap(),
        ];
        let sweep = Sweep::new(scene.clone(), "big", &axes).unwrap();
        assert_eq!(sweep.len(), MAX_VARIANTS);
        let (id, vary, last) = sweep.variant(MAX_VARIANTS - 1).unwrap();
        assert_eq!(id, "big-999999");
        assert_eq!(last["object"]["weight"], json!(1000.0));
        assert_eq!(vary["fingers[0].friction.mu"], json!(1.0));
        assert_eq!(sweep.variant(0).unwrap().0, "big-000000");
        let more = [
            axes[0].clone(),
            axes[1].clone(),
            Axis::parse("object.weight=1,2").unwrap(),
        ];
        let e = Sweep::new(scene, "big", &more).unwrap_err().to_string();
        assert!(e.contains("2000000 variants; at most 1000000"), "{e}");
    }
}
