//! Parameter sweeps: a grid of variants of one scene, `--vary PATH=START:END:COUNT` (COUNT
//! values evenly spaced, both ends included) or `--vary PATH=V1,V2,...`, one axis per `--vary`,
//! the last varying fastest. `PATH` is dotted with indices: `object.weight`,
//! `fingers[0].friction.mu`, `fingers[*].friction.mu` (every finger),
//! `fingers[0].texture.random.seed` (an integer in the scene stays an integer when the value
//! is whole).

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

/// Largest magnitude below which every whole `f64` is exact (2^53).
const EXACT_WHOLE: f64 = 9_007_199_254_740_992.0;

/// Sets every number the path reaches to `value`; false if the path reaches nothing or a value
/// that is not a number. A whole value replacing an integer is written as an integer, so that
/// integer fields (a texture's `seed`, a patch's `grid`) can be swept.
fn set(v: &mut Value, path: &[Step], value: f64) -> bool {
    let Some((first, rest)) = path.split_first() else {
        return match v {
            Value::Number(old) => {
                let whole = value.fract() == 0.0 && value.abs() < EXACT_WHOLE;
                *v = match (old.is_f64(), whole) {
                    (false, true) => json!(value as i64),
                    _ => json!(value),
                };
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

    /// A texture's numbers sweep like any other, its seed as an integer (a float seed would
    /// not read), and each variant is a scene whose height map is read relative to the swept
    /// scene's folder.
    #[test]
    fn textures_are_swept_seeds_as_integers() {
        let text = include_str!("../../../examples/cube_a.json");
        let mut scene: Value = serde_json::from_str(text).unwrap();
        scene["fingers"][0]["texture"] = json!({"random": {"rms_m": 1e-6, "hurst": 0.8, "wavelengths_m": [2e-2, 5e-3], "seed": 1}});
        scene["fingers"][1]["texture"] =
            json!({"heights": {"file": "h.csv", "pixel_m": [4e-3, 4e-3]}});
        let axes = [
            Axis::parse("fingers[0].texture.random.seed=2,3").unwrap(),
            Axis::parse("fingers[0].texture.random.hurst=0.5:1:2").unwrap(),
            Axis::parse("fingers[1].texture.heights.pixel_m[0]=4e-3,5e-3").unwrap(),
        ];
        let sweep = Sweep::new(scene, "t", &axes).unwrap();
        assert_eq!(sweep.len(), 8);
        let dir = std::env::temp_dir().join(format!("grasp-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("h.csv"), "0,0,0\n0,1e-6,0\n0,0,0\n").unwrap();
        let mut seen = Vec::new();
        for k in 0..sweep.len() {
            let (_, vary, v) = sweep.variant(k).unwrap();
            assert!(
                v["fingers"][0]["texture"]["random"]["seed"].is_u64(),
                "{vary}"
            );
            let mut inputs = grasp_io::RunInputs::new();
            let s = grasp_io::scene_from_value(v, &dir, &mut inputs)
                .unwrap_or_else(|e| panic!("{vary}: {e}"));
            assert_eq!(inputs.len(), 1, "the height map is read and noted");
            let t = s.fingers[0].texture.as_ref().unwrap().random.unwrap();
            let map = s.fingers[1]
                .texture
                .as_ref()
                .unwrap()
                .heights
                .as_ref()
                .unwrap();
            seen.push((t.seed, t.hurst, map.pixel_m[0]));
        }
        assert_eq!(seen[0], (2, 0.5, 4e-3));
        assert_eq!(seen[7], (3, 1.0, 5e-3));
        // A fractional value of an integer field stays fractional (and is refused when read).
        let (_, _, v) = Sweep::new(json!({"seed": 1}), "f", &[Axis::parse("seed=2.5").unwrap()])
            .unwrap()
            .variant(0)
            .unwrap();
        assert_eq!(v["seed"], json!(2.5));
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
