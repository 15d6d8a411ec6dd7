//! Load profiles from CSV files: a header row, then comma-separated numbers.
//!
//! The file is read through `grasp_io::InputFile` (a regular file, checked before opening,
//! so a FIFO never blocks and a device such as `/dev/zero` is refused; at most
//! `grasp_io::LOAD_PROFILE`'s 64 MiB, bounded while reading).

use std::path::Path;

use grasp_io::{read_text, FileIdentity, LOAD_PROFILE};

type ProfileError = (&'static str, String, String);

/// Columns a message lists when a named one is missing (the rest are counted).
const LISTED_COLUMNS: usize = 20;

/// Characters of a cell or column name a message quotes (a longer one is cut with `...`).
const QUOTED_CHARS: usize = 40;

/// `text` between backticks for a message, cut to [`QUOTED_CHARS`].
fn quoted(text: &str) -> String {
    match text.char_indices().nth(QUOTED_CHARS) {
        Some((cut, _)) => format!("`{}...`", &text[..cut]),
        None => format!("`{text}`"),
    }
}

/// The text of a profile and the identity of the file read.
fn read_profile_file(path: &Path) -> Result<(String, FileIdentity), ProfileError> {
    read_text(path, LOAD_PROFILE).map_err(|e| ("path", e.message, e.fix))
}

/// Reads `(time s, load N)` rows from the named columns, with the identity of the file read.
/// On failure returns `(field, message, fix)` where `field` is the schedule field to blame
/// (`path`, `time_column` or `load_column`).
pub fn read_profile_csv_noting(
    path: &Path,
    time_column: &str,
    load_column: &str,
) -> Result<(Vec<(f64, f64)>, FileIdentity), ProfileError> {
    let (text, identity) = read_profile_file(path)?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Err((
            "path",
            format!("{} is empty", path.display()),
            "add a header row and data".into(),
        ));
    };
    let cols: Vec<&str> = header.split(',').map(|c| c.trim()).collect();
    let find = |name: &str, field: &'static str| {
        cols.iter().position(|c| *c == name).ok_or_else(|| {
            let mut listed: Vec<String> = cols
                .iter()
                .take(LISTED_COLUMNS)
                .map(|c| quoted(c))
                .collect();
            if cols.len() > LISTED_COLUMNS {
                listed.push(format!("and {} more", cols.len() - LISTED_COLUMNS));
            }
            (
                field,
                format!(
                    "column {} is not in {} (columns: {})",
                    quoted(name),
                    path.display(),
                    listed.join(", ")
                ),
                "name an existing column".to_string(),
            )
        })
    };
    let (ti, li) = (
        find(time_column, "time_column")?,
        find(load_column, "load_column")?,
    );
    let mut rows = Vec::new();
    for (n, line) in lines {
        let cells: Vec<&str> = line.split(',').map(|c| c.trim()).collect();
        let num = |i: usize, what: &str| -> Result<f64, ProfileError> {
            let cell = cells.get(i).copied();
            cell.and_then(|c| c.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    let found = match cell {
                        Some(c) => format!("{} is not a finite number", quoted(c)),
                        None => "is missing (the row has too few cells)".to_string(),
                    };
                    (
                        "path",
                        format!("line {} of {}: the {what} {found}", n + 1, path.display()),
                        "give finite numbers in every row".to_string(),
                    )
                })
        };
        rows.push((num(ti, "time")?, num(li, "load")?));
    }
    if rows.is_empty() {
        return Err((
            "path",
            format!("{} has no data rows", path.display()),
            "add rows".into(),
        ));
    }
    Ok((rows, identity))
}
