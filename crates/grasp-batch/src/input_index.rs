//! The first pass over a batch's input: how many scenes it holds and the id of each, so every
//! result line can say how many scenes the whole input has (for `merge`), a duplicate id is
//! refused before anything is solved (naming every line that repeats one), and a resumed
//! output can be checked against the input it came from.
//!
//! A line's id is found by a light scan that builds no scene ([`line_id`]); the full parse of
//! the line (on a worker) gives the same id by the same rule.

use std::collections::hash_map::Entry;
use std::collections::HashMap;

use serde::de::{Error as _, IgnoredAny, MapAccess, Visitor};
use serde::{Deserialize, Deserializer};
use serde_json::Value;

use crate::error::BatchError;

/// Most scenes a batch input may hold (a sweep has at most 1,000,000).
pub const MAX_SCENES: usize = 10_000_000;

/// Ids listed in a duplicate-id error (the rest are counted).
const MAX_LISTED_IDS: usize = 10;

/// The scenes of an input: their number and, per id, the position and line of its scene.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InputIndex {
    /// Number of scenes (blank lines not counted).
    pub scenes: usize,
    ids: HashMap<String, (usize, usize)>,
    repeats: Vec<(String, usize)>,
}

impl InputIndex {
    /// Notes the scene at `index` (from line `line`, 1-based) with `id`.
    pub(crate) fn add(&mut self, id: String, index: usize, line: usize) -> Result<(), BatchError> {
        if self.scenes >= MAX_SCENES {
            return Err(BatchError::Usage {
                what: "input".into(),
                message: format!(
                    "holds more than {MAX_SCENES} scenes; split it into several batches"
                ),
            });
        }
        self.scenes += 1;
        match self.ids.entry(id) {
            Entry::Occupied(e) => self.repeats.push((e.key().clone(), line)),
            Entry::Vacant(e) => {
                e.insert((index, line));
            }
        }
        Ok(())
    }

    /// The position of the scene with `id`, if the input has one.
    pub fn position_of(&self, id: &str) -> Option<usize> {
        self.ids.get(id).map(|e| e.0)
    }

    /// Refuses an input whose ids repeat, naming each id with the lines that give it.
    pub(crate) fn refuse_duplicates(&self) -> Result<(), BatchError> {
        if self.repeats.is_empty() {
            return Ok(());
        }
        let mut lines: Vec<(&str, Vec<usize>)> = Vec::new();
        for (id, line) in &self.repeats {
            match lines.iter_mut().find(|(i, _)| i == id) {
                Some((_, l)) => l.push(*line),
                None => lines.push((id, vec![self.ids[id].1, *line])),
            }
        }
        let listed: Vec<String> = lines
            .iter()
            .take(MAX_LISTED_IDS)
            .map(|(id, l)| {
                let l: Vec<String> = l.iter().map(usize::to_string).collect();
                format!("`{id}` on lines {}", l.join(", "))
            })
            .collect();
        let more = lines.len().saturating_sub(MAX_LISTED_IDS);
        Err(BatchError::DuplicateIds(format!(
            "{} id(s) repeat: {}{}; give each scene its own id (results, resume and merge \
             match scenes by id)",
            lines.len(),
            listed.join("; "),
            if more > 0 {
                format!("; and {more} more")
            } else {
                String::new()
            }
        )))
    }
}

/// The id a JSONL line gives its scene: the `id` (a string, or a number as written) of a
/// line that is a JSON object with a `scene` key; otherwise `line-<number>` (a bare scene, or
/// a line that is not JSON).
pub fn line_id(text: &str, number: usize) -> String {
    serde_json::from_str::<IdScan>(text)
        .ok()
        .filter(|s| s.scene)
        .and_then(|s| s.id)
        .unwrap_or_else(|| default_id(number))
}

/// The id of a line whose scene has no id of its own.
pub fn default_id(number: usize) -> String {
    format!("line-{number}")
}

/// The id of a parsed line object (the same rule as [`line_id`]).
pub(crate) fn id_of(obj: &serde_json::Map<String, Value>, number: usize) -> String {
    match obj.get("id") {
        Some(v) if obj.contains_key("scene") => id_value(v.clone()),
        _ => None,
    }
    .unwrap_or_else(|| default_id(number))
}

fn id_value(v: Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s),
        Value::Number(n) => Some(n.to_string()),
        _ => None,
    }
}

/// The keys of a line that decide its id (a JSON object only); the rest is skipped unbuilt.
struct IdScan {
    id: Option<String>,
    scene: bool,
}

impl<'de> Deserialize<'de> for IdScan {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(IdScanVisitor)
    }
}

struct IdScanVisitor;

impl<'de> Visitor<'de> for IdScanVisitor {
    type Value = IdScan;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<IdScan, A::Error> {
        let mut scan = IdScan {
            id: None,
            scene: false,
        };
        let mut seen_id = false;
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "id" if !seen_id => {
                    seen_id = true;
                    scan.id = id_value(map.next_value::<Value>()?);
                }
                "scene" if !scan.scene => {
                    scan.scene = true;
                    map.next_value::<IgnoredAny>()?;
                }
                "id" | "scene" => return Err(A::Error::custom(format!("`{key}` twice"))),
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(scan)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use grasp_model::{strict_json::from_str_strict, strict_json::StrictValue};

    /// The scan and the full parse give every line the same id.
    #[test]
    fn the_scan_and_the_parse_agree() {
        let lines = [
            (r#"{"id": "a", "scene": {}}"#, "a"),
            (r#"{"id": 7, "scene": null}"#, "7"),
            (r#"{"id": 1.5e3, "scene": {}, "vary": {}}"#, "1500.0"),
            (r#"{"id": null, "scene": {}}"#, "line-9"),
            (r#"{"id": [1], "scene": {}}"#, "line-9"),
            (r#"{"id": "b"}"#, "line-9"),
            (r#"{"object": {}, "fingers": []}"#, "line-9"),
            (r#"[1, 2]"#, "line-9"),
        ];
        for (text, want) in lines {
            assert_eq!(line_id(text, 9), want, "{text}");
            let StrictValue(v) = from_str_strict::<StrictValue>(text).unwrap();
            let parsed = v.as_object().map_or(default_id(9), |o| id_of(o, 9));
            assert_eq!(parsed, want, "{text}");
        }
        // Not JSON, a key twice, or text after the object: the line's number.
        for bad in [
            "{not json",
            r#"{"id": "a", "id": "b", "scene": {}}"#,
            r#"{"id": "a", "scene": {}} trailing"#,
        ] {
            assert_eq!(line_id(bad, 4), "line-4", "{bad}");
            assert!(from_str_strict::<StrictValue>(bad).is_err());
        }
    }

    #[test]
    fn duplicates_are_listed_with_their_lines() {
        let mut ix = InputIndex::default();
        for (k, id) in ["a", "b", "a", "c", "b", "a"].iter().enumerate() {
            ix.add(id.to_string(), k, k + 1).unwrap();
        }
        let e = ix.refuse_duplicates().unwrap_err().to_string();
        assert!(
            e.contains("`a` on lines 1, 3, 6") && e.contains("`b` on lines 2, 5"),
            "{e}"
        );
        assert_eq!(ix.position_of("c"), Some(3));
        assert_eq!(ix.scenes, 6);
    }
}
