//! Load profiles from CSV files: a header row, then comma-separated numbers.
//!
//! Only a regular file is read (checked before opening, so a FIFO never blocks and a device
//! such as `/dev/zero` is refused), of at most [`MAX_PROFILE_BYTES`].

use std::io::Read;
use std::path::Path;

/// Largest CSV profile read, bytes.
pub const MAX_PROFILE_BYTES: u64 = 64 * 1024 * 1024;

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

/// The text of a profile: a regular file (symlinks followed) of at most
/// [`MAX_PROFILE_BYTES`], read without blocking on pipes or growing on devices.
fn read_regular_file(path: &Path) -> Result<String, ProfileError> {
    let err = |message: String, fix: &str| ("path", message, fix.to_string());
    let meta = std::fs::metadata(path).map_err(|e| {
        err(
            format!("cannot read {}: {e}", path.display()),
            "give an existing CSV file",
        )
    })?;
    if !meta.is_file() {
        return Err(err(
            format!(
                "{} is not a regular file (a folder, a pipe or a device)",
                path.display()
            ),
            "give a CSV file",
        ));
    }
    if meta.len() > MAX_PROFILE_BYTES {
        return Err(err(
            format!(
                "{} has {} bytes, more than the {} MiB a profile may have",
                path.display(),
                meta.len(),
                MAX_PROFILE_BYTES / 1048576
            ),
            "thin out the profile (the schedule interpolates between rows)",
        ));
    }
    let file = std::fs::File::open(path).map_err(|e| {
        err(
            format!("cannot read {}: {e}", path.display()),
            "give a readable CSV file",
        )
    })?;
    let mut bytes = Vec::new();
    file.take(MAX_PROFILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| {
            err(
                format!("cannot read {}: {e}", path.display()),
                "give a readable CSV file",
            )
        })?;
    if bytes.len() as u64 > MAX_PROFILE_BYTES {
        return Err(err(
            format!(
                "{} grew beyond {} MiB while being read",
                path.display(),
                MAX_PROFILE_BYTES / 1048576
            ),
            "give a CSV file that is not being written",
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        err(
            format!("{} is not UTF-8 text: {e}", path.display()),
            "save the profile as plain (UTF-8) text",
        )
    })
}

/// Reads `(time s, load N)` rows from the named columns. On failure returns
/// `(field, message, fix)` where `field` is the schedule field to blame (`path`,
/// `time_column` or `load_column`).
pub fn read_profile_csv(
    path: &Path,
    time_column: &str,
    load_column: &str,
) -> Result<Vec<(f64, f64)>, ProfileError> {
    let text = read_regular_file(path)?;
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
    Ok(rows)
}
