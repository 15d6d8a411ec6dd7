//! Every structural problem of a scene at once: a missing field, a key the format does not
//! know, a value of the wrong type or length, found by walking the parsed JSON against the
//! scene's JSON Schema ([`crate::scene::scene_format::scene_json_schema`]). The typed reader (serde) stops
//! at the first such problem; this walk runs when it has, so the user sees them all, each with
//! a fix taken from the field's documentation.
//!
//! The walk knows the part of JSON Schema the generated schema uses: `$ref` into `$defs`,
//! `type`, `properties`, `required`, `additionalProperties: false`, `items`, `prefixItems`,
//! `minItems`, `maxItems`, `const`, `enum`, `anyOf` and `oneOf`. Value ranges are not its
//! business: [`crate::scene::scene_validation`] checks them once the scene reads.

use serde_json::{Map, Value};

use crate::error::InputProblem;
use crate::scene::strict_json::describe;

/// The message's end for a value that fits none of a field's forms.
pub const NO_FORM_FITS: &str = "which is none of the forms this field takes";

/// The structural problems of `value` against `schema` (a root schema with `$defs`): depth
/// first, the keys of each object in alphabetical order (missing ones among them); empty when
/// it fits.
pub fn structural_problems(value: &Value, schema: &Value) -> Vec<InputProblem> {
    let mut out = Vec::new();
    Walk { root: schema }.check(value, schema, ".", &mut out);
    out
}

struct Walk<'a> {
    root: &'a Value,
}

impl<'a> Walk<'a> {
    /// `s` with a `$ref` replaced by its definition, the reference's own keys added where the
    /// definition has none (the definition's description says what forms the value takes).
    fn resolve(&self, s: &'a Value) -> Map<String, Value> {
        let mut out = Map::new();
        if let Some(name) = s
            .get("$ref")
            .and_then(Value::as_str)
            .and_then(|r| r.strip_prefix("#/$defs/"))
        {
            if let Some(Value::Object(def)) = self.root.get("$defs").and_then(|d| d.get(name)) {
                out.extend(def.iter().map(|(k, v)| (k.clone(), v.clone())));
            }
        }
        if let Value::Object(own) = s {
            for (k, v) in own {
                if k != "$ref" && !out.contains_key(k) {
                    out.insert(k.clone(), v.clone());
                }
            }
        }
        out
    }

    /// Problems of `v` at `path` against the schema node `s`.
    fn check(&self, v: &Value, s: &'a Value, path: &str, out: &mut Vec<InputProblem>) {
        let node = self.resolve(s);
        let hint = hint_of(&node);
        if let Some(branches) = node
            .get("anyOf")
            .or_else(|| node.get("oneOf"))
            .and_then(Value::as_array)
        {
            self.check_branches(v, branches, path, &hint, out);
            return;
        }
        if let Some(c) = node.get("const") {
            if v != c {
                let message = format!("is {}, expected {c}", describe(v));
                out.push(problem(path, message, &format!("write {c}"), &hint));
            }
            return;
        }
        if let Some(options) = node.get("enum").and_then(Value::as_array) {
            if !options.contains(v) {
                let names: Vec<String> = options.iter().map(Value::to_string).collect();
                let names = names.join(", ");
                let message = format!("is {}, expected one of {names}", describe(v));
                out.push(problem(
                    path,
                    message,
                    &format!("write one of {names}"),
                    &hint,
                ));
            }
            return;
        }
        if let Some(types) = node.get("type") {
            if !type_matches(v, types) {
                let words = type_words(types);
                let message = format!("is {}, expected {words}", describe(v));
                out.push(problem(path, message, &format!("write {words}"), &hint));
                return;
            }
        }
        match v {
            Value::Object(m) => self.check_object(m, &node, path, out),
            Value::Array(items) => self.check_array(items, &node, path, &hint, out),
            _ => {}
        }
    }

    /// A value that must fit one of `branches`: fine when one fits; otherwise the problems
    /// of the one branch it comes closest to (of its type, fewest problems, no tie), or one
    /// problem naming the forms.
    fn check_branches(
        &self,
        v: &Value,
        branches: &'a [Value],
        path: &str,
        hint: &str,
        out: &mut Vec<InputProblem>,
    ) {
        let mut tries: Vec<Vec<InputProblem>> = Vec::new();
        for b in branches {
            let mut p = Vec::new();
            self.check(v, b, path, &mut p);
            if p.is_empty() {
                return;
            }
            if self.accepts_kind(v, b) {
                tries.push(p);
            }
        }
        tries.sort_by_key(Vec::len);
        match tries.as_slice() {
            [best] => out.extend(best.iter().cloned()),
            [best, next, ..] if best.len() < next.len() => out.extend(best.iter().cloned()),
            _ => out.push(problem(
                path,
                format!("is {}, {NO_FORM_FITS}", describe(v)),
                "write one of its forms",
                hint,
            )),
        }
    }

    /// Whether the schema node `s` (through its alternatives) takes values of `v`'s JSON type.
    fn accepts_kind(&self, v: &Value, s: &'a Value) -> bool {
        let node = self.resolve(s);
        if let Some(branches) = node
            .get("anyOf")
            .or_else(|| node.get("oneOf"))
            .and_then(Value::as_array)
        {
            return branches.iter().any(|b| self.accepts_kind(v, b));
        }
        let same = |c: &Value| std::mem::discriminant(c) == std::mem::discriminant(v);
        if let Some(c) = node.get("const") {
            return same(c);
        }
        if let Some(options) = node.get("enum").and_then(Value::as_array) {
            return options.iter().any(same);
        }
        node.get("type").is_none_or(|t| type_matches(v, t))
    }

    fn check_object(
        &self,
        m: &Map<String, Value>,
        node: &Map<String, Value>,
        path: &str,
        out: &mut Vec<InputProblem>,
    ) {
        let empty = Map::new();
        let props = node
            .get("properties")
            .and_then(Value::as_object)
            .unwrap_or(&empty);
        let required = node.get("required").and_then(Value::as_array);
        let missing = required
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .filter(|k| !m.contains_key(*k));
        let mut keys: Vec<&str> = m.keys().map(String::as_str).chain(missing).collect();
        keys.sort_unstable();
        let closed = node.get("additionalProperties") == Some(&Value::Bool(false));
        for key in keys {
            match (m.get(key), props.get(key)) {
                (Some(value), Some(p)) => self.check(value, p, &join(path, key), out),
                (Some(_), None) if closed => out.push(unknown_key(path, key, props)),
                (Some(_), None) => {}
                (None, p) => {
                    let hint = p.map_or(String::new(), |p| hint_of(&self.resolve(p)));
                    let fix = fix_text(&format!("add `{key}`"), &hint);
                    out.push(InputProblem::new(join(path, key), "is missing", fix));
                }
            }
        }
    }

    fn check_array(
        &self,
        items: &[Value],
        node: &Map<String, Value>,
        path: &str,
        hint: &str,
        out: &mut Vec<InputProblem>,
    ) {
        let n = items.len() as u64;
        let min = node.get("minItems").and_then(Value::as_u64);
        let max = node.get("maxItems").and_then(Value::as_u64);
        let count = match (min, max) {
            (Some(a), Some(b)) if a == b => format!("{a}"),
            (Some(a), Some(b)) => format!("{a} to {b}"),
            (Some(a), None) => format!("at least {a}"),
            (None, Some(b)) => format!("at most {b}"),
            (None, None) => String::new(),
        };
        if min.is_some_and(|a| n < a) || max.is_some_and(|b| n > b) {
            let message = format!("has {n} item(s), expected {count}");
            out.push(problem(
                path,
                message,
                &format!("give {count} item(s)"),
                hint,
            ));
            return;
        }
        let prefix = node.get("prefixItems").and_then(Value::as_array);
        for (i, item) in items.iter().enumerate() {
            let schema = prefix
                .and_then(|p| p.get(i))
                .or_else(|| node.get("items").filter(|s| s.is_object()));
            if let Some(s) = schema {
                self.check(item, s, &format!("{}[{i}]", root_less(path)), out);
            }
        }
    }
}

/// A problem whose fix is `action` and what the field's documentation says it holds.
fn problem(path: &str, message: String, action: &str, hint: &str) -> InputProblem {
    InputProblem::new(path, message, fix_text(action, hint))
}

/// `action; the field: hint`, or the action and where the format is described.
fn fix_text(action: &str, hint: &str) -> String {
    match hint {
        "" => format!("{action} (see `grasp schema`)"),
        h => format!("{action}; the field: {h}"),
    }
}

/// A key the object does not have, with the closest known key.
fn unknown_key(path: &str, key: &str, props: &Map<String, Value>) -> InputProblem {
    let known: Vec<&str> = props.keys().map(String::as_str).collect();
    let closest = known
        .iter()
        .map(|k| (edit_distance(key, k), *k))
        .min()
        .filter(|(d, k)| *d <= 2.max(k.len() / 3));
    let guess = closest.map_or(String::new(), |(_, k)| format!("did you mean `{k}`? "));
    InputProblem::new(
        join(path, key),
        "is not a field here",
        format!(
            "{guess}remove it or correct its spelling (the fields here: {})",
            known.join(", ")
        ),
    )
}

/// The first sentence of a schema node's description: what the field is (a hint for the
/// fix), with line breaks joined.
fn hint_of(node: &Map<String, Value>) -> String {
    let text = node
        .get("description")
        .and_then(Value::as_str)
        .unwrap_or("")
        .replace('\n', " ");
    // A sentence ends at ". " before a capital ("eq. 40" does not end one).
    let end = text
        .match_indices(". ")
        .find(|(i, _)| text[i + 2..].starts_with(|c: char| c.is_uppercase()))
        .map_or(text.len(), |(i, _)| i + 1);
    let first = text[..end].trim().trim_end_matches('.');
    let mut chars = first.chars();
    match chars.next() {
        Some(c) => c.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}

/// Whether `v` has one of the JSON Schema `types` (a name or a list of names).
fn type_matches(v: &Value, types: &Value) -> bool {
    let one = |t: &str| match t {
        "null" => v.is_null(),
        "boolean" => v.is_boolean(),
        "string" => v.is_string(),
        "array" => v.is_array(),
        "object" => v.is_object(),
        "number" => v.is_number(),
        "integer" => v.is_u64() || v.is_i64(),
        _ => true,
    };
    match types {
        Value::String(t) => one(t),
        Value::Array(ts) => ts.iter().filter_map(Value::as_str).any(one),
        _ => true,
    }
}

/// The types as words: `a number or null`.
fn type_words(types: &Value) -> String {
    let word = |t: &str| match t {
        "null" => "null".to_string(),
        "integer" => "an integer".to_string(),
        "array" | "object" => format!("an {t}"),
        t => format!("a {t}"),
    };
    match types {
        Value::String(t) => word(t),
        Value::Array(ts) => ts
            .iter()
            .filter_map(Value::as_str)
            .map(word)
            .collect::<Vec<_>>()
            .join(" or "),
        _ => "another type".to_string(),
    }
}

/// `path.key`, or `key` at the top.
fn join(path: &str, key: &str) -> String {
    match path {
        "." => key.to_string(),
        p => format!("{p}.{key}"),
    }
}

/// The path without the top-level marker (`.` becomes empty), to append `[i]` to.
fn root_less(path: &str) -> &str {
    if path == "." {
        ""
    } else {
        path
    }
}

/// Levenshtein distance of two keys (short ASCII words).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let here = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb))
                .min(row[j] + 1)
                .min(here + 1);
            prev = here;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn scene_schema() -> Value {
        crate::scene::scene_format::scene_json_schema()
            .as_value()
            .clone()
    }

    fn example(name: &str) -> Value {
        let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    /// Every scene of `examples/` and `examples/mujoco/` (schedules, MuJoCo material maps,
    /// reports and states are not scenes), found by listing the folders.
    #[test]
    fn every_bundled_example_fits_the_schema() {
        let not_a_scene = [
            ".schedule.json",
            ".materials.json",
            ".report.json",
            ".state.json",
        ];
        let mut checked = 0;
        for folder in ["", "mujoco/"] {
            let dir = format!("{}/../../examples/{folder}", env!("CARGO_MANIFEST_DIR"));
            for entry in std::fs::read_dir(dir).unwrap() {
                let name = format!("{folder}{}", entry.unwrap().file_name().to_string_lossy());
                if !name.ends_with(".json") || not_a_scene.iter().any(|s| name.ends_with(s)) {
                    continue;
                }
                let p = structural_problems(&example(&name), &scene_schema());
                assert!(p.is_empty(), "{name}: {p:?}");
                checked += 1;
            }
        }
        assert!(checked >= 20, "{checked} scenes");
    }

    #[test]
    fn every_structural_problem_is_listed_with_a_fix() {
        let mut v = example("cube_a.json");
        let fingers = v["fingers"].as_array_mut().unwrap();
        fingers[0].as_object_mut().unwrap().remove("material");
        fingers[1]["nromal"] = json!([0, 1, 0]);
        fingers[2]["friction"] = json!({"mu": "high"});
        v["object"]["center_of_mass"] = json!([0.0, 0.0]);
        v["model"] = json!("coulumb");
        let p = structural_problems(&v, &scene_schema());
        let paths: Vec<&str> = p.iter().map(|q| q.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "fingers[0].material",
                "fingers[1].nromal",
                "fingers[2].friction.mu",
                "model",
                "object.center_of_mass",
            ],
            "{p:#?}"
        );
        assert_eq!(p[0].message, "is missing");
        assert!(
            p[0].fix.starts_with("add `material`; the field: "),
            "{}",
            p[0].fix
        );
        assert!(
            p[1].fix.starts_with("did you mean `normal`?"),
            "{}",
            p[1].fix
        );
        assert!(
            p[2].message.contains("expected a number"),
            "{}",
            p[2].message
        );
        assert!(p[3].message.contains("\"coulumb\""), "{}", p[3].message);
        assert_eq!(p[4].message, "has 2 item(s), expected 3");
        assert!(p.iter().all(|q| !q.fix.is_empty()), "{p:#?}");
    }

    #[test]
    fn a_value_of_no_known_form_is_one_problem() {
        let mut v = example("cube_a.json");
        v["fingers"][0]["friction"] = json!(0.4);
        let p = structural_problems(&v, &scene_schema());
        assert_eq!(p.len(), 1, "{p:#?}");
        assert_eq!(p[0].path, "fingers[0].friction");
        assert!(
            p[0].message.contains("none of the forms"),
            "{}",
            p[0].message
        );
        assert!(p[0].fix.contains("{\"mu\": c}"), "{}", p[0].fix);
        assert!(p[0].fix.ends_with("(thesis eq. 40)"), "{}", p[0].fix);
        assert!(p[0].fix.ends_with("(thesis eq. 40)"), "{}", p[0].fix);
    }

    #[test]
    fn edit_distance_counts_single_edits() {
        assert_eq!(edit_distance("nromal", "normal"), 2);
        assert_eq!(edit_distance("normal", "normal"), 0);
        assert_eq!(edit_distance("tip", "tips"), 1);
    }
}
