//! Joining the outputs of a batch's shards into the output of one unsharded run, streamed (one
//! line per shard held at a time): each shard's lines are in input order (as a batch writes
//! them), so the join is a k-way merge by position. Checked as it goes: every line is a result
//! line, all shards saw the same input (the same `of`), and the shards cover the input: every
//! position `0..of` exactly once (none missing, none twice). Shards without a single line
//! cannot make a run.

use std::io::Write;
use std::path::{Path, PathBuf};

use grasp_io::{InputFile, LineReader, LineText, SHARD_OUTPUT};

use crate::error::{io, BatchError};
use crate::result_line::ResultLine;

/// Positions listed in a "missing" error (the rest are counted).
const MAX_LISTED_MISSING: usize = 10;

/// What a merge wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MergeSummary {
    /// Result lines written (the input's scene count).
    pub lines: usize,
}

/// One shard being read: its next result line (position, text, line number).
struct ShardReader<'a> {
    path: &'a Path,
    lines: LineReader,
    head: Option<(ResultLine, String, usize)>,
    last: Option<usize>,
}

impl ShardReader<'_> {
    /// Reads the next result line into `head` (None at the end), checking it.
    fn advance(&mut self) -> Result<(), BatchError> {
        self.head = None;
        while let Some(line) = self.lines.next_line()? {
            let text =
                match line.text {
                    LineText::Text(t) if t.trim().is_empty() => continue,
                    LineText::Text(t) if line.terminated => t,
                    LineText::Text(_) => return Err(self.bad(
                        line.number,
                        "is unfinished (its run was interrupted): resume that shard, then merge",
                    )),
                    _ => return Err(self.bad(line.number, "is not UTF-8 text or is too long")),
                };
            let r: ResultLine = serde_json::from_str(&text).map_err(|e| {
                self.bad(
                    line.number,
                    &format!("is not a result line of grasp batch: {e}"),
                )
            })?;
            if self.last.is_some_and(|l| r.index <= l) {
                return Err(self.bad(
                    line.number,
                    &format!(
                        "is position {}, after position {}: a shard's lines are in input order",
                        r.index,
                        self.last.unwrap_or(0)
                    ),
                ));
            }
            self.last = Some(r.index);
            self.head = Some((r, text, line.number));
            return Ok(());
        }
        Ok(())
    }

    fn bad(&self, number: usize, what: &str) -> BatchError {
        io(self.path, format!("line {number} {what}"))
    }
}

/// Writes the lines of the shard outputs `files` to `out` in input order, checked complete.
pub fn merge(
    files: &[PathBuf],
    out: &mut dyn Write,
    out_name: &Path,
) -> Result<MergeSummary, BatchError> {
    let mut shards = Vec::with_capacity(files.len());
    for f in files {
        let mut s = ShardReader {
            path: f,
            lines: InputFile::open(f, SHARD_OUTPUT)?.lines(),
            head: None,
            last: None,
        };
        s.advance()?;
        shards.push(s);
    }
    let mut of: Option<(usize, &Path)> = None;
    let (mut next, mut lines) = (0usize, 0usize);
    let mut missing: Vec<usize> = Vec::new();
    let mut missing_count = 0usize;
    while let Some(k) = (0..shards.len())
        .filter(|&k| shards[k].head.is_some())
        .min_by_key(|&k| shards[k].head.as_ref().map_or(usize::MAX, |h| h.0.index))
    {
        let Some((r, text, number)) = shards[k].head.take() else {
            break;
        };
        let path = shards[k].path;
        let (total, first) = *of.get_or_insert((r.of, path));
        check_line(&r, number, path, total, first, next, &shards)?;
        for m in next..r.index {
            missing_count += 1;
            if missing.len() < MAX_LISTED_MISSING {
                missing.push(m);
            }
        }
        writeln!(out, "{text}").map_err(|e| io(out_name, e))?;
        lines += 1;
        next = r.index + 1;
        shards[k].advance()?;
    }
    let Some((total, _)) = of else {
        return Err(BatchError::Merge(
            "the shards hold no result line; run the shards (or resume them) and merge again"
                .into(),
        ));
    };
    for m in next..total {
        missing_count += 1;
        if missing.len() < MAX_LISTED_MISSING {
            missing.push(m);
        }
    }
    if missing_count > 0 {
        let listed: Vec<String> = missing.iter().map(usize::to_string).collect();
        return Err(BatchError::Merge(format!(
            "{missing_count} of {total} scenes have no result (positions {}{}); run the missing \
             shards (or resume them) and merge again",
            listed.join(", "),
            if missing_count > missing.len() {
                ", ..."
            } else {
                ""
            }
        )));
    }
    out.flush().map_err(|e| io(out_name, e))?;
    Ok(MergeSummary { lines })
}

/// One line against the merge so far: the same input (`of` scenes, as the shard output
/// `first` counted them), a position inside it, and not one already written or waiting in
/// another shard.
fn check_line(
    r: &ResultLine,
    number: usize,
    path: &Path,
    of: usize,
    first: &Path,
    next: usize,
    shards: &[ShardReader<'_>],
) -> Result<(), BatchError> {
    if r.of != of {
        return Err(BatchError::Merge(format!(
            "{} line {number} counts {} scenes in its input, {} counts {of}: the shards come \
             from different inputs",
            path.display(),
            r.of,
            first.display()
        )));
    }
    if r.index >= of {
        return Err(BatchError::Merge(format!(
            "{} line {number} is position {} of an input of {of} scenes",
            path.display(),
            r.index
        )));
    }
    let twice = shards
        .iter()
        .filter_map(|s| s.head.as_ref().map(|h| (s.path, h)))
        .find(|(_, h)| h.0.index == r.index);
    if r.index < next || twice.is_some() {
        let other = twice.map_or("an earlier line".to_string(), |(p, h)| {
            format!("{} line {}", p.display(), h.2)
        });
        return Err(BatchError::Merge(format!(
            "position {} (`{}`) appears twice, in {} line {number} and in {other}; each scene \
             must come from exactly one shard (was a shard given twice?)",
            r.index,
            r.id,
            path.display()
        )));
    }
    Ok(())
}
