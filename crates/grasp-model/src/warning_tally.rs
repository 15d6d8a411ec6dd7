//! The one collector of the warnings of many solves: each warning kept once, with how many
//! solves gave it, which ones, and the range of every figure that changed between them.
//!
//! A hand-off's steps (or a study's grids, a margin search's directions) repeat the same
//! warning, often with figures that change from one solve to the next ("the slope reaches
//! 0.357", then "0.366"); a [`WarningTally`] keeps it once, with the solves' indices as runs of
//! consecutive ones and their time span, each changing figure written as its range ("reaches
//! 0.357 to 0.441").
//!
//! Two warnings are the same when they read the same with their figures left out. A figure is
//! a number standing alone in the text (`0.357`, `75.34%`, `1.2e-4 m`): not a digit of a name
//! (`f1`), an index (`fingers[0]`), a dotted section number (`2.2.1`) or anything between
//! backticks, so warnings of two fingers stay two warnings.

use serde::{Deserialize, Serialize};

/// Most distinct warnings a tally keeps (later distinct ones are counted in
/// [`WarningTally::dropped`]): a run's warnings are few kinds per finger, so this bounds the
/// memory of a tally without losing any warning a real run gives.
pub const MAX_TALLIED_WARNINGS: usize = 100;

/// Most runs of consecutive indices kept per warning (a warning that comes and goes more often
/// keeps its first runs; [`TalliedWarning::more_runs`] counts the rest): a tally's memory does
/// not grow with the number of solves.
pub const MAX_LISTED_RUNS: usize = 20;

/// A run of consecutive solves that gave a warning: their first and last index (inclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct IndexRun {
    /// The first index of the run (a hand-off's step index).
    pub first: usize,
    /// The last index of the run, inclusive.
    pub last: usize,
}

/// A warning as collected over many solves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TalliedWarning {
    /// The warning's text; each figure that differed between the solves is written as its
    /// range over them, smallest to largest ("reaches 0.357 to 0.441").
    pub message: String,
    /// How many solves gave it.
    pub count: usize,
    /// Which: their indices (a hand-off's step indices) as runs of consecutive ones, the first
    /// [`MAX_LISTED_RUNS`].
    pub steps: Vec<IndexRun>,
    /// Runs beyond those listed in `steps`.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub more_runs: usize,
    /// The time of the first solve that gave it, s (a hand-off's schedule time; absent when
    /// the solves have no time).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_time_s: Option<f64>,
    /// The time of the last solve that gave it, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub last_time_s: Option<f64>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl TalliedWarning {
    /// The indices as text, each run `a-b` (or `a`), comma-separated, the runs not listed
    /// counted: `3-17, 25`, `0-3, 5, 7, ... and 4 more runs`. `label` names an index
    /// (a step's, a grid's): `|k| k.to_string()` writes it as it is.
    pub fn runs_text(&self, label: impl Fn(usize) -> String) -> String {
        let mut parts: Vec<String> = self
            .steps
            .iter()
            .map(|r| match r.first == r.last {
                true => label(r.first),
                false => format!("{}-{}", label(r.first), label(r.last)),
            })
            .collect();
        if self.more_runs > 0 {
            let runs = if self.more_runs == 1 { "run" } else { "runs" };
            parts.push(format!("... and {} more {runs}", self.more_runs));
        }
        parts.join(", ")
    }

    /// Whether every solve of `total` gave it.
    pub fn at_every_one_of(&self, total: usize) -> bool {
        self.count >= total
    }
}

/// One piece of a warning's text: words as they are, or a figure with its range so far.
#[derive(Debug, Clone, PartialEq)]
enum Piece {
    /// Text kept as it is.
    Words(String),
    /// A figure: its smallest and largest value so far with their texts.
    Figure(FigureRange),
}

/// The smallest and largest value of one figure over the solves, each with its text.
#[derive(Debug, Clone, PartialEq)]
struct FigureRange {
    /// The smallest value and how it was written.
    low: (f64, String),
    /// The largest value and how it was written.
    high: (f64, String),
}

/// A warning being collected: its pieces and where it came from.
#[derive(Debug, Clone, PartialEq)]
struct Entry {
    /// The text with its figures left out: what makes two warnings the same.
    key: String,
    pieces: Vec<Piece>,
    count: usize,
    runs: Vec<IndexRun>,
    more_runs: usize,
    /// The index of the last solve that gave it.
    last_index: usize,
    first_time_s: Option<f64>,
    last_time_s: Option<f64>,
}

/// Collects the warnings of many solves, each kept once (see the module).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WarningTally {
    entries: Vec<Entry>,
    /// Distinct warnings beyond [`MAX_TALLIED_WARNINGS`], not kept.
    dropped: usize,
}

/// Where a solve sits among the solves of a tally: its index (a hand-off's step index; the
/// indices of one tally ascend) and its time, s, when it has one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveAt {
    /// The index.
    pub index: usize,
    /// The time, s.
    pub time_s: Option<f64>,
}

impl WarningTally {
    /// An empty tally.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the warnings of the solve at `at` (a warning repeated within one solve counts
    /// once).
    pub fn add(&mut self, at: SolveAt, warnings: &[String]) {
        for w in warnings {
            let pieces = pieces_of(w);
            let key = key_of(&pieces);
            let full = self.entries.len() >= MAX_TALLIED_WARNINGS;
            match self.entries.iter_mut().find(|e| e.key == key) {
                Some(e) => e.note(at, &pieces),
                None if full => self.dropped += 1,
                None => self.entries.push(Entry {
                    key,
                    pieces,
                    count: 1,
                    runs: vec![IndexRun {
                        first: at.index,
                        last: at.index,
                    }],
                    more_runs: 0,
                    last_index: at.index,
                    first_time_s: at.time_s,
                    last_time_s: at.time_s,
                }),
            }
        }
    }

    /// True when no solve gave a warning.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty() && self.dropped == 0
    }

    /// Distinct warnings given beyond [`MAX_TALLIED_WARNINGS`] (not kept).
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// The warnings collected, in the order they first came.
    pub fn warnings(&self) -> Vec<TalliedWarning> {
        self.entries
            .iter()
            .map(|e| TalliedWarning {
                message: e.pieces.iter().map(Piece::text).collect(),
                count: e.count,
                steps: e.runs.clone(),
                more_runs: e.more_runs,
                first_time_s: e.first_time_s,
                last_time_s: e.last_time_s,
            })
            .collect()
    }
}

impl Entry {
    /// The warning again, from the solve at `at`, with these pieces (the same key).
    fn note(&mut self, at: SolveAt, pieces: &[Piece]) {
        self.widen(pieces);
        if at.index == self.last_index {
            // The same warning twice in one solve: its figures count, the solve once.
            return;
        }
        self.count += 1;
        let continues = at.index == self.last_index + 1;
        let listing = self.more_runs == 0;
        let room = self.runs.len() < MAX_LISTED_RUNS;
        match self.runs.last_mut() {
            // The current run is the last listed one: it grows.
            Some(r) if continues && listing => r.last = at.index,
            // An unlisted run goes on.
            _ if continues => {}
            _ if listing && room => self.runs.push(IndexRun {
                first: at.index,
                last: at.index,
            }),
            _ => self.more_runs += 1,
        }
        self.last_index = at.index;
        if at.time_s.is_some() {
            self.first_time_s = self.first_time_s.or(at.time_s);
            self.last_time_s = at.time_s;
        }
    }

    /// Widens each figure's range with the same figure of `pieces`.
    fn widen(&mut self, pieces: &[Piece]) {
        for (mine, theirs) in self.pieces.iter_mut().zip(pieces) {
            if let (Piece::Figure(m), Piece::Figure(t)) = (mine, theirs) {
                if t.low.0 < m.low.0 {
                    m.low = t.low.clone();
                }
                if t.high.0 > m.high.0 {
                    m.high = t.high.clone();
                }
            }
        }
    }
}

impl Piece {
    /// The piece as the collected warning writes it: a figure as its range when it varied.
    fn text(&self) -> String {
        match self {
            Piece::Words(w) => w.clone(),
            Piece::Figure(f) if f.low.0 == f.high.0 => f.low.1.clone(),
            Piece::Figure(f) => format!("{} to {}", f.low.1, f.high.1),
        }
    }
}

/// The key of a warning: its words, each figure written as `#`.
fn key_of(pieces: &[Piece]) -> String {
    pieces
        .iter()
        .map(|p| match p {
            Piece::Words(w) => w.as_str(),
            Piece::Figure(_) => "#",
        })
        .collect()
}

/// A warning's text cut into words and figures (see the module for what a figure is).
fn pieces_of(text: &str) -> Vec<Piece> {
    let chars: Vec<char> = text.chars().collect();
    let mut pieces = Vec::new();
    let mut words = String::new();
    let (mut i, mut quoted) = (0, false);
    while i < chars.len() {
        let c = chars[i];
        if c == '`' {
            quoted = !quoted;
        }
        let end = (!quoted)
            .then(|| figure_end(&chars, i))
            .flatten()
            .and_then(|end| {
                let t: String = chars[i..end].iter().collect();
                Some((end, t.parse::<f64>().ok()?, t))
            });
        match end {
            Some((end, value, t)) if value.is_finite() => {
                if !words.is_empty() {
                    pieces.push(Piece::Words(std::mem::take(&mut words)));
                }
                pieces.push(Piece::Figure(FigureRange {
                    low: (value, t.clone()),
                    high: (value, t),
                }));
                i = end;
            }
            _ => {
                words.push(c);
                i += 1;
            }
        }
    }
    if !words.is_empty() {
        pieces.push(Piece::Words(words));
    }
    pieces
}

/// Where the figure starting at `chars[i]` ends (exclusive), when a figure starts there: an
/// optional sign, digits with an optional fraction, an optional exponent; standing alone (not
/// after a letter, digit, `_`, `[`, `.` or `-` of a word, and not followed by a letter, digit,
/// `_`, `]` or a `.` with a digit after it).
fn figure_end(chars: &[char], i: usize) -> Option<usize> {
    let at = |k: usize| chars.get(k).copied();
    let word = |c: char| c.is_alphanumeric() || c == '_';
    if let Some(p) = i.checked_sub(1).and_then(at) {
        if word(p) || matches!(p, '[' | '.' | '-' | '+') {
            return None;
        }
    }
    let mut k = i;
    if matches!(at(k), Some('-' | '+')) {
        k += 1;
    }
    let digits = |mut k: usize| {
        while at(k).is_some_and(|c| c.is_ascii_digit()) {
            k += 1;
        }
        k
    };
    let start = k;
    k = digits(k);
    if k == start {
        return None;
    }
    if at(k) == Some('.') && at(k + 1).is_some_and(|c| c.is_ascii_digit()) {
        k = digits(k + 1);
    }
    if at(k) == Some('e') {
        let sign = usize::from(matches!(at(k + 1), Some('-' | '+')));
        if at(k + 1 + sign).is_some_and(|c| c.is_ascii_digit()) {
            k = digits(k + 1 + sign);
        }
    }
    let dotted = at(k) == Some('.') && at(k + 1).is_some_and(|c| c.is_ascii_digit());
    if at(k).is_some_and(|c| word(c) || c == ']') || dotted {
        return None;
    }
    Some(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slope(finger: &str, i: usize, slope: &str, degrees: u32) -> String {
        format!(
            "fingers[{i}] `{finger}`: the surfaces' slope over the contact reaches {slope} \
             ({degrees} degrees), beyond the half-space's small slopes (0.3): its forces are \
             approximate"
        )
    }

    fn at(index: usize) -> SolveAt {
        SolveAt {
            index,
            time_s: Some(0.1 * index as f64),
        }
    }

    #[test]
    fn a_warning_repeated_with_changing_figures_is_told_once_with_their_ranges() {
        let mut tally = WarningTally::new();
        for (k, (s, d)) in [("0.357", 20), ("0.441", 24), ("0.366", 20)]
            .into_iter()
            .enumerate()
        {
            tally.add(at(k + 3), &[slope("a1", 0, s, d)]);
        }
        let w = tally.warnings();
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].count, 3);
        assert!(
            w[0].message
                .contains("reaches 0.357 to 0.441 (20 to 24 degrees), beyond the half-space's small slopes (0.3)"),
            "{}",
            w[0].message
        );
        assert!(
            w[0].message.starts_with("fingers[0] `a1`:"),
            "{}",
            w[0].message
        );
        assert_eq!(w[0].steps, [IndexRun { first: 3, last: 5 }]);
        assert_eq!(w[0].first_time_s, Some(0.30000000000000004));
        assert_eq!(w[0].last_time_s, Some(0.5));
    }

    #[test]
    fn the_same_warning_of_two_fingers_stays_two_warnings() {
        let mut tally = WarningTally::new();
        tally.add(
            at(0),
            &[slope("a1", 0, "0.357", 20), slope("a2", 1, "0.357", 20)],
        );
        tally.add(at(1), &[slope("f1", 0, "0.4", 21)]);
        let w = tally.warnings();
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[2].message.starts_with("fingers[0] `f1`"), "{w:?}");
    }

    #[test]
    fn a_warning_that_comes_and_goes_lists_its_runs_of_steps() {
        let mut tally = WarningTally::new();
        for k in [2, 3, 4, 9, 12, 13] {
            tally.add(at(k), &["the patch hangs over the edge".to_string()]);
        }
        let w = &tally.warnings()[0];
        assert_eq!(w.count, 6);
        assert_eq!(w.runs_text(|k| k.to_string()), "2-4, 9, 12-13");
        assert!(!w.at_every_one_of(14));
    }

    #[test]
    fn runs_beyond_the_listed_ones_are_counted_not_kept() {
        let mut tally = WarningTally::new();
        for k in (0..2 * MAX_LISTED_RUNS + 2).map(|k| 2 * k) {
            tally.add(at(k), &["w".to_string()]);
        }
        let w = &tally.warnings()[0];
        assert_eq!(w.steps.len(), MAX_LISTED_RUNS);
        assert_eq!(w.more_runs, MAX_LISTED_RUNS + 2);
        assert_eq!(w.count, 2 * MAX_LISTED_RUNS + 2);
        assert!(w
            .runs_text(|k| k.to_string())
            .ends_with("... and 22 more runs"));
    }

    #[test]
    fn names_indices_section_numbers_and_quoted_text_are_not_figures() {
        let text = "fingers[2] `f3`: carries 75.34% of its load (thesis 2.2.1); grow it \
                    with `--grid 48`, 1.2e-4 m, -0.5 N";
        let figures: Vec<String> = pieces_of(text)
            .into_iter()
            .filter_map(|p| match p {
                Piece::Figure(f) => Some(f.low.1),
                Piece::Words(_) => None,
            })
            .collect();
        assert_eq!(figures, ["75.34", "1.2e-4", "-0.5"]);
        let back: String = pieces_of(text).iter().map(Piece::text).collect();
        assert_eq!(back, text);
    }

    #[test]
    fn distinct_warnings_beyond_the_limit_are_counted() {
        let mut tally = WarningTally::new();
        let many: Vec<String> = (0..MAX_TALLIED_WARNINGS + 3)
            .map(|k| format!("fingers[{k}] `x`: w"))
            .collect();
        tally.add(at(0), &many);
        assert_eq!(tally.warnings().len(), MAX_TALLIED_WARNINGS);
        assert_eq!(tally.dropped(), 3);
        assert!(!tally.is_empty());
    }
}
