//! A solution's JSON text (`grasp solve --json`, Python's `Solution.to_json`): pretty, one
//! value a line, as `serde_json::to_writer_pretty` writes it, except inside a fine patch's
//! `"element_fields"` (`grasp_model::COLUMNS_ABOVE_ELEMENTS`), where each field's array is
//! written on one line without spaces (`"pressure_pa": [0.0,1.5e6,...]`), about half the bytes
//! of one number a line. Serialised straight into the writer: nothing but the writer's buffer
//! is held in memory. Solutions without such a patch are written byte for byte as before.

use std::io::Write;

use serde::Serialize;
use serde_json::ser::{CompactFormatter, Formatter, PrettyFormatter};

use crate::solution_record::SolutionRecord;

/// Writes `record` as the solution's JSON text into `w` (see the module documentation).
pub fn write_solution_json<W: Write>(w: W, record: &SolutionRecord<'_>) -> serde_json::Result<()> {
    let mut ser = serde_json::Serializer::with_formatter(w, ColumnsFormatter::default());
    record.serialize(&mut ser)
}

/// The key whose object's arrays are written compactly.
const COLUMNS_KEY: &str = "element_fields";

/// Pretty, except the arrays inside a [`COLUMNS_KEY`] object, written compactly.
#[derive(Default)]
struct ColumnsFormatter {
    pretty: PrettyFormatter<'static>,
    compact: CompactFormatter,
    /// Containers open.
    depth: usize,
    /// The depth of the open columns object, when one is open.
    columns_at: Option<usize>,
    /// The object key being written, while one is.
    key: Option<String>,
    /// The next object is the columns object (its key was just written).
    columns_next: bool,
}

impl ColumnsFormatter {
    /// Inside the columns object's arrays.
    fn inside(&self) -> bool {
        self.columns_at.is_some_and(|d| self.depth > d)
    }
}

impl Formatter for ColumnsFormatter {
    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.depth += 1;
        match self.inside() {
            true => self.compact.begin_array(w),
            false => self.pretty.begin_array(w),
        }
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        let inside = self.inside();
        self.depth -= 1;
        match inside {
            true => self.compact.end_array(w),
            false => self.pretty.end_array(w),
        }
    }

    fn begin_array_value<W: ?Sized + Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        match self.inside() {
            true => self.compact.begin_array_value(w, first),
            false => self.pretty.begin_array_value(w, first),
        }
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        match self.inside() {
            true => self.compact.end_array_value(w),
            false => self.pretty.end_array_value(w),
        }
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.depth += 1;
        if std::mem::take(&mut self.columns_next) && self.columns_at.is_none() {
            self.columns_at = Some(self.depth);
        }
        match self.inside() {
            true => self.compact.begin_object(w),
            false => self.pretty.begin_object(w),
        }
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        let inside = self.inside();
        if self.columns_at == Some(self.depth) {
            self.columns_at = None;
        }
        self.depth -= 1;
        match inside {
            true => self.compact.end_object(w),
            false => self.pretty.end_object(w),
        }
    }

    fn begin_object_key<W: ?Sized + Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        match self.inside() {
            true => self.compact.begin_object_key(w, first),
            false => {
                self.key = Some(String::new());
                self.pretty.begin_object_key(w, first)
            }
        }
    }

    fn write_string_fragment<W: ?Sized + Write>(
        &mut self,
        w: &mut W,
        fragment: &str,
    ) -> std::io::Result<()> {
        if let Some(k) = self.key.as_mut() {
            k.push_str(fragment);
        }
        w.write_all(fragment.as_bytes())
    }

    fn end_object_key<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        if let Some(k) = self.key.take() {
            self.columns_next = k == COLUMNS_KEY;
        }
        match self.inside() {
            true => self.compact.end_object_key(w),
            false => self.pretty.end_object_key(w),
        }
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        match self.inside() {
            true => self.compact.begin_object_value(w),
            false => self.pretty.begin_object_value(w),
        }
    }

    fn end_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.columns_next = false;
        match self.inside() {
            true => self.compact.end_object_value(w),
            false => self.pretty.end_object_value(w),
        }
    }
}
