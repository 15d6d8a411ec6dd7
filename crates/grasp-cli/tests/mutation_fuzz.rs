//! Mutation fuzzing of the input formats through the `grasp` binary: a seeded (deterministic)
//! generator mutates the example scenes and schedules (deleted keys, extreme and non-finite
//! numbers, wrong types, huge grids, trailing data, duplicated keys) and every mutant is run
//! with a timeout, a memory limit (`--max-memory 256M` and an address-space limit of 4 GiB).
//!
//! Asserted for every mutant: no panic (exit 101 or "panicked"), no death by a signal or the
//! timeout; exit 0 only with finite numbers in the outputs and residuals within tolerance
//! (equilibrium and cone violation <= 1e-6 of the load); exit 1 with a JSON path (or the file
//! position) in the message; exit 2 with a reason. One summary line with the counts is printed
//! (run with `--show-output`). `GRASP_FUZZ_MUTANTS` changes the number of mutants (default 600).

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
/// grid); returns what it did.
fn mutate(v: &mut Value, rng: &mut Rng) -> String {
    let mut ptrs = Vec::new();
    pointers(v, String::new(), &mut ptrs);
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
    let mut v = base.clone();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(2) {
        what.push(mutate(&mut v, rng));
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

#[derive(Default)]
struct Tally {
    mutants: usize,
    scenes: usize,
    schedules: usize,
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

/// Every number in a solution JSON is finite (NaN and infinities serialize as `null`; only
/// `reason` and `sequential` may be null) and its residuals are within tolerance.
// `!(x <= tol)` is meant: a NaN residual must fail.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn solution_is_sound(text: &str) -> Result<(), String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("JSON: {e}"))?;
    fn walk(v: &Value, key: &str, bad: &mut Vec<String>) {
        match v {
            Value::Null if !matches!(key, "reason" | "sequential") => bad.push(key.into()),
            Value::Number(n) if !n.as_f64().is_some_and(f64::is_finite) => bad.push(key.into()),
            Value::Object(m) => m.iter().for_each(|(k, x)| walk(x, k, bad)),
            Value::Array(a) => a.iter().for_each(|x| walk(x, key, bad)),
            _ => {}
        }
    }
    let mut bad = Vec::new();
    walk(&v, "", &mut bad);
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

/// Every cell of a force-history CSV is a finite number, except the three text columns
/// named in its header: `status`, `solver` (`native` or `clarabel`) and `warm_start`
/// (`true` or `false`).
fn csv_is_sound(text: &str) -> Result<(), String> {
    let header: Vec<&str> = text.lines().next().unwrap_or("").split(',').collect();
    for (i, line) in text.lines().enumerate().skip(1) {
        for (j, cell) in line.split(',').enumerate() {
            let sound = match header.get(j).copied() {
                Some("status") => !cell.is_empty(),
                Some("solver") => cell == "native" || cell == "clarabel",
                Some("warm_start") => cell == "true" || cell == "false",
                // Empty unless the run computed margins (--margins).
                Some("smallest_margin_n") if cell.is_empty() => true,
                _ => cell.parse::<f64>().is_ok_and(f64::is_finite),
            };
            if !sound {
                return Err(format!("row {i} column {j}: `{cell}`"));
            }
        }
    }
    Ok(())
}

/// A message naming where the input is wrong: a JSON path, or the file position.
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
        "description:",
        ".: ",
        "(after the document)",
        " at line ",
    ];
    paths.iter().any(|p| stderr.contains(p))
}

fn check(
    t: &mut Tally,
    what: &str,
    out: Result<(Option<i32>, String, String, f64), String>,
    output: &Path,
    is_csv: bool,
) {
    let (code, stdout, stderr, secs) = match out {
        Ok(o) => o,
        Err(e) => return t.failures.push(format!("{what}: {e}")),
    };
    t.slowest_s = t.slowest_s.max(secs);
    if code == Some(101) || stderr.contains("panicked") {
        t.panics += 1;
        return t.failures.push(format!("{what}: panic\n{stderr}"));
    }
    let verdict = match code {
        Some(0) => {
            let body = std::fs::read_to_string(output).unwrap_or_default();
            let sound = if is_csv {
                csv_is_sound(&body)
            } else {
                solution_is_sound(&body)
            };
            sound.map_err(|e| {
                t.garbage_exit_0 += 1;
                format!("exit 0 with garbage: {e}")
            })
        }
        Some(1) if names_a_path(&stderr) => Ok(()),
        Some(1) => Err(format!("exit 1 without a JSON path: {stderr}")),
        Some(2) => {
            let all = format!("{stdout}{stderr}");
            let reasons = [
                "no equilibrium",
                "no convergence",
                "cannot hold",
                "failed steps: ",
            ];
            match reasons.iter().any(|r| all.contains(r)) {
                true => Ok(()),
                false => Err(format!("exit 2 without a reason: {all}")),
            }
        }
        other => Err(format!("exit {other:?} (signal or unknown code): {stderr}")),
    };
    if let Some(c) = code.filter(|c| (0..3).contains(c)) {
        t.exits[c as usize] += 1;
    }
    if let Err(e) = verdict {
        t.failures.push(format!("{what}: {e}"));
    }
}

#[test]
fn mutated_scenes_and_schedules_never_panic_or_report_garbage() {
    let n: usize = std::env::var("GRASP_FUZZ_MUTANTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
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
        t.mutants += 1;
        let input = dir.join(format!("m{k}.json"));
        if rng.below(4) == 0 {
            t.schedules += 1;
            let h = *rng.pick(&hand_offs);
            let (text, what) = mutant(&short_schedule(&format!("{h}.schedule.json")), &mut rng);
            std::fs::write(&input, &text).unwrap();
            let out = dir.join(format!("m{k}.csv"));
            let scene = examples().join(format!("{h}.json"));
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
            check(
                &mut t,
                &format!("schedule mutant {k} of {h} ({})", what.join("; ")),
                run(&args),
                &out,
                true,
            );
        } else {
            t.scenes += 1;
            let s = *rng.pick(&scenes);
            let (text, what) = mutant(&load(s), &mut rng);
            std::fs::write(&input, &text).unwrap();
            let out = dir.join(format!("m{k}.solution.json"));
            let args = [
                "solve",
                input.to_str().unwrap(),
                "--json",
                out.to_str().unwrap(),
                "--max-memory",
                "256M",
                "--force",
            ];
            check(
                &mut t,
                &format!("scene mutant {k} of {s} ({})", what.join("; ")),
                run(&args),
                &out,
                false,
            );
        }
    }
    println!(
        "mutation fuzz: {} mutants ({} scenes, {} schedules), exit 0: {}, exit 1: {}, exit 2: {}, \
         panics {}, garbage-with-exit-0 {}, other failures {}; slowest run {:.2} s, all {:.1} s (seed {SEED:#x})",
        t.mutants, t.scenes, t.schedules, t.exits[0], t.exits[1], t.exits[2], t.panics,
        t.garbage_exit_0, t.failures.len(), t.slowest_s, start.elapsed().as_secs_f64()
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
    let _ = std::fs::remove_dir_all(&dir);
}
