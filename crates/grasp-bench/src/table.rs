//! The benchmark table: its columns, a row's cells, how a time, a memory and a verdict against
//! a target read, and the table as aligned text or as Markdown, with the legend under it.

use std::fmt::Write as _;

/// The table's columns, in order.
pub const HEADER: [&str; 12] = [
    "case",
    "timed",
    "solver",
    "median",
    "range",
    "runs",
    "unknowns",
    "iterations",
    "factorizations",
    "peak MiB",
    "error",
    "target",
];

/// The legend printed under the table: what the runs, iterations, memory and errors are.
pub const LEGEND: &str = "(release build, this machine; times are medians of the timing runs; \
     iterations: Newton steps (native) or interior-point iterations (Clarabel) per solve or step \
     (the plan: hand-off runs); peak MiB: resident memory above the start of the case's first \
     run; error: Hertz peak-pressure error for hertz_*, the stick radius's error in elements \
     against Cattaneo's for cattaneo_*, how far the plan's margin falls short for the plan, else \
     the worst relative residual)";

/// One row of the table: a cell per column of [`HEADER`], blank where the row has nothing to
/// say.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Row {
    /// The case, or what a derived row compares.
    pub case: String,
    /// What is timed (per solve, per step, a ratio...).
    pub timed: String,
    /// The solver (or the peer library).
    pub solver: String,
    /// The median time (or the derived quantity: a ratio, an exponent, a rate).
    pub median: String,
    /// The range of the timing runs (or the two quantities of a ratio, or a file's size).
    pub range: String,
    /// Timing runs.
    pub runs: String,
    /// Unknowns of the program.
    pub unknowns: String,
    /// Solver iterations per solve or step.
    pub iterations: String,
    /// Factorisations per solve or step.
    pub factorizations: String,
    /// Peak resident memory above the start of the case's first run, MiB.
    pub peak_mib: String,
    /// The run's error (see [`LEGEND`]).
    pub error: String,
    /// The target, and whether it was met.
    pub target: String,
}

impl Row {
    /// The cells in column order.
    pub fn cells(&self) -> [&str; 12] {
        [
            &self.case,
            &self.timed,
            &self.solver,
            &self.median,
            &self.range,
            &self.runs,
            &self.unknowns,
            &self.iterations,
            &self.factorizations,
            &self.peak_mib,
            &self.error,
            &self.target,
        ]
    }
}

/// A time in seconds, in the unit that reads best: us below 1 ms, ms below 1 s, else s.
pub fn time(s: f64) -> String {
    match s {
        s if s < 1e-3 => format!("{:.1} us", s * 1e6),
        s if s < 1.0 => format!("{:.3} ms", s * 1e3),
        s => format!("{s:.2} s"),
    }
}

/// A memory in bytes as MiB with two decimals, `-` where it is not known.
pub fn mib(bytes: Option<u64>) -> String {
    bytes.map_or("-".into(), |b| format!("{:.2}", b as f64 / 1048576.0))
}

/// `value` against its upper `limit`: `<= limit (met)` or `<= limit (MISSED)`, the limit
/// written by `show`.
pub fn verdict(value: f64, limit: f64, show: impl Fn(f64) -> String) -> String {
    let mark = if value <= limit { "met" } else { "MISSED" };
    format!("<= {} ({mark})", show(limit))
}

/// A speed-up against its lower `limit`: `>= 1.7x (met)` or `>= 1.7x (MISSED)`.
pub fn speed_up_verdict(speed_up: f64, limit: f64) -> String {
    let mark = if speed_up >= limit { "met" } else { "MISSED" };
    format!(">= {limit}x ({mark})")
}

/// The rows under the header: aligned text (each column as wide as its widest cell, two
/// spaces after every cell) or a Markdown table.
pub fn render(rows: &[Row], markdown: bool) -> String {
    let mut out = String::new();
    if markdown {
        let mut line = |cells: &[&str]| {
            let _ = writeln!(out, "| {} |", cells.join(" | "));
        };
        line(&HEADER);
        line(&["---"; 12]);
        for r in rows {
            line(&r.cells());
        }
        return out;
    }
    let widths: Vec<usize> = (0..HEADER.len())
        .map(|j| {
            rows.iter()
                .map(|r| r.cells()[j].chars().count())
                .chain([HEADER[j].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut line = |cells: &[&str]| {
        for (j, c) in cells.iter().enumerate() {
            let _ = write!(out, "{c:<w$}  ", w = widths[j]);
        }
        out.push('\n');
    };
    line(&HEADER);
    for r in rows {
        line(&r.cells());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_read_in_the_unit_that_fits() {
        assert_eq!(time(4.54e-4), "454.0 us");
        assert_eq!(time(0.0184), "18.400 ms");
        assert_eq!(time(2.8), "2.80 s");
    }

    #[test]
    fn columns_are_as_wide_as_their_widest_cell() {
        let row = Row {
            case: "cube_a_5x5".into(),
            median: "1.0 us".into(),
            ..Row::default()
        };
        let text = render(std::slice::from_ref(&row), false);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("case        timed  "), "{text}");
        assert!(lines[1].starts_with("cube_a_5x5         "), "{text}");
        assert_eq!(lines[0].len(), lines[1].len());
        let md = render(&[row], true);
        assert!(md.starts_with("| case | timed | solver |"), "{md}");
        assert!(md.contains("\n| --- | --- |"), "{md}");
        assert!(md.contains("\n| cube_a_5x5 |  |  | 1.0 us |"), "{md}");
    }
}
