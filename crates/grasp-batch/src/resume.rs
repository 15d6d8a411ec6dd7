//! Reading back a batch's output to resume it, checked whole before anything is changed: every
//! complete line must be a result line of this input (its scene count, the id the input has
//! at that position, a position of this shard, each position once), and an unfinished last
//! line (left by an interrupted run) must be the start of one. Only then may the caller cut
//! that unfinished line ([`ResumePoint::cut_at`]) and append; an output that fails the check
//! (a scene file given as `--out`, another input's results) is left exactly as it was.

use std::collections::HashSet;
use std::path::Path;

use grasp_io::{FileIdentity, FileLine, InputFile, LineText, BATCH_OUTPUT};

use crate::error::BatchError;
use crate::input_index::InputIndex;
use crate::result_line::ResultLine;
use crate::shard::Shard;

/// How every result line begins (`serde_json` writes the fields in declaration order).
const RESULT_LINE_START: &[u8] = b"{\"id\":";

/// Where a resumed run starts.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ResumePoint {
    /// Positions already in the output.
    pub done: HashSet<usize>,
    /// The byte where an unfinished last line starts (to cut before appending).
    pub cut_at: Option<u64>,
    /// The output file read (None when it does not exist yet).
    pub identity: Option<FileIdentity>,
}

/// Reads and checks the output `path` of a batch of the input `index`, shard `shard`.
pub fn read_batch_output(
    path: &Path,
    index: &InputIndex,
    shard: Shard,
) -> Result<ResumePoint, BatchError> {
    if std::fs::symlink_metadata(path).is_err() {
        return Ok(ResumePoint::default());
    }
    let file = InputFile::open(path, BATCH_OUTPUT)?;
    let mut point = ResumePoint {
        identity: Some(file.identity()),
        ..ResumePoint::default()
    };
    let mut lines = file.lines();
    while let Some(line) = lines.next_line()? {
        if !line.terminated {
            if !starts_a_result_line(&line) {
                return Err(not_ours(
                    path,
                    line.number,
                    "is not the start of a result line",
                ));
            }
            point.cut_at = Some(line.start);
            break;
        }
        let text = match &line.text {
            LineText::Text(t) if t.trim().is_empty() => continue,
            LineText::Text(t) => t,
            _ => {
                return Err(not_ours(
                    path,
                    line.number,
                    "is not UTF-8 text or is too long",
                ))
            }
        };
        let r: ResultLine = serde_json::from_str(text)
            .map_err(|_| not_ours(path, line.number, "is not a result line of grasp batch"))?;
        check_line(path, line.number, &r, index, shard)?;
        if !point.done.insert(r.index) {
            return Err(not_ours(
                path,
                line.number,
                &format!("repeats position {} (`{}`)", r.index, r.id),
            ));
        }
    }
    Ok(point)
}

/// One complete line against the input and the shard.
fn check_line(
    path: &Path,
    number: usize,
    r: &ResultLine,
    index: &InputIndex,
    shard: Shard,
) -> Result<(), BatchError> {
    if r.of != index.scenes {
        return Err(not_ours(
            path,
            number,
            &format!(
                "counts {} scenes in its input, but the input has {}: it was written from \
                 another input",
                r.of, index.scenes
            ),
        ));
    }
    if index.position_of(&r.id) != Some(r.index) {
        return Err(not_ours(
            path,
            number,
            &format!(
                "holds `{}` at position {}, which the input does not: it was written from \
                 another input",
                r.id, r.index
            ),
        ));
    }
    if !shard.takes(r.index) {
        return Err(not_ours(
            path,
            number,
            &format!(
                "holds position {}, which is not in shard {}/{}: resume with the shard that \
                 wrote it",
                r.index, shard.index, shard.count
            ),
        ));
    }
    Ok(())
}

/// True when an unfinished line is the beginning of a result line.
fn starts_a_result_line(line: &FileLine) -> bool {
    let bytes = match &line.text {
        LineText::Text(t) => t.as_bytes(),
        LineText::NotUtf8 { bytes, .. } => bytes,
        LineText::TooLong { .. } => return false,
    };
    let n = bytes.len().min(RESULT_LINE_START.len());
    n > 0 && bytes[..n] == RESULT_LINE_START[..n]
}

fn not_ours(path: &Path, number: usize, what: &str) -> BatchError {
    BatchError::NotBatchOutput {
        path: path.to_path_buf(),
        message: format!(
            "line {number} {what}; resuming appends only to this batch's own output, so \
             nothing was changed (give the output of this input, or a new file)"
        ),
    }
}
