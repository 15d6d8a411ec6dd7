//! Strict reading of the JSON input files (scenes, schedules): one document and nothing after
//! it, no key given twice, and the real field error of an enum whose variant is chosen by its
//! shape (`"rigid"` or `{...}`, `{"mu"}` or `{"table"}`, ...), with its full JSON path.
//!
//! The enums buffer their value ([`StrictValue`]: like `serde_json::Value`, but refusing
//! duplicate keys), pick the variant the value's shape asks for, and deserialize it with path
//! tracking. The inner path travels in the error message behind a marker and is joined to the
//! outer path by [`from_str_strict`].

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, DeserializeOwned, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use serde_json::{Map, Value};

/// Where a JSON input went wrong: path (`.` for the whole document) and message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JsonError {
    /// JSON path, e.g. `fingers[0].friction.mu`.
    pub path: String,
    /// What is wrong.
    pub message: String,
}

/// Marks the start and end of an inner path carried in an error message.
const INNER: char = '\u{1f}';

/// Parses one JSON document of type `T`: field errors carry their full path; anything but
/// whitespace after the document is an error naming its line and column.
pub fn from_str_strict<T: DeserializeOwned>(text: &str) -> Result<T, JsonError> {
    let mut de = serde_json::Deserializer::from_str(text);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let inner = e.inner();
        if inner.is_syntax() || inner.is_eof() {
            return syntax_error(text, inner);
        }
        let (path, message) = join_path(&e.path().to_string(), &inner.to_string());
        JsonError { path, message }
    })?;
    de.end().map_err(|e| JsonError {
        path: "(after the document)".into(),
        message: format!(
            "{e}: a file holds one JSON document; remove what follows its closing brace"
        ),
    })?;
    Ok(value)
}

/// Deserializes `T` from a value already parsed (strictly, with [`StrictValue`]), so a document
/// inside a larger one (a batch line's scene) is not parsed again; field errors carry their
/// full path, as with [`from_str_strict`].
pub fn from_value_strict<T: DeserializeOwned>(value: Value) -> Result<T, JsonError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let (path, message) = join_path(&e.path().to_string(), &e.inner().to_string());
        JsonError { path, message }
    })
}

/// A syntax error, located by line and column; a `//` or `/* */` comment at or before it is
/// named as the cause (JSON has none: a common paste from commented examples).
fn syntax_error(text: &str, e: &serde_json::Error) -> JsonError {
    let at = (e.line(), e.column());
    match first_comment(text) {
        Some((line, column, mark)) if (line, column) <= at => JsonError {
            path: format!("line {line}, column {column}"),
            message: format!(
                "JSON has no comments, and `{mark}` at line {line} column {column} starts one; \
                 remove every comment (the commented example in docs/guide/scenes.md shows alternatives: keep \
                 one, delete the rest)"
            ),
        },
        _ => JsonError {
            path: format!("line {}, column {}", at.0, at.1),
            message: e.to_string(),
        },
    }
}

/// Line and column (from 1) of the first `//` or `/*` outside a string, and which.
fn first_comment(text: &str) -> Option<(usize, usize, &'static str)> {
    let (mut line, mut column) = (1, 0);
    let (mut in_string, mut escaped) = (false, false);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        column += 1;
        match c {
            '\n' => (line, column) = (line + 1, 0),
            _ if in_string && escaped => escaped = false,
            '\\' if in_string => escaped = true,
            '"' => in_string = !in_string,
            '/' if !in_string => match chars.peek() {
                Some('/') => return Some((line, column, "//")),
                Some('*') => return Some((line, column, "/*")),
                _ => {}
            },
            _ => {}
        }
    }
    None
}

/// Joins an outer path and a message that may carry an inner path (from [`variant`]): the
/// full path and the message without the marker.
pub fn join_path(outer: &str, message: &str) -> (String, String) {
    let Some(rest) = message.strip_prefix(INNER) else {
        return (outer.to_string(), message.to_string());
    };
    let Some((inner, msg)) = rest.split_once(INNER) else {
        return (outer.to_string(), rest.to_string());
    };
    let outer = if outer == "." { "" } else { outer };
    let path = match inner {
        "" | "." => outer.to_string(),
        i if i.starts_with('[') || outer.is_empty() => format!("{outer}{i}"),
        i => format!("{outer}.{i}"),
    };
    let path = if path.is_empty() { ".".into() } else { path };
    join_path(&path, msg)
}

/// Deserializes the variant type `T` from a buffered value; its errors keep their path inside
/// the value (joined to the outer path by [`from_str_strict`]).
pub fn variant<T: DeserializeOwned, E: de::Error>(value: Value) -> Result<T, E> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let inner = e.path().to_string();
        let message = e.inner().to_string();
        // Nested enums already carry their inner path: prepend ours.
        let (path, message) = join_path(&inner, &message);
        E::custom(format!("{INNER}{path}{INNER}{message}"))
    })
}

/// The JSON type of a value, for messages.
pub fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// A value as a message names it: its type, the string, or an object's keys.
pub fn describe(v: &Value) -> String {
    match v {
        Value::String(s) => format!("the string \"{s}\""),
        Value::Object(m) if !m.is_empty() => format!(
            "an object with the key(s) {}",
            m.keys()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        v => kind(v).to_string(),
    }
}

/// A JSON value that refuses an object with the same key twice.
pub struct StrictValue(pub Value);

impl<'de> Deserialize<'de> for StrictValue {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(StrictVisitor).map(StrictValue)
    }
}

struct StrictVisitor;

impl<'de> Visitor<'de> for StrictVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_string()))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        StrictValue::deserialize(d).map(|v| v.0)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut out = Vec::new();
        while let Some(StrictValue(v)) = seq.next_element()? {
            out.push(v);
        }
        Ok(Value::Array(out))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            if out.contains_key(&key) {
                return Err(de::Error::custom(format!("duplicate field `{key}`")));
            }
            let StrictValue(v) = map.next_value()?;
            out.insert(key, v);
        }
        Ok(Value::Object(out))
    }
}

/// Deserializes a map with string keys, refusing a key given twice (serde's maps keep the
/// last silently). Use with `#[serde(deserialize_with = "unique_keys")]`.
pub fn unique_keys<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct UniqueVisitor<V>(std::marker::PhantomData<V>);
    impl<'de, V: Deserialize<'de>> Visitor<'de> for UniqueVisitor<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("an object")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<String>()? {
                if out.contains_key(&key) {
                    return Err(de::Error::custom(format!(
                        "`{key}` is given twice; fix: give each name once (merge the two \
                         entries)"
                    )));
                }
                out.insert(key, map.next_value()?);
            }
            Ok(out)
        }
    }
    d.deserialize_map(UniqueVisitor(std::marker::PhantomData))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Inner {
        #[allow(dead_code)]
        x: f64,
    }

    #[derive(Debug)]
    struct Wrap(#[allow(dead_code)] Inner);

    impl<'de> Deserialize<'de> for Wrap {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let StrictValue(v) = StrictValue::deserialize(d)?;
            variant(v).map(Wrap)
        }
    }

    #[derive(Debug, Deserialize)]
    struct Outer {
        #[allow(dead_code)]
        a: Vec<Wrap>,
    }

    #[test]
    fn inner_paths_join_the_outer_path() {
        let e = from_str_strict::<Outer>(r#"{"a": [{"x": 1}, {"x": "no"}]}"#).unwrap_err();
        assert_eq!(e.path, "a[1].x", "{e:?}");
        assert!(e.message.contains("invalid type"), "{e:?}");
    }

    #[test]
    fn a_comment_is_named_as_the_cause_of_a_syntax_error() {
        let text = "{ \"a\": [],          // a list\n  \"b\": 1 }";
        let e = from_str_strict::<Value>(text).unwrap_err();
        assert_eq!(e.path, "line 1, column 21", "{e:?}");
        assert!(e.message.starts_with("JSON has no comments"), "{e:?}");
        let e = from_str_strict::<Value>("{\"a\": 1 /* one */}").unwrap_err();
        assert!(e.message.contains("`/*`"), "{e:?}");
        // A `//` inside a string is text, and the error is the real one.
        let e = from_str_strict::<Value>("{\"url\": \"http://x\", }").unwrap_err();
        assert!(!e.message.contains("comment"), "{e:?}");
        assert!(e.path.starts_with("line 1, column "), "{e:?}");
    }

    #[test]
    fn trailing_data_and_duplicate_keys_are_refused() {
        let e = from_str_strict::<Outer>(r#"{"a": []} {"a": []}"#).unwrap_err();
        assert!(e.message.contains("trailing characters at line 1"), "{e:?}");
        let e = from_str_strict::<Outer>(r#"{"a": [{"x": 1, "x": 2}]}"#).unwrap_err();
        assert!(e.message.contains("duplicate field `x`"), "{e:?}");
    }
}
