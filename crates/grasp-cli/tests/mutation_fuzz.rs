//! Mutation fuzzing of the input formats through the `grasp` binary: a seeded (deterministic)
//! generator mutates the example inputs (deleted keys, extreme and non-finite numbers, wrong
//! types, huge grids, trailing data, duplicated keys) and every mutant is run with a timeout, a
//! memory limit (`--max-memory 256M` and an address-space limit of 4 GiB). Eight classes:
//!
//! - scenes (`solve`), and shapes: mutations under `object.shape` and `fingers[*].place` of
//!   the scenes with a primitive shape;
//! - meshes: the OBJ of the mug scene with vertices, faces or lines mutated (non-finite,
//!   extreme, out-of-range indices, text), or its `unit` / `scale`;
//! - schedules (`transfer`), and external-load schedules: the task-load schedules with their
//!   `external` wrench (a ramp, or a CSV whose cells, header and rows are mutated too);
//! - batch lines (`batch`): a JSONL of mutated scenes, bare or with ids, and broken lines;
//! - sweep specs (`sweep`, sometimes `--run`): paths, ranges, counts and value lists;
//! - margin options (`margin`): `--length`, `--tolerance`, `--directions` (counts, `planes:K`,
//!   a mutated directions file).
//!
//! Asserted for every mutant: no panic (exit 101 or "panicked"), no death by a signal or the
//! timeout; exit 0 only with sound outputs (finite numbers, residuals within tolerance:
//! equilibrium and cone violation <= 1e-6 of the load; one result line per input line, each
//! sound; one JSON variant per grid point); exit 1 with a JSON path, the file position or the
//! flag in the message; exit 2 with a reason; no number written out in full (a run of more
//! than 20 digits). One summary line with the counts per class is printed (run with
//! `--show-output`). `GRASP_FUZZ_MUTANTS` changes the number of mutants (default 900).

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

/// Wall-time limit of one run, s.
const TIMEOUT_S: u64 = 30;
/// Residuals (relative to the load) a solved grasp must meet.
const RESIDUAL_TOLERANCE: f64 = 1e-6;
/// Fixed seed: the same mutants on every run.
const SEED: u64 = 0x6772_6173_7000_0010;

/// SplitMix64: small, seeded, deterministic.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn load(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(examples().join(name)).unwrap()).unwrap()
}

/// JSON pointers of every node below the root.
fn pointers(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => m.iter().for_each(|(k, x)| {
            let p = format!("{at}/{k}");
            out.push(p.clone());
            pointers(x, p, out);
        }),
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| {
            let p = format!("{at}/{i}");
            out.push(p.clone());
            pointers(x, p, out);
        }),
        _ => {}
    }
}

const EXTREMES: [f64; 14] = [
    1e308, -1e308, 1e200, -1e200, 1e150, 1e-320, 5e-324, 1e-300, -0.0, 0.0, -1.0, 1e7, 1e15,
    65536.0,
];

/// One structural mutation of `v` (a key deleted, a number made extreme, a wrong type, a huge
/// grid) at a node below one of the pointers starting with `prefix` (any node when none does);
/// returns what it did.
fn mutate_under(v: &mut Value, rng: &mut Rng, prefix: &str) -> String {
    let mut ptrs = Vec::new();
    pointers(v, String::new(), &mut ptrs);
    let below: Vec<String> = ptrs
        .iter()
        .filter(|p| p.starts_with(prefix))
        .cloned()
        .collect();
    if !below.is_empty() {
        ptrs = below;
    }
    let p = rng.pick(&ptrs).clone();
    let (parent, key) = p.rsplit_once('/').unwrap();
    let kind = rng.below(12);
    match kind {
        0 | 1 => {
            let parent = v.pointer_mut(parent).unwrap();
            match parent {
                Value::Object(m) => drop(m.remove(key)),
                Value::Array(a) => drop(a.remove(key.parse::<usize>().unwrap())),
                _ => {}
            }
            format!("delete {p}")
        }
        8 | 9 if v.pointer(&p).is_some_and(Value::is_number) => {
            // A milder change of a number: a factor 1e-3 to 1e3, or its sign.
            let target = v.pointer_mut(&p).unwrap();
            let old = target.as_f64().unwrap_or(0.0);
            let f = *rng.pick(&[1e-3, 1e-2, 0.1, 0.5, 2.0, 10.0, 1e2, 1e3, -1.0]);
            *target = json!(old * f);
            format!("{p} = {:e} (x {f})", old * f)
        }
        2..=5 => {
            let x = *rng.pick(&EXTREMES);
            let scale = 1e6_f64.powi(rng.below(5) as i32 - 2);
            let target = v.pointer_mut(&p).unwrap();
            let x = match target.as_f64() {
                Some(old) if kind == 5 => old * scale,
                _ => x,
            };
            *target = json!(x);
            format!("{p} = {x:e}")
        }
        6 | 7 => {
            let wrong = [
                json!("x"),
                json!(true),
                Value::Null,
                json!([]),
                json!({}),
                json!([1, 2]),
                json!({"mu": "a"}),
                json!("rigid"),
                json!("held"),
                json!("current"),
            ];
            let w = rng.pick(&wrong).clone();
            *v.pointer_mut(&p).unwrap() = w.clone();
            format!("{p} = {w}")
        }
        _ => {
            let grids = [
                json!([64, 64]),
                json!([4096, 1]),
                json!([100000, 100000]),
                json!([0, 5]),
                json!([1, 1]),
                json!([18446744073709551615u64, 2]),
            ];
            let g = rng.pick(&grids).clone();
            match v.pointer_mut("/fingers/0/patch/grid") {
                Some(t) => {
                    *t = g.clone();
                    format!("fingers[0].patch.grid = {g}")
                }
                None => {
                    *v.pointer_mut(&p).unwrap() = g.clone();
                    format!("{p} = {g}")
                }
            }
        }
    }
}

/// Serializes `v`, duplicating one object key (the value mutated) when `dup` is set.
fn text_with_duplicate(v: &Value, rng: &mut Rng) -> (String, String) {
    let mut objects = Vec::new();
    let mut ptrs = vec![String::new()];
    pointers(v, String::new(), &mut ptrs);
    for p in ptrs {
        if let Some(Value::Object(m)) = v.pointer(&p) {
            if !m.is_empty() {
                objects.push(p);
            }
        }
    }
    let p = rng.pick(&objects).clone();
    let m = v.pointer(&p).unwrap().as_object().unwrap();
    let keys: Vec<&String> = m.keys().collect();
    let k = (*rng.pick(&keys)).clone();
    let marker = "\"__grasp_fuzz_dup__\": 0";
    let mut w = v.clone();
    w.pointer_mut(&p)
        .unwrap()
        .as_object_mut()
        .unwrap()
        .insert("__grasp_fuzz_dup__".into(), json!(0));
    let text = serde_json::to_string(&w).unwrap();
    let dup = format!("{}: {}", json!(k), m[&k]);
    (
        text.replacen(marker, &dup, 1),
        format!("duplicate key {p}/{k}"),
    )
}

/// A mutant's text: 1 or 2 mutations, sometimes a duplicated key, trailing data or
/// a non-finite literal.
fn mutant(base: &Value, rng: &mut Rng) -> (String, Vec<String>) {
    mutant_under(base, rng, "")
}

/// [`mutant`] with its mutations mostly below `prefix` (see [`mutate_under`]).
fn mutant_under(base: &Value, rng: &mut Rng, prefix: &str) -> (String, Vec<String>) {
    let mut v = base.clone();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(2) {
        let at = *rng.pick(&[prefix, prefix, ""]);
        what.push(mutate_under(&mut v, rng, at));
    }
    let mut text = v.to_string();
    match rng.below(12) {
        0 => {
            let (t, w) = text_with_duplicate(&v, rng);
            text = t;
            what.push(w);
        }
        1 => {
            let tail = *rng.pick(&[" {}", "x", "\n{\"object\": 1}", ",", " // comment", "\u{0}"]);
            text.push_str(tail);
            what.push(format!("trailing {tail:?}"));
        }
        2 => {
            let lit = *rng.pick(&["NaN", "Infinity", "-Infinity", "1e400", "-1e999"]);
            if let Some(pos) = text.find(|c: char| c.is_ascii_digit()) {
                let end = text[pos..]
                    .find([',', ']', '}'])
                    .map_or(text.len(), |e| pos + e);
                text.replace_range(pos..end, lit);
                what.push(format!("number -> {lit}"));
            }
        }
        _ => {}
    }
    (text, what)
}

/// A schedule shortened to at most about 12 steps (the fuzz tests inputs, not long runs).
fn short_schedule(name: &str) -> Value {
    let mut s = load(name);
    let t = &mut s["time"];
    if let (Some(a), Some(b)) = (t["start"].as_f64(), t["end"].as_f64()) {
        t["step"] = json!((b - a) / 11.0);
    }
    s
}

/// The classes of input mutated, in the order the summary lists them.
const CLASSES: [&str; 8] = [
    "scenes",
    "shapes",
    "meshes",
    "schedules",
    "external loads",
    "batch lines",
    "sweep specs",
    "margin options",
];

/// What a run's exit 0 must have written.
enum Output {
    /// A solution JSON (`solve --json`).
    Solution,
    /// A force-history CSV (`transfer --csv`).
    History,
    /// One batch result line per non-blank input line.
    Results(usize),
    /// Sweep variants (JSONL of `{"id", "vary", "scene"}`).
    Variants,
    /// A margin report (`margin --json`).
    Margins,
}

#[derive(Default)]
struct Tally {
    /// Per class: mutants, then exits 0, 1, 2.
    classes: [[usize; 4]; CLASSES.len()],
    exits: [usize; 3],
    panics: usize,
    garbage_exit_0: usize,
    failures: Vec<String>,
    slowest_s: f64,
}

/// Runs the binary with a timeout and a 4 GiB address-space limit: (exit code, stdout, stderr).
fn run(args: &[&str]) -> Result<(Option<i32>, String, String, f64), String> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_grasp"));
    cmd.args(args).stdout(Stdio::piped()).stderr(Stdio::piped());
    unsafe {
        cmd.pre_exec(|| {
            let lim = libc::rlimit {
                rlim_cur: 4 << 30,
                rlim_max: 4 << 30,
            };
            libc::setrlimit(libc::RLIMIT_AS, &lim);
            Ok(())
        });
    }
    let start = Instant::now();
    let mut child = cmd.spawn().map_err(|e| e.to_string())?;
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if start.elapsed() > Duration::from_secs(TIMEOUT_S) {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("timeout after {TIMEOUT_S} s"));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    Ok((
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
        start.elapsed().as_secs_f64(),
    ))
}

/// The keys (besides `reason` and `sequential`) a sound output may hold null at.
const NULLABLE: [&str; 9] = [
    "reason",
    "sequential",
    "fails_at_n",
    "failing_finger",
    "failure",
    "vary",
    "rigid_displacement",
    "residuals",
    // Null when unbounded or undetermined (`held_to_n` says how far it held).
    "margin_n",
];

/// Every number in `v` is finite (NaN and infinities serialize as `null`; only the keys of
/// [`NULLABLE`] may be null); the bad keys.
fn non_finite_keys(v: &Value, nullable: &[&str]) -> Vec<String> {
    fn walk(v: &Value, key: &str, nullable: &[&str], bad: &mut Vec<String>) {
        match v {
            Value::Null if !nullable.contains(&key) => bad.push(key.into()),
            Value::Number(n) if !n.as_f64().is_some_and(f64::is_finite) => bad.push(key.into()),
            Value::Object(m) => m.iter().for_each(|(k, x)| walk(x, k, nullable, bad)),
            Value::Array(a) => a.iter().for_each(|x| walk(x, key, nullable, bad)),
            _ => {}
        }
    }
    let mut bad = Vec::new();
    walk(v, "", nullable, &mut bad);
    bad
}

/// Every number in a solution JSON is finite (only `reason` and `sequential` may be null, and
/// `rigid_displacement` when no finger carries load, as documented) and its residuals are
/// within tolerance.
// `!(x <= tol)` is meant: a NaN residual must fail.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn solution_is_sound(text: &str) -> Result<(), String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("JSON: {e}"))?;
    let unloaded = v["fingers"]
        .as_array()
        .is_some_and(|f| f.iter().all(|f| f["normal_force_n"].as_f64() == Some(0.0)));
    let nullable: &[&str] = match unloaded {
        true => &["reason", "sequential", "rigid_displacement"],
        false => &NULLABLE[..2],
    };
    let bad = non_finite_keys(&v, nullable);
    if !bad.is_empty() {
        return Err(format!("null or non-finite numbers at {bad:?}"));
    }
    let r = &v["residuals"];
    for k in ["equilibrium_relative", "cone_violation_relative"] {
        let x = r[k].as_f64().ok_or(format!("no residual {k}"))?;
        if !(x <= RESIDUAL_TOLERANCE) {
            return Err(format!("residual {k} = {x:e}"));
        }
    }
    Ok(())
}

/// Every cell of a force-history CSV is a finite number, except the text columns named in its
/// header: `status`, `solver` (`native` or `clarabel`), `warm_start` (`true` or `false`) and
/// `compliance` (`dense`, `fft` or `mixed`), and the last, `warnings` (free text, quoted when
/// it holds a comma).
fn csv_is_sound(text: &str) -> Result<(), String> {
    let header: Vec<&str> = text.lines().next().unwrap_or("").split(',').collect();
    assert_eq!(header.last(), Some(&"warnings"), "{header:?}");
    for (i, line) in text.lines().enumerate().skip(1) {
        // The cells before the last, free-text one.
        for (j, cell) in line.split(',').take(header.len() - 1).enumerate() {
            let sound = match header.get(j).copied() {
                Some("status") => !cell.is_empty(),
                Some("solver") => cell == "native" || cell == "clarabel",
                Some("warm_start") => cell == "true" || cell == "false",
                Some("compliance") => ["dense", "fft", "mixed"].contains(&cell),
                // Empty unless the run computed margins (--margins), or undetermined; `inf`
                // when unbounded.
                Some("smallest_margin_n") if cell.is_empty() || cell == "inf" => true,
                Some("margin_held_to_n") if cell.is_empty() => true,
                _ => cell.parse::<f64>().is_ok_and(f64::is_finite),
            };
            if !sound {
                return Err(format!("row {i} column {j}: `{cell}`"));
            }
        }
    }
    Ok(())
}

/// `lines` batch result lines, each sound: solved ones with finite forces and residuals within
/// tolerance, invalid ones with problems (path and fix), the others with a reason.
// `!(x <= tol)` is meant: a NaN residual must fail.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn results_are_sound(text: &str, lines: usize) -> Result<(), String> {
    let got: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    if got.len() != lines {
        return Err(format!(
            "{} result lines for {lines} input lines",
            got.len()
        ));
    }
    for (k, line) in got.iter().enumerate() {
        let v: Value = serde_json::from_str(line).map_err(|e| format!("line {k}: {e}"))?;
        let bad = non_finite_keys(&v, &NULLABLE);
        if !bad.is_empty() {
            return Err(format!("line {k}: null or non-finite numbers at {bad:?}"));
        }
        match v["status"].as_str() {
            Some("solved") => {
                let x = v["worst_residual"].as_f64().unwrap_or(f64::NAN);
                if !(x <= RESIDUAL_TOLERANCE) {
                    return Err(format!("line {k}: solved with worst residual {x:e}"));
                }
            }
            Some("reduced_accuracy") => {}
            Some("invalid") => {
                let problems = v["problems"].as_array().map_or(0, Vec::len);
                let named = v["problems"].as_array().is_some_and(|p| {
                    p.iter()
                        .all(|q| q["path"].is_string() && q["fix"].is_string())
                });
                if problems == 0 || !named {
                    return Err(format!("line {k}: invalid without problems: {line}"));
                }
            }
            Some("no_equilibrium" | "no_convergence") => {
                if v["reason"].as_str().is_none_or(str::is_empty) {
                    return Err(format!("line {k}: no reason: {line}"));
                }
            }
            other => return Err(format!("line {k}: status {other:?}")),
        }
    }
    Ok(())
}

/// Sweep variants: each line `{"id", "vary", "scene"}` with a scene object.
fn variants_are_sound(text: &str) -> Result<(), String> {
    for (k, line) in text.lines().enumerate() {
        let v: Value = serde_json::from_str(line).map_err(|e| format!("line {k}: {e}"))?;
        if !(v["id"].is_string() && v["vary"].is_object() && v["scene"].is_object()) {
            return Err(format!("line {k} is not a variant: {line:.200}"));
        }
    }
    Ok(())
}

/// A margin report: finite numbers (only the keys of [`NULLABLE`] null), a margin per
/// direction at most where it fails.
fn margins_are_sound(text: &str) -> Result<(), String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("JSON: {e}"))?;
    let bad = non_finite_keys(&v, &NULLABLE);
    if !bad.is_empty() {
        return Err(format!("null or non-finite numbers at {bad:?}"));
    }
    for d in v["directions"].as_array().ok_or("no directions")? {
        // A margin exactly when a magnitude that fails was found; else how far it held.
        let m = d["held_to_n"].as_f64().ok_or("no held_to_n")?;
        if d["margin_n"].as_f64() != d["fails_at_n"].as_f64().map(|_| m) {
            return Err(format!(
                "margin_n is not held_to_n with a failing magnitude: {d}"
            ));
        }
        if m < 0.0 || d["fails_at_n"].as_f64().is_some_and(|h| h < m) {
            return Err(format!("margin {m} above where it fails: {d}"));
        }
    }
    Ok(())
}

/// A message naming where the input is wrong: a JSON path, the file position, or the flag.
fn names_a_path(stderr: &str) -> bool {
    let paths = [
        "object.",
        "object:",
        "fingers[",
        "fingers.",
        "fingers:",
        "planar",
        "model:",
        "time.",
        "time:",
        "external",
        "description:",
        ".: ",
        "(after the document)",
        " at line ",
        "--vary",
        "--length",
        "--tolerance",
        "--directions",
        "directions[",
    ];
    paths.iter().any(|p| stderr.contains(p))
}

/// The longest run of digits in `text`: a number written in full (1e308 has 309 digits).
fn longest_digit_run(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// The verdict on one run of a mutant of `class`.
fn check(
    t: &mut Tally,
    (class, what): (usize, &str),
    out: Result<(Option<i32>, String, String, f64), String>,
    (output, kind): (&Path, Output),
) {
    t.classes[class][0] += 1;
    let (code, stdout, stderr, secs) = match out {
        Ok(o) => o,
        Err(e) => return t.failures.push(format!("{what}: {e}")),
    };
    t.slowest_s = t.slowest_s.max(secs);
    if code == Some(101) || stderr.contains("panicked") {
        t.panics += 1;
        return t.failures.push(format!("{what}: panic\n{stderr}"));
    }
    let all = format!("{stdout}{stderr}");
    let verdict = match code {
        Some(0) => {
            let body = std::fs::read_to_string(output).unwrap_or_default();
            let sound = match kind {
                Output::Solution => solution_is_sound(&body),
                Output::History => csv_is_sound(&body),
                Output::Results(n) => results_are_sound(&body, n),
                Output::Variants => variants_are_sound(&body),
                Output::Margins => margins_are_sound(&body),
            };
            sound.map_err(|e| {
                t.garbage_exit_0 += 1;
                format!("exit 0 with garbage: {e}")
            })
        }
        Some(1) if names_a_path(&stderr) => Ok(()),
        Some(1) => Err(format!("exit 1 without a JSON path: {stderr}")),
        Some(2) => {
            let reasons = [
                "no equilibrium",
                "no convergence",
                "cannot hold",
                "failed steps: ",
                "does not hold",
            ];
            match reasons.iter().any(|r| all.contains(r)) {
                true => Ok(()),
                false => Err(format!("exit 2 without a reason: {all}")),
            }
        }
        other => Err(format!("exit {other:?} (signal or unknown code): {stderr}")),
    };
    // Numbers in messages are readable (the output files may hold long ids, not messages).
    let verdict = verdict.and_then(|()| match longest_digit_run(&all) {
        n if n > 20 => Err(format!("a number written out in full ({n} digits): {all}")),
        _ => Ok(()),
    });
    if let Some(c) = code.filter(|c| (0..3).contains(c)) {
        t.exits[c as usize] += 1;
        t.classes[class][1 + c as usize] += 1;
    }
    if let Err(e) = verdict {
        t.failures.push(format!("{what}: {e}"));
    }
}

/// Where a mutant is written and run: the fuzz folder and the mutant's number.
struct Slot<'a> {
    dir: &'a Path,
    k: usize,
}

impl Slot<'_> {
    fn path(&self, name: &str) -> PathBuf {
        self.dir.join(format!("m{}.{name}", self.k))
    }
    /// A folder of its own (for inputs that name files relative to themselves).
    fn folder(&self) -> PathBuf {
        let d = self.dir.join(format!("m{}", self.k));
        std::fs::create_dir_all(&d).unwrap();
        d
    }
}

/// `solve` of a scene text written at `input`.
fn solve_mutant(t: &mut Tally, class: usize, what: &str, input: &Path, slot: &Slot) {
    let out = slot.path("solution.json");
    let args = [
        "solve",
        input.to_str().unwrap(),
        "--json",
        out.to_str().unwrap(),
        "--max-memory",
        "256M",
        "--force",
    ];
    check(t, (class, what), run(&args), (&out, Output::Solution));
}

/// `transfer` of `scene` with the schedule written at `input`.
fn transfer_mutant(
    t: &mut Tally,
    class: usize,
    what: &str,
    (scene, input): (&Path, &Path),
    slot: &Slot,
) {
    let out = slot.path("csv");
    let args = [
        "transfer",
        scene.to_str().unwrap(),
        "--schedule",
        input.to_str().unwrap(),
        "--csv",
        out.to_str().unwrap(),
        "--max-memory",
        "256M",
        "--force",
    ];
    check(t, (class, what), run(&args), (&out, Output::History));
}

/// A scene with a primitive shape, mutated under `object.shape` or a finger's `place`.
fn shape_mutant(t: &mut Tally, rng: &mut Rng, slot: &Slot) {
    let s = *rng.pick(&[
        "box_pinch.json",
        "sphere_three_fingers.json",
        "cylinder_handoff.json",
    ]);
    let prefix = *rng.pick(&[
        "/object/shape",
        "/fingers/0/place",
        "/fingers/1/place",
        "/object",
    ]);
    let (text, what) = mutant_under(&load(s), rng, prefix);
    let input = slot.path("json");
    std::fs::write(&input, &text).unwrap();
    let what = format!("shape mutant {} of {s} ({})", slot.k, what.join("; "));
    solve_mutant(t, 1, &what, &input, slot);
}

/// One mutation of an OBJ text: a vertex or face made garbage, a line deleted or doubled, the
/// file cut short.
fn mutate_obj(obj: &str, rng: &mut Rng) -> (String, String) {
    let mut lines: Vec<String> = obj.lines().map(String::from).collect();
    let i = rng.below(lines.len());
    let what = match rng.below(6) {
        0 | 1 if lines[i].starts_with("v ") || rng.below(2) == 0 => {
            let x = *rng.pick(&[
                "nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "abc", "1e30", "",
            ]);
            let j = 1 + rng.below(3);
            let mut parts: Vec<String> = lines[i].split(' ').map(String::from).collect();
            if parts[0] != "v" {
                // The first vertex line instead.
                let v = lines.iter().position(|l| l.starts_with("v ")).unwrap_or(0);
                parts = lines[v].split(' ').map(String::from).collect();
                parts.resize(4, "0".into());
                parts[j] = x.into();
                lines[v] = parts.join(" ");
                return (
                    lines.join("\n"),
                    format!("line {v}: coordinate {j} = {x:?}"),
                );
            }
            parts.resize(4, "0".into());
            parts[j] = x.into();
            lines[i] = parts.join(" ");
            format!("line {i}: coordinate {j} = {x:?}")
        }
        2 => {
            let f = lines.iter().rposition(|l| l.starts_with("f ")).unwrap_or(i);
            let idx = *rng.pick(&[
                "0",
                "-1",
                "-99999",
                "99999",
                "4294967296",
                "1/2/3",
                "x",
                "1.5",
            ]);
            let mut parts: Vec<String> = lines[f].split(' ').map(String::from).collect();
            let j = 1 + rng.below(parts.len().saturating_sub(1).max(1));
            if j < parts.len() {
                parts[j] = idx.into();
            }
            lines[f] = parts.join(" ");
            format!("line {f}: face index {j} = {idx:?}")
        }
        3 => {
            lines.remove(i);
            format!("line {i} deleted")
        }
        4 => {
            let l = lines[i].clone();
            lines.insert(i, l);
            format!("line {i} doubled")
        }
        _ => {
            let keep = rng.below(lines.len());
            lines.truncate(keep);
            format!("cut after {keep} lines")
        }
    };
    (lines.join("\n"), what)
}

/// The mug scene with its OBJ mutated, or its mesh `unit` / `scale`.
fn mesh_mutant(t: &mut Tally, rng: &mut Rng, slot: &Slot) {
    let folder = slot.folder();
    std::fs::create_dir_all(folder.join("meshes")).unwrap();
    let obj = std::fs::read_to_string(examples().join("meshes/mug.obj")).unwrap();
    let mut scene = load("mug_power_grasp.json");
    let what = if rng.below(4) == 0 {
        std::fs::write(folder.join("meshes/mug.obj"), &obj).unwrap();
        let (key, value) = match rng.below(2) {
            0 => (
                "unit",
                rng.pick(&[json!("furlong"), json!(""), json!(1), json!("M")])
                    .clone(),
            ),
            _ => (
                "scale",
                json!(*rng.pick(&[1e308, 1e-308, 0.0, -1.0, 1e6, 1e-6])),
            ),
        };
        scene["object"]["shape"]["mesh"][key] = value.clone();
        format!("mesh.{key} = {value}")
    } else {
        let (text, what) = mutate_obj(&obj, rng);
        std::fs::write(folder.join("meshes/mug.obj"), text).unwrap();
        what
    };
    let input = folder.join("scene.json");
    std::fs::write(&input, scene.to_string()).unwrap();
    let what = format!("mesh mutant {} ({what})", slot.k);
    solve_mutant(t, 2, &what, &input, slot);
}

/// One mutation of a CSV text: a cell made garbage, the header renamed, a row deleted or
/// doubled, a cell added.
fn mutate_csv(csv: &str, rng: &mut Rng) -> (String, String) {
    let mut rows: Vec<Vec<String>> = csv
        .lines()
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    let r = rng.below(rows.len());
    let c = rng.below(rows[r].len());
    let what = match rng.below(5) {
        0 | 1 => {
            let x = *rng.pick(&[
                "nan", "inf", "1e308", "-1e308", "abc", "", "1e-320", "5", "-5",
            ]);
            rows[r][c] = x.into();
            format!("row {r} cell {c} = {x:?}")
        }
        2 => {
            rows[0][c] = "renamed".into();
            format!("column {c} renamed")
        }
        3 => {
            let row = rows.remove(r.max(1).min(rows.len() - 1));
            if rng.below(2) == 0 {
                rows.insert(1, row);
                "a row moved first".to_string()
            } else {
                format!("row {r} deleted")
            }
        }
        _ => {
            rows[r].push("7".into());
            format!("row {r}: a cell added")
        }
    };
    let text = rows
        .iter()
        .map(|r| r.join(","))
        .collect::<Vec<_>>()
        .join("\n");
    (text, what)
}

/// A task-load schedule (an external wrench ramp or CSV) mutated, mostly under `external`, or
/// its CSV.
fn external_mutant(t: &mut Tally, rng: &mut Rng, slot: &Slot) {
    let folder = slot.folder();
    let name = *rng.pick(&["plate_bump", "plate_pull"]);
    let csv = std::fs::read_to_string(examples().join("plate_bump.csv")).unwrap();
    let base = short_schedule(&format!("{name}.schedule.json"));
    let (text, csv, what) = if name == "plate_bump" && rng.below(2) == 0 {
        let (c, w) = mutate_csv(&csv, rng);
        (base.to_string(), c, vec![format!("CSV: {w}")])
    } else {
        let (text, what) = mutant_under(&base, rng, "/external");
        (text, csv, what)
    };
    std::fs::write(folder.join("plate_bump.csv"), csv).unwrap();
    let input = folder.join("schedule.json");
    std::fs::write(&input, &text).unwrap();
    let scene = examples().join("plate_handoff_coulomb.json");
    let what = format!(
        "external-load mutant {} of {name} ({})",
        slot.k,
        what.join("; ")
    );
    transfer_mutant(t, 4, &what, (&scene, &input), slot);
}

/// A JSONL of 2 to 5 lines: mutated scenes with ids, bare, or broken lines.
fn batch_mutant(t: &mut Tally, rng: &mut Rng, slot: &Slot, scenes: &[&str]) {
    let mut lines = Vec::new();
    let mut what = Vec::new();
    for j in 0..2 + rng.below(4) {
        let s = *rng.pick(scenes);
        let (text, w) = mutant(&load(s), rng);
        let line = match rng.below(6) {
            0 => text.replace('\n', " "),
            1 => r#"{"id": "x", "scene": "#.to_string() + &text.replace('\n', " "),
            2 => (*rng.pick(&["{", "[]", "null", "42", "{\"id\": 7}", "\"scene\""])).to_string(),
            _ => {
                let scene: Value =
                    serde_json::from_str(&text).unwrap_or_else(|_| json!(text.clone()));
                json!({"id": format!("s{j}"), "scene": scene}).to_string()
            }
        };
        what.push(format!("line {j}: {s} ({})", w.join("; ")));
        lines.push(line);
    }
    let input = slot.path("jsonl");
    std::fs::write(&input, lines.join("\n") + "\n").unwrap();
    let out = slot.path("results.jsonl");
    let args = [
        "batch",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "2",
        "--max-memory",
        "256M",
        "--force",
    ];
    let what = format!("batch mutant {} ({})", slot.k, what.join(" | "));
    check(
        t,
        (5, &what),
        run(&args),
        (&out, Output::Results(lines.len())),
    );
}

/// A `--vary` spec: a path (valid or not) and a range or list of values (valid or garbage).
fn sweep_spec(rng: &mut Rng) -> String {
    let path = *rng.pick(&[
        "object.weight",
        "fingers[*].friction.mu",
        "fingers[0].patch.size[0]",
        "object.center_of_mass[2]",
        "fingers[0].material.youngs_modulus",
        "fingers[1].patch.grid[0]",
        "fingers[99].friction.mu",
        "fingers[*]",
        "object",
        "a..b",
        "",
        "fingers[18446744073709551616].friction.mu",
    ]);
    let number = |rng: &mut Rng| -> String {
        match rng.below(3) {
            0 => format!("{:e}", rng.pick(&EXTREMES)),
            1 => (*rng.pick(&["nan", "inf", "abc", "", "1e400"])).to_string(),
            _ => format!("{}", 0.1 * (1 + rng.below(20)) as f64),
        }
    };
    let values = match rng.below(3) {
        0 | 1 => {
            let n = *rng.pick(&[
                "1", "2", "3", "7", "20", "0", "-1", "100001", "nan", "1e3", "x",
            ]);
            format!("{}:{}:{n}", number(rng), number(rng))
        }
        _ => (0..1 + rng.below(4))
            .map(|_| number(rng))
            .collect::<Vec<_>>()
            .join(","),
    };
    format!("{path}={values}")
}

/// `sweep` of an example with 1 or 2 mutated axes (or four of 65536 values, a grid whose count
/// overflows), written out or (sometimes) run.
fn sweep_mutant(t: &mut Tally, rng: &mut Rng, slot: &Slot) {
    let s = *rng.pick(&[
        "cube_a.json",
        "plate_four_fingers.json",
        "disc_three_fingers.json",
    ]);
    let specs: Vec<String> = match rng.below(10) {
        0 => vec!["object.weight=1:2:65536".into(); 4],
        _ => (0..1 + rng.below(2)).map(|_| sweep_spec(rng)).collect(),
    };
    let run_it = rng.below(3) == 0;
    let scene = examples().join(s);
    let out = slot.path("sweep.jsonl");
    let mut args: Vec<String> = vec!["sweep".into(), scene.display().to_string()];
    for v in &specs {
        args.push(format!("--vary={v}"));
    }
    args.extend(["--out".into(), out.display().to_string(), "--force".into()]);
    args.extend([
        "--max-memory".into(),
        "256M".into(),
        "--jobs".into(),
        "2".into(),
    ]);
    if run_it {
        args.push("--run".into());
    }
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let what = format!("sweep mutant {} of {s} ({specs:?}, run {run_it})", slot.k);
    let result = run(&argv);
    // With --run the output is result lines, one per variant of the grid written.
    let kind = match &result {
        Ok((Some(0), ..)) if run_it => {
            let n = std::fs::read_to_string(&out).map_or(0, |b| b.lines().count());
            Output::Results(n)
        }
        _ => Output::Variants,
    };
    check(t, (6, &what), result, (&out, kind));
}

/// `margin` of an example with mutated `--length`, `--tolerance` and `--directions` (a count,
/// `planes:K`, or a mutated directions file).
fn margin_mutant(t: &mut Tally, rng: &mut Rng, slot: &Slot) {
    let s = *rng.pick(&[
        "plate_handoff_coulomb.json",
        "box_pinch.json",
        "disc_three_fingers.json",
    ]);
    let value = |rng: &mut Rng, normal: &[&str]| -> String {
        match rng.below(3) {
            0 => format!("{:e}", rng.pick(&EXTREMES)),
            1 => (*rng.pick(&["nan", "inf", "-inf", "2e-16", "1e-300", "1e305", "0"])).to_string(),
            _ => (*rng.pick(normal)).to_string(),
        }
    };
    let mut args: Vec<String> = vec!["margin".into(), examples().join(s).display().to_string()];
    let mut what = Vec::new();
    if rng.below(2) == 0 {
        let l = value(rng, &["0.05", "1e-9", "1000", "0.5", "1e-3"]);
        what.push(format!("--length {l}"));
        args.push(format!("--length={l}"));
    }
    if rng.below(2) == 0 {
        let tol = value(rng, &["1e-3", "1e-9", "0.5", "0.1", "1e-6"]);
        what.push(format!("--tolerance {tol}"));
        args.push(format!("--tolerance={tol}"));
    }
    let dirs = match rng.below(4) {
        0 => (*rng.pick(&["1", "2", "3", "0", "10001", "-1", "nan"])).to_string(),
        1 => (*rng.pick(&["planes:4", "planes:3", "planes:361", "planes:x"])).to_string(),
        2 => {
            let base = json!([{"force": [0.0, 0.0, -1.0]}, {"torque": [1.0, 0.0, 0.0]},
                              {"force": [1.0, 0.0, 0.0], "torque": [0.0, 0.0, 0.5]}]);
            let (text, w) = mutant(&base, rng);
            let file = slot.path("directions.json");
            std::fs::write(&file, text).unwrap();
            what.push(format!("directions file: {}", w.join("; ")));
            file.display().to_string()
        }
        _ => "2".into(),
    };
    what.push(format!("--directions {dirs}"));
    args.push(format!("--directions={dirs}"));
    let out = slot.path("margins.json");
    args.extend(["--json".into(), out.display().to_string(), "--force".into()]);
    args.extend(["--max-memory".into(), "256M".into()]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let what = format!("margin mutant {} of {s} ({})", slot.k, what.join(", "));
    check(t, (7, &what), run(&argv), (&out, Output::Margins));
}

#[test]
fn mutated_inputs_never_panic_hang_or_report_garbage() {
    let n: usize = std::env::var("GRASP_FUZZ_MUTANTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(900);
    let dir = std::env::temp_dir().join(format!("grasp-fuzz-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scenes = [
        "cube_a.json",
        "cube_b.json",
        "plate_four_fingers.json",
        "disc_three_fingers.json",
        "pipe_three_fingers.json",
        "hertz_sphere_on_flat.json",
        "plate_handoff_coulomb.json",
    ];
    let hand_offs = ["plate_transfer", "disc_transfer", "plate_handoff_coulomb"];
    let mut rng = Rng(SEED);
    let mut t = Tally::default();
    let start = Instant::now();
    for k in 0..n {
        let slot = Slot { dir: &dir, k };
        // Classes by weight (per 20): scenes 7, shapes 2, meshes 2, schedules 3, external
        // loads 2, batch lines 1.5, sweep specs 1.5, margin options 1.
        match rng.below(40) {
            0..=13 => {
                let s = *rng.pick(&scenes);
                let (text, what) = mutant(&load(s), &mut rng);
                let input = slot.path("json");
                std::fs::write(&input, &text).unwrap();
                let what = format!("scene mutant {k} of {s} ({})", what.join("; "));
                solve_mutant(&mut t, 0, &what, &input, &slot);
            }
            14..=17 => shape_mutant(&mut t, &mut rng, &slot),
            18..=21 => mesh_mutant(&mut t, &mut rng, &slot),
            22..=27 => {
                let h = *rng.pick(&hand_offs);
                let (text, what) = mutant(&short_schedule(&format!("{h}.schedule.json")), &mut rng);
                let input = slot.path("schedule.json");
                std::fs::write(&input, &text).unwrap();
                let scene = examples().join(format!("{h}.json"));
                let what = format!("schedule mutant {k} of {h} ({})", what.join("; "));
                transfer_mutant(&mut t, 3, &what, (&scene, &input), &slot);
            }
            28..=31 => external_mutant(&mut t, &mut rng, &slot),
            32..=34 => batch_mutant(&mut t, &mut rng, &slot, &scenes),
            35..=37 => sweep_mutant(&mut t, &mut rng, &slot),
            _ => margin_mutant(&mut t, &mut rng, &slot),
        }
    }
    let classes: Vec<String> = CLASSES
        .iter()
        .zip(&t.classes)
        .map(|(name, c)| format!("{name} {} (exit 0/1/2: {}/{}/{})", c[0], c[1], c[2], c[3]))
        .collect();
    println!(
        "mutation fuzz: {n} mutants: {}; exit 0: {}, exit 1: {}, exit 2: {}, panics {}, \
         garbage-with-exit-0 {}, other failures {}; slowest run {:.2} s, all {:.1} s (seed \
         {SEED:#x})",
        classes.join(", "),
        t.exits[0],
        t.exits[1],
        t.exits[2],
        t.panics,
        t.garbage_exit_0,
        t.failures.len(),
        t.slowest_s,
        start.elapsed().as_secs_f64()
    );
    assert!(
        t.failures.is_empty(),
        "mutants in {}:\n{}",
        dir.display(),
        t.failures.join("\n")
    );
    assert!(
        t.exits.iter().all(|&c| c > 0),
        "every exit code should occur: {:?}",
        t.exits
    );
    assert!(
        t.classes.iter().all(|c| c[0] > 0) || n < 100,
        "every class should be run: {classes:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
