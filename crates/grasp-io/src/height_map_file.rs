//! Height map files of `fingers[i].texture.heights`: NumPy `.npy` (2-D; `f64`, `f32` or
//! integers of any size and byte order; C or Fortran order; with `npyz`) and `.csv` (one row
//! of the map per line, numbers separated by commas, or by blanks when a line has no comma;
//! no header), read through [`crate::input_file`] (a regular file of at most
//! [`HEIGHT_MAP_FILE`]'s 256 MiB) and parsed from memory. Heights are in metres, rows along
//! `t1`; a map holds at most [`MAX_PIXELS`] heights.

use std::path::Path;

use grasp_model::{FileProblem, HeightGrid};
use npyz::{DType, NpyFile, Order, TypeChar};

use crate::input_file::{read_bytes, FileIdentity, HEIGHT_MAP_FILE};

/// Most heights in one map (8192 x 4096: 256 MiB of `f64`).
pub const MAX_PIXELS: usize = 1 << 25;

/// What the fix of a malformed map says.
const MAP_FIX: &str = "give a 2-D array of heights in metres: a .npy file (numpy.save) or a \
                       .csv file with one row of the map (along t1) per line and no header";

fn problem(path: &Path, message: impl std::fmt::Display, fix: &str) -> FileProblem {
    FileProblem {
        message: format!("{}: {message}", path.display()),
        fix: fix.into(),
    }
}

/// The height map in the file at `path` (`.npy` or `.csv`), with the identity of the file read.
pub fn read_height_map(path: &Path) -> Result<(HeightGrid, FileIdentity), FileProblem> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if ext != "npy" && ext != "csv" {
        return Err(problem(
            path,
            format!("unknown height map format `.{ext}`"),
            "give a .npy or .csv file",
        ));
    }
    let (bytes, identity) = read_bytes(path, HEIGHT_MAP_FILE).map_err(|e| FileProblem {
        message: e.message,
        fix: format!(
            "{} (the path is relative to the scene file's folder)",
            e.fix
        ),
    })?;
    let grid = if ext == "npy" {
        parse_npy(&bytes)
    } else {
        let text = std::str::from_utf8(&bytes).map_err(|e| format!("is not UTF-8 text: {e}"));
        text.and_then(parse_csv)
    }
    .map_err(|message| problem(path, message, MAP_FIX))?;
    Ok((grid, identity))
}

/// The heights of a `.npy` file's bytes.
pub fn parse_npy(bytes: &[u8]) -> Result<HeightGrid, String> {
    let npy = NpyFile::new(bytes).map_err(|e| format!("is not a readable .npy file: {e}"))?;
    let &[rows, cols] = npy.shape() else {
        return Err(format!(
            "holds an array of shape {:?}, not a 2-D one",
            npy.shape()
        ));
    };
    let (rows, cols) = (rows as usize, cols as usize);
    check_size(rows, cols)?;
    let order = npy.order();
    let DType::Plain(t) = npy.dtype() else {
        return Err(format!(
            "holds records of {}, not numbers",
            npy.dtype().descr()
        ));
    };
    let bad = || format!("holds {t}, not floats or integers");
    let read = |e: std::io::Error| format!("is not a readable .npy file: {e}");
    let values: Vec<f64> = match (t.type_char(), t.size_field()) {
        (TypeChar::Float, 8) => npy.into_vec::<f64>().map_err(read)?,
        (TypeChar::Float, 4) => widen(npy.into_vec::<f32>().map_err(read)?),
        (TypeChar::Int, 1) => widen(npy.into_vec::<i8>().map_err(read)?),
        (TypeChar::Int, 2) => widen(npy.into_vec::<i16>().map_err(read)?),
        (TypeChar::Int, 4) => widen(npy.into_vec::<i32>().map_err(read)?),
        (TypeChar::Int, 8) => npy
            .into_vec::<i64>()
            .map_err(read)?
            .iter()
            .map(|&x| x as f64)
            .collect(),
        (TypeChar::Uint, 1) => widen(npy.into_vec::<u8>().map_err(read)?),
        (TypeChar::Uint, 2) => widen(npy.into_vec::<u16>().map_err(read)?),
        (TypeChar::Uint, 4) => widen(npy.into_vec::<u32>().map_err(read)?),
        (TypeChar::Uint, 8) => npy
            .into_vec::<u64>()
            .map_err(read)?
            .iter()
            .map(|&x| x as f64)
            .collect(),
        _ => return Err(bad()),
    };
    if values.len() != rows * cols {
        return Err(format!(
            "holds {} values, not its shape's {rows} x {cols}",
            values.len()
        ));
    }
    let heights_m = match order {
        Order::C => values,
        // Fortran order: the first index runs fastest.
        Order::Fortran => (0..rows * cols)
            .map(|k| values[(k % cols) * rows + k / cols])
            .collect(),
    };
    Ok(HeightGrid {
        rows,
        cols,
        heights_m,
    })
}

/// Numbers of a type that `f64` holds exactly.
fn widen<T: Copy + Into<f64>>(v: Vec<T>) -> Vec<f64> {
    v.into_iter().map(Into::into).collect()
}

fn check_size(rows: usize, cols: usize) -> Result<(), String> {
    if rows == 0 || cols == 0 {
        return Err(format!("holds a {rows} x {cols} array: no heights"));
    }
    if rows.saturating_mul(cols) > MAX_PIXELS {
        return Err(format!(
            "holds {rows} x {cols} heights, more than {MAX_PIXELS}"
        ));
    }
    Ok(())
}

/// The heights of a `.csv` file's text: one row per line (blank lines skipped), cells
/// separated by commas (or blanks on a line without a comma); a byte-order mark before the
/// first line (as spreadsheets write) is skipped. A cell that is not a number is refused for
/// what it is: empty (a trailing comma), quoted, beyond the range of a number (`1e400`), or on
/// the first line, a header.
pub fn parse_csv(text: &str) -> Result<HeightGrid, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut heights_m = Vec::new();
    let (mut rows, mut cols) = (0usize, 0usize);
    for (number, line) in text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())) {
        if line.is_empty() {
            continue;
        }
        let cells: Vec<&str> = match line.contains(',') {
            true => line.split(',').map(str::trim).collect(),
            false => line.split_whitespace().collect(),
        };
        let values = csv_row(&cells, number, rows == 0, line)?;
        if rows > 0 && values.len() != cols {
            return Err(format!(
                "line {number} has {} numbers, the lines before it {cols}: every row of the \
                 map needs the same count",
                values.len()
            ));
        }
        cols = values.len();
        rows += 1;
        check_size(rows, cols)?;
        heights_m.extend(values);
    }
    check_size(rows, cols)?;
    Ok(HeightGrid {
        rows,
        cols,
        heights_m,
    })
}

/// The numbers of one line's `cells` (line `number`, the map's first row when `first`), or
/// what the first cell that is not one is.
fn csv_row(cells: &[&str], number: usize, first: bool, line: &str) -> Result<Vec<f64>, String> {
    let mut values = Vec::with_capacity(cells.len());
    for (c, cell) in cells.iter().enumerate() {
        let at = format!("line {number}, column {}", c + 1);
        // A number between quotes (a spreadsheet's text cell), not a quoted word.
        let quoted = ['"', '\''].iter().any(|&q| {
            cell.len() >= 2
                && cell.starts_with(q)
                && cell.ends_with(q)
                && cell[1..cell.len() - 1].trim().parse::<f64>().is_ok()
        });
        match cell.parse::<f64>() {
            Ok(x) if x.is_infinite() && !cell.to_ascii_lowercase().contains("inf") => {
                return Err(format!(
                    "{at}: `{}` is beyond the range of a number (magnitudes up to about \
                     1.8e308); heights are in metres",
                    shorten(cell)
                ))
            }
            Ok(x) => values.push(x),
            Err(_) if cell.is_empty() && c + 1 == cells.len() => {
                return Err(format!(
                    "line {number} ends with a comma (an empty last cell): remove the trailing \
                     commas"
                ))
            }
            Err(_) if cell.is_empty() => {
                return Err(format!(
                    "{at} is empty (two commas in a row): give a number"
                ))
            }
            Err(_) if quoted => {
                return Err(format!(
                    "{at}: `{}` is quoted: write the numbers without quotes",
                    shorten(cell)
                ))
            }
            Err(_) if first => {
                return Err(format!(
                    "starts with a header line (`{}`): remove it, the file holds heights only",
                    shorten(line)
                ))
            }
            Err(_) => return Err(format!("{at}: `{}` is not a number", shorten(cell))),
        }
    }
    Ok(values)
}

/// At most 40 characters of `s`, for messages.
fn shorten(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}...", &s[..i]),
        None => s.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version 1.0 `.npy` file of `shape`, dtype `descr`, holding `data` (already encoded).
    fn npy(descr: &str, fortran: bool, shape: &[usize], data: &[u8]) -> Vec<u8> {
        let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
        let shape = match dims.len() {
            1 => format!("({},)", dims[0]),
            _ => format!("({})", dims.join(", ")),
        };
        let mut header = format!(
            "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
            if fortran { "True" } else { "False" }
        );
        // Magic, version and length (10 bytes), the header padded to 64 bytes with a newline.
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend((header.len() as u16).to_le_bytes());
        out.extend(header.as_bytes());
        out.extend(data);
        out
    }

    #[test]
    fn npy_of_every_number_type_and_order() {
        // The 2 x 3 map [[0, 1, 2], [10, 11, 12]].
        let want = [0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        let c_order = [0u8, 1, 2, 10, 11, 12];
        let f_order = [0u8, 10, 1, 11, 2, 12];
        for (fortran, data) in [(false, c_order), (true, f_order)] {
            let bytes: Vec<u8> = data
                .iter()
                .flat_map(|x| (*x as f64).to_le_bytes())
                .collect();
            let g = parse_npy(&npy("<f8", fortran, &[2, 3], &bytes)).unwrap();
            assert_eq!((g.rows, g.cols, &g.heights_m[..]), (2, 3, &want[..]));
            let bytes: Vec<u8> = data
                .iter()
                .flat_map(|x| (*x as f32).to_be_bytes())
                .collect();
            let g = parse_npy(&npy(">f4", fortran, &[2, 3], &bytes)).unwrap();
            assert_eq!(g.heights_m, want);
            let g = parse_npy(&npy("|u1", fortran, &[2, 3], &data)).unwrap();
            assert_eq!(g.heights_m, want);
            let bytes: Vec<u8> = data
                .iter()
                .flat_map(|x| (-(*x as i64)).to_le_bytes())
                .collect();
            let g = parse_npy(&npy("<i8", fortran, &[2, 3], &bytes)).unwrap();
            assert_eq!(g.heights_m, want.map(|x| -x));
        }
    }

    #[test]
    fn malformed_npy_files_are_refused_with_what_is_wrong() {
        let one_d = npy("<f8", false, &[2], &[0; 16]);
        assert!(parse_npy(&one_d).unwrap_err().contains("not a 2-D one"));
        let complex = npy("<c16", false, &[1, 1], &[0; 16]);
        assert!(parse_npy(&complex)
            .unwrap_err()
            .contains("not floats or integers"));
        let short = npy("<f8", false, &[2, 2], &[0; 16]);
        assert!(parse_npy(&short).is_err());
        let empty = npy("<f8", false, &[0, 3], &[]);
        assert!(parse_npy(&empty).unwrap_err().contains("no heights"));
        assert!(parse_npy(b"not numpy")
            .unwrap_err()
            .contains("not a readable .npy"));
    }

    #[test]
    fn csv_rows_with_commas_or_blanks() {
        let g = parse_csv("1e-6, 2e-6,3e-6\n\n4e-6,5e-6,6e-6\n").unwrap();
        assert_eq!((g.rows, g.cols), (2, 3));
        assert_eq!(g.heights_m, [1e-6, 2e-6, 3e-6, 4e-6, 5e-6, 6e-6]);
        let g = parse_csv("1 2\n3 4").unwrap();
        assert_eq!(g.heights_m, [1.0, 2.0, 3.0, 4.0]);
    }

    #[test]
    fn csv_headers_ragged_rows_and_words_are_refused() {
        let e = parse_csv("x,y\n1,2\n").unwrap_err();
        assert!(
            e.contains("header line (`x,y`)") && e.contains("remove it"),
            "{e}"
        );
        let e = parse_csv("1,2\n3\n").unwrap_err();
        assert!(e.contains("line 2 has 1 numbers"), "{e}");
        let e = parse_csv("1,2\n3,abc\n").unwrap_err();
        assert!(e.contains("line 2, column 2: `abc`"), "{e}");
        let e = parse_csv("1,,2\n").unwrap_err();
        assert!(
            e.contains("line 1, column 2 is empty"),
            "an empty cell on the first line: {e}"
        );
        assert!(parse_csv("\n\n").unwrap_err().contains("no heights"));
    }

    /// A byte-order mark, trailing commas, quoted numbers and a number beyond `f64`'s range
    /// are each named for what they are, never called a header line nor read as `inf`.
    #[test]
    fn csv_bom_trailing_commas_quotes_and_overflow_are_named_not_called_a_header() {
        let g = parse_csv("\u{feff}1e-6,2e-6\n3e-6,4e-6\n").unwrap();
        assert_eq!(g.heights_m, [1e-6, 2e-6, 3e-6, 4e-6]);
        for (text, words) in [
            ("1e-6,2e-6,\n3e-6,4e-6,\n", "line 1 ends with a comma"),
            ("1e-6,2e-6\n3e-6,4e-6,\n", "line 2 ends with a comma"),
            (
                "\"1e-6\",\"2e-6\"\n",
                "line 1, column 1: `\"1e-6\"` is quoted",
            ),
            ("1e-6,'2e-6'\n", "line 1, column 2: `'2e-6'` is quoted"),
            (
                "1e-6,1e400\n",
                "line 1, column 2: `1e400` is beyond the range of a number",
            ),
            ("1,2\n-1e400,2\n", "line 2, column 1: `-1e400` is beyond"),
            ("\"x\",\"y\"\n1,2\n", "header line"),
        ] {
            let e = parse_csv(text).unwrap_err();
            assert!(e.contains(words), "{text:?}: {e}");
            assert!(!e.contains("inf"), "{text:?}: {e}");
            if words != "header line" {
                assert!(!e.contains("header"), "{text:?}: {e}");
            }
        }
    }
}
