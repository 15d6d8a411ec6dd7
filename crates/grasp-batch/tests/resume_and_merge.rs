//! The library's checks of what a batch reads back, on hand-made result lines (no solving):
//! a resumed output is checked whole against the input (its count, the id at each position,
//! the shard, each position once, an unfinished last line only if it starts a result line);
//! a merge writes every position 0..of exactly once, in order, or refuses naming why.

use std::path::{Path, PathBuf};

use grasp_batch::{merge, read_batch_output, BatchInput, InputIndex, ResultLine, Shard};

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-batch-lib-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An input of scenes with the ids `ids` (their scenes are never parsed here).
fn index_of(dir: &Path, ids: &[&str]) -> InputIndex {
    let p = dir.join("in.jsonl");
    let body: Vec<String> = ids
        .iter()
        .map(|id| format!(r#"{{"id": "{id}", "scene": {{}}}}"#))
        .collect();
    std::fs::write(&p, body.join("\n")).unwrap();
    BatchInput::open(&p).unwrap().index().unwrap()
}

/// The text of result lines `(id, index)` of an input of `of` scenes.
fn lines(of: usize, items: &[(&str, usize)]) -> String {
    items
        .iter()
        .map(|(id, i)| {
            let l = ResultLine::invalid(id.to_string(), *i, of, Vec::new());
            format!("{}\n", serde_json::to_string(&l).unwrap())
        })
        .collect()
}

#[test]
fn a_resumed_output_is_checked_whole_against_its_input() {
    let d = scratch("resume");
    let ix = index_of(&d, &["a", "b", "c", "d"]);
    let out = d.join("out.jsonl");
    // Two lines and half of a third: resumes after them, cutting the half line.
    let good = lines(4, &[("a", 0), ("b", 1)]);
    let half = &lines(4, &[("c", 2)])[..20];
    std::fs::write(&out, format!("{good}{half}")).unwrap();
    let p = read_batch_output(&out, &ix, Shard::ALL).unwrap();
    assert_eq!(p.done, [0, 1].into_iter().collect());
    assert_eq!(p.cut_at, Some(good.len() as u64));
    let cases = [
        (lines(5, &[("a", 0)]), Shard::ALL, "counts 5 scenes"),
        (lines(4, &[("b", 0)]), Shard::ALL, "holds `b` at position 0"),
        (
            lines(4, &[("zz", 3)]),
            Shard::ALL,
            "holds `zz` at position 3",
        ),
        (
            lines(4, &[("b", 1)]),
            Shard { index: 0, count: 2 },
            "not in shard 0/2",
        ),
        (
            lines(4, &[("a", 0), ("a", 0)]),
            Shard::ALL,
            "repeats position 0",
        ),
        (
            format!("{good}not a result"),
            Shard::ALL,
            "is not the start of a result line",
        ),
        (
            "{\"object\": {}}\n".into(),
            Shard::ALL,
            "is not a result line",
        ),
    ];
    for (text, shard, words) in cases {
        std::fs::write(&out, &text).unwrap();
        let e = read_batch_output(&out, &ix, shard).unwrap_err().to_string();
        assert!(
            e.contains(words) && e.contains("nothing was changed"),
            "{words}: {e}"
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    }
    // No output yet: nothing done.
    let p = read_batch_output(&d.join("new.jsonl"), &ix, Shard::ALL).unwrap();
    assert!(p.done.is_empty() && p.cut_at.is_none() && p.identity.is_none());
}

#[test]
fn a_merge_covers_every_position_exactly_once() {
    let d = scratch("merge");
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let s0 = write("s0", &lines(5, &[("a", 0), ("c", 2), ("e", 4)]));
    let s1 = write("s1", &lines(5, &[("b", 1), ("d", 3)]));
    let empty = write("empty", "");
    let mut out = Vec::new();
    let m = merge(
        &[s1.clone(), empty.clone(), s0.clone()],
        &mut out,
        Path::new("o"),
    )
    .unwrap();
    assert_eq!(m.lines, 5);
    let ids: Vec<String> = String::from_utf8(out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<ResultLine>(l).unwrap().id)
        .collect();
    assert_eq!(ids, ["a", "b", "c", "d", "e"]);
    let unordered = write("u", &lines(5, &[("c", 2), ("a", 0)]));
    let foreign = write("f", &lines(6, &[("b", 1)]));
    let beyond = write("x", &lines(5, &[("f", 5)]));
    let cases: Vec<(Vec<&PathBuf>, &str)> = vec![
        (vec![&empty, &empty], "hold no result line"),
        (vec![&s0], "2 of 5 scenes have no result (positions 1, 3)"),
        (vec![&s0, &s1, &s0], "appears twice"),
        (vec![&unordered, &s1], "a shard's lines are in input order"),
        (vec![&s0, &foreign], "different inputs"),
        (vec![&s0, &s1, &beyond], "position 5 of an input of 5"),
    ];
    for (shards, words) in cases {
        let files: Vec<PathBuf> = shards.into_iter().cloned().collect();
        let e = merge(&files, &mut Vec::new(), Path::new("o"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(words), "{words}: {e}");
    }
}
