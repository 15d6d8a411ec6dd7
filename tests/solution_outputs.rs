//! A solution's JSON text and `.npz` archive (`grasp solve --json`, `--npz`):
//!
//! - a solution without a fine patch is written byte for byte as `serde_json`'s pretty printer
//!   writes it (the text before the columns existed);
//! - a fine patch's `element_fields` hold, column by column, exactly the records the
//!   per-element form holds (the records serialised on their own, the columns turned back into
//!   records here by plain JSON code), each column on one line, and the text reads back into
//!   the same solution;
//! - the `.npz` archive read back with npyz holds the solution's own float64 values, bit for
//!   bit (numpy reads it in the Python tests).

mod support;

use grasp_io::SolutionRecord;
use grasp_model::{Solution, COLUMNS_ABOVE_ELEMENTS};
use serde_json::Value;
use support::{example_json, solve_json};

/// The text `grasp solve --json` writes for `solution`.
fn json_text(solution: &Solution) -> String {
    let record = SolutionRecord {
        solution,
        time: None,
        sensitivities: None,
        sensors: None,
    };
    let mut text = Vec::new();
    grasp_io::write_solution_json(&mut text, &record).unwrap();
    String::from_utf8(text).unwrap()
}

/// The Hertz example on an `n x n` grid.
fn hertz(n: usize) -> Solution {
    let mut v = example_json("hertz_sphere_on_flat.json");
    v["fingers"][0]["patch"]["grid"] = serde_json::json!([n, n]);
    solve_json(&v)
}

#[test]
fn solutions_without_a_fine_patch_keep_the_pretty_text() {
    for name in [
        "cube_a.json",
        "box_pinch.json",
        "plate_transfer.json",
        "cube_b.json",
    ] {
        let solution = solve_json(&example_json(name));
        let record = SolutionRecord {
            solution: &solution,
            time: None,
            sensitivities: None,
            sensors: None,
        };
        let pretty = serde_json::to_string_pretty(&record).unwrap();
        assert_eq!(json_text(&solution), pretty, "{name}");
        assert!(!pretty.contains("element_fields"), "{name}");
        let back: Solution = serde_json::from_str(&pretty).unwrap();
        assert_eq!(back, solution, "{name} reads back");
    }
}

/// The records a columns object stands for, by plain JSON code: row `k` takes element `k`
/// of every column.
fn records_of_columns(columns: &Value) -> Vec<Value> {
    let columns = columns.as_object().unwrap();
    let n = columns["index"].as_array().unwrap().len();
    (0..n)
        .map(|k| {
            let row = columns
                .iter()
                .map(|(field, column)| {
                    let column = column.as_array().unwrap();
                    assert_eq!(column.len(), n, "{field}");
                    (field.clone(), column[k].clone())
                })
                .collect();
            Value::Object(row)
        })
        .collect()
}

#[test]
fn a_fine_patch_writes_the_records_as_columns() {
    // 72 x 72 = 5184 elements, above the 64 x 64 threshold.
    let solution = hertz(72);
    let finger = &solution.fingers[0];
    assert!(finger.elements.len() > COLUMNS_ABOVE_ELEMENTS);
    let text = json_text(&solution);
    let parsed: Value = serde_json::from_str(&text).unwrap();
    let written = &parsed["fingers"][0];
    assert!(written.get("elements").is_none());
    // The records as the per-element form writes them, serialised on their own.
    let records = serde_json::to_value(&finger.elements).unwrap();
    assert_eq!(
        Value::Array(records_of_columns(&written["element_fields"])),
        records
    );
    // Everything but the elements as before.
    let mut before = serde_json::to_value(&solution).unwrap();
    let mut after = parsed.clone();
    for v in [&mut before, &mut after] {
        let f = v["fingers"][0].as_object_mut().unwrap();
        f.remove("elements");
        f.remove("element_fields");
    }
    assert_eq!(after, before);
    // One line a column: the eleven fields' lines start with their key.
    for field in [
        "\"index\": [[0,0],[0,1],",
        "\"pressure_pa\": [",
        "\"state\": [\"",
    ] {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with(&field[..8]));
        assert!(
            line.is_some_and(|l| l.trim_start().starts_with(field)),
            "{field}"
        );
    }
    // The eleven columns are the only long lines (5184 values each); the rest is one value a
    // line as before.
    let long = text.lines().filter(|l| l.len() > 5184).count();
    assert_eq!(long, 11);
    assert!(text
        .lines()
        .filter(|l| l.len() <= 5184)
        .all(|l| l.len() < 120));
    // The text reads back into the same solution.
    let back: Solution = serde_json::from_str(&text).unwrap();
    assert_eq!(back, solution);
}

#[test]
fn columns_of_unequal_length_are_refused() {
    let solution = hertz(72);
    let mut v: Value = serde_json::from_str(&json_text(&solution)).unwrap();
    v["fingers"][0]["element_fields"]["gap_m"]
        .as_array_mut()
        .unwrap()
        .pop();
    let e = serde_json::from_value::<Solution>(v).unwrap_err();
    assert!(e.to_string().contains("differ in length"), "{e}");
}

#[test]
fn the_npz_archive_holds_every_field_bit_for_bit() {
    let solution = hertz(72);
    let mut archive = grasp_io::NpzArchive::new(std::io::Cursor::new(Vec::new()));
    archive.add_solution("", &solution).unwrap();
    let bytes = archive.finish().unwrap().into_inner();
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    let mut read = |name: &str| -> npyz::NpyFile<std::io::Cursor<Vec<u8>>> {
        let mut entry = zip.by_name(&format!("{name}.npy")).unwrap();
        let mut data = Vec::new();
        std::io::Read::read_to_end(&mut entry, &mut data).unwrap();
        npyz::NpyFile::new(std::io::Cursor::new(data)).unwrap()
    };
    let e = &solution.fingers[0].elements;
    let n = e.len() as u64;
    let bits = |v: Vec<f64>| v.into_iter().map(f64::to_bits).collect::<Vec<_>>();
    let p = read("tip/pressure_pa");
    assert_eq!(p.shape(), [n]);
    let want: Vec<f64> = e.iter().map(|e| e.pressure_pa).collect();
    assert_eq!(bits(p.into_vec().unwrap()), bits(want));
    let x = read("tip/position_m");
    assert_eq!(x.shape(), [n, 3]);
    let want: Vec<f64> = e.iter().flat_map(|e| e.position_m).collect();
    assert_eq!(bits(x.into_vec().unwrap()), bits(want));
    let index = read("tip/index");
    assert_eq!(index.shape(), [n, 2]);
    let index: Vec<i64> = index.into_vec().unwrap();
    assert_eq!(&index[..4], [0, 0, 0, 1]);
    let state: Vec<u8> = read("tip/state").into_vec().unwrap();
    let names = read("state_names");
    assert_eq!(names.dtype().descr(), "'<U12'");
    let want: Vec<u8> = e
        .iter()
        .map(|e| match e.state.as_str() {
            "stick" => 0,
            "slip" => 1,
            "separated" => 2,
            "off_surface" => 3,
            _ => 4,
        })
        .collect();
    assert_eq!(state, want);
}

/// Each finger's fields are one row per element: the archive carries the patch's `[nx, ny]`
/// as `<finger>/grid`, int64, to reshape them into the patch's map.
#[test]
fn the_npz_archive_carries_each_patch_s_grid_shape() {
    for side in [21, 72] {
        let solution = hertz(side);
        let mut archive = grasp_io::NpzArchive::new(std::io::Cursor::new(Vec::new()));
        archive.add_solution("", &solution).unwrap();
        let bytes = archive.finish().unwrap().into_inner();
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let mut entry = zip.by_name("tip/grid.npy").unwrap();
        let mut data = Vec::new();
        std::io::Read::read_to_end(&mut entry, &mut data).unwrap();
        let grid = npyz::NpyFile::new(std::io::Cursor::new(data)).unwrap();
        assert_eq!(grid.shape(), [2]);
        assert_eq!(grid.into_vec::<i64>().unwrap(), [side as i64, side as i64]);
    }
}

#[test]
fn the_same_solution_gives_the_same_archive() {
    let solution = solve_json(&example_json("cube_a.json"));
    let archive = || {
        let mut a = grasp_io::NpzArchive::new(std::io::Cursor::new(Vec::new()));
        a.add_solution("", &solution).unwrap();
        a.finish().unwrap().into_inner()
    };
    let first = archive();
    std::thread::sleep(std::time::Duration::from_millis(1100));
    // Entries carry no clock: a second later the bytes are the same.
    assert_eq!(archive(), first);
}
