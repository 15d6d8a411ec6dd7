//! `grasp bench --case outputs --quick`: the rows on writing a fine patch's solution print
//! alone, well formed (a 256 x 256 solve, then the JSON and the `.npz` written). Times are not
//! asserted (they belong to the benchmark); what holds on any machine is: one row per format
//! after the solve's, each with a size in MB and its ratio to the solve against its target.

mod common;
use common::grasp;

#[test]
fn quick_output_rows_print_one_row_per_format() {
    let out = grasp(&["bench", "--case", "outputs", "--quick", "--markdown"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<Vec<&str>> = stdout
        .lines()
        .filter(|l| l.starts_with("| hertz"))
        .map(|l| l.trim_matches('|').split(" | ").map(str::trim).collect())
        .collect();
    let names: Vec<&str> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(
        names,
        [
            "hertz_256x256 outputs",
            "hertz_256x256 outputs --json",
            "hertz_256x256 outputs --npz"
        ],
        "{stdout}"
    );
    assert_eq!(rows[0][6], "65536", "256 x 256 elements");
    for (row, limit) in rows[1..].iter().zip(["<= 0.5x", "<= 0.1x"]) {
        assert!(row[4].ends_with(" MB"), "{row:?}");
        // At least the 65,536 pressures' 8 bytes.
        let mb: f64 = row[4].trim_end_matches(" MB").parse().unwrap();
        assert!(mb > 0.5, "{row:?}");
        assert!(
            row[11].contains("x solve ") && row[11].contains(limit),
            "{row:?}"
        );
    }
    assert!(rows[1][11].contains("peak <= 1.2 GB"), "{:?}", rows[1]);
}
