//! Joining the outputs of a batch's shards into the output of one unsharded run: every line
//! read back, sorted by input position, and checked: all shards saw the same input (the same
//! `of`), no position is missing, none appears twice with different ids.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::{io, BatchError};
use crate::result_line::ResultLine;

/// The lines of the shard outputs `files`, in input order, checked complete.
pub fn merge(files: &[PathBuf]) -> Result<Vec<ResultLine>, BatchError> {
    let mut by_index: BTreeMap<usize, (ResultLine, &Path)> = BTreeMap::new();
    let mut of: Option<(usize, &Path)> = None;
    for f in files {
        let text = std::fs::read_to_string(f).map_err(|e| io(f, e))?;
        for (n, line) in text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
        {
            let r: ResultLine = serde_json::from_str(line).map_err(|e| {
                io(
                    f,
                    format!("line {} is not a result line of grasp batch: {e}", n + 1),
                )
            })?;
            match of {
                Some((o, first)) if o != r.of => {
                    return Err(BatchError::Merge(format!(
                        "{} counts {} scenes in its input, {} counts {o}: the shards come from \
                         different inputs",
                        f.display(),
                        r.of,
                        first.display()
                    )))
                }
                None => of = Some((r.of, f)),
                _ => {}
            }
            if let Some((old, where_)) = by_index.get(&r.index) {
                if old.id != r.id {
                    return Err(BatchError::Merge(format!(
                        "scene {} is `{}` in {} but `{}` in {}",
                        r.index,
                        old.id,
                        where_.display(),
                        r.id,
                        f.display()
                    )));
                }
                continue;
            }
            by_index.insert(r.index, (r, f));
        }
    }
    let total = of.map_or(0, |o| o.0);
    let missing: Vec<usize> = (0..total).filter(|i| !by_index.contains_key(i)).collect();
    if !missing.is_empty() {
        let first: Vec<String> = missing.iter().take(10).map(|i| i.to_string()).collect();
        return Err(BatchError::Merge(format!(
            "{} of {total} scenes have no result (positions {}{}); run the missing shards (or \
             resume them) and merge again",
            missing.len(),
            first.join(", "),
            if missing.len() > 10 { ", ..." } else { "" }
        )));
    }
    Ok(by_index.into_values().map(|(r, _)| r).collect())
}
