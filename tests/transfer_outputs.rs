//! Hand-off outputs: the MCAP log read back with the `mcap` crate (channels, schemas, counts,
//! values equal to the in-memory results, deterministic bytes), the `.rrd`'s deterministic
//! bytes before Rerun's footer, the CSV history, and the independent `rerun` CLI (Python
//! package rerun-sdk==0.36.3, installed by scripts/install-checkers.sh) accepting the `.mcap`
//! and the `.rrd`.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command as Process;

use grasp_model::LOADED_FRACTION;
use grasp_transfer::{
    CsvSink, FailedStep, Fallbacks, FingersMessage, MarginCost, McapSink, RerunSink, Sink,
    SlipMargin, StepRecord, TransferOptions, TransferSummary, FINGERS_TOPIC, PATCHES_TOPIC,
    SCENE_TOPIC,
};

fn out_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-outputs-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the plate hand-off into `dir` (plate.mcap, plate.rrd, plate.csv).
fn run_plate(dir: &Path) -> Vec<StepRecord> {
    let (scene, schedule) = support::transfer_example("plate_transfer");
    let mut m = McapSink::create(&dir.join("plate.mcap")).unwrap();
    let mut r = RerunSink::create(&dir.join("plate.rrd")).unwrap();
    let mut c = CsvSink::create(&dir.join("plate.csv")).unwrap();
    let mut sinks: Vec<&mut dyn Sink> = vec![&mut m, &mut r, &mut c];
    let (records, _) =
        grasp_transfer::run_collect(&scene, &schedule, TransferOptions::default(), &mut sinks)
            .unwrap();
    records
}

#[test]
fn mcap_reads_back_as_written() {
    let dir = out_dir("read");
    let records = run_plate(&dir);
    let bytes = std::fs::read(dir.join("plate.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("summary written");
    let stats = summary.stats.as_ref().expect("statistics written");
    // Fingers and patches per step; the scene: the object once, then the forces per step.
    assert_eq!(stats.message_count, 3 * records.len() as u64 + 1);
    let mut topics: Vec<(String, String, String, String)> = summary
        .channels
        .values()
        .map(|c| {
            let s = c.schema.as_ref().expect("schema");
            (
                c.topic.clone(),
                c.message_encoding.clone(),
                s.name.clone(),
                s.encoding.clone(),
            )
        })
        .collect();
    topics.sort();
    assert_eq!(
        topics,
        vec![
            (
                FINGERS_TOPIC.into(),
                "json".into(),
                "grasp.FingerResultants".into(),
                "jsonschema".into()
            ),
            (
                PATCHES_TOPIC.into(),
                "json".into(),
                "grasp.PatchFields".into(),
                "jsonschema".into()
            ),
            (
                SCENE_TOPIC.into(),
                "json".into(),
                "foxglove.SceneUpdate".into(),
                "jsonschema".into()
            ),
        ]
    );
    for c in summary.channels.values() {
        let schema: serde_json::Value =
            serde_json::from_slice(&c.schema.as_ref().unwrap().data).unwrap();
        assert_eq!(schema["type"], "object");
        let extra = u64::from(c.topic == SCENE_TOPIC);
        assert_eq!(
            stats.channel_message_counts[&c.id],
            records.len() as u64 + extra
        );
    }
    assert!(!summary.chunk_indexes.is_empty(), "chunk index written");

    let mut fingers = Vec::new();
    let mut patches = 0;
    let mut scene_ids = Vec::new();
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        match msg.channel.topic.as_str() {
            FINGERS_TOPIC => fingers.push((
                msg.log_time,
                serde_json::from_slice::<FingersMessage>(&msg.data).unwrap(),
            )),
            PATCHES_TOPIC => {
                let v: serde_json::Value = serde_json::from_slice(&msg.data).unwrap();
                let r = &records[patches];
                assert_eq!(
                    v["patches"].as_array().unwrap().len(),
                    r.solution.fingers.len()
                );
                let e0 = &r.solution.fingers[0].elements[3];
                assert_eq!(
                    v["patches"][0]["elements"][3]["normal_force_n"]
                        .as_f64()
                        .unwrap(),
                    e0.normal_force_n
                );
                patches += 1;
            }
            SCENE_TOPIC => {
                let v: serde_json::Value = serde_json::from_slice(&msg.data).unwrap();
                let ids: Vec<&str> = v["entities"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|e| e["id"].as_str().unwrap())
                    .collect();
                scene_ids.push(ids.join(","));
            }
            t => panic!("unexpected topic {t}"),
        }
    }
    assert_eq!(patches, records.len());
    assert_eq!(fingers.len(), records.len());
    // The object, contact points and fingertips first, then one set of force arrows per step.
    assert_eq!(scene_ids[0], "object,contacts,fingertips");
    assert!(
        scene_ids[1..].iter().all(|ids| ids == "forces") && scene_ids.len() == records.len() + 1
    );
    for ((log_time, m), r) in fingers.iter().zip(&records) {
        assert_eq!(
            *log_time,
            (r.time_s * 1e9).round() as u64,
            "log time is schedule time"
        );
        // JSON round trip of f64 is exact (shortest round-trip representation).
        assert_eq!(m, &FingersMessage::from_record(r));
        for f in &m.fingers {
            assert_eq!(f.normal_force_n, r.normal_force_n(&f.name));
        }
    }
}

#[test]
fn mcap_is_deterministic() {
    let (a, b) = (out_dir("det-a"), out_dir("det-b"));
    run_plate(&a);
    run_plate(&b);
    assert_eq!(
        std::fs::read(a.join("plate.mcap")).unwrap(),
        std::fs::read(b.join("plate.mcap")).unwrap()
    );
}

/// The recording is byte-identical from run to run up to its footer, and the footer holds the
/// same manifests (Rerun 0.36 lists them, and each one's schema fields, in hash-map order: see
/// the Rerun sink, `crates/grasp-transfer/src/sinks/rerun_log.rs`). Two runs in one process:
/// every random id the SDK would draw differs between them, so a run-dependent id anywhere
/// before the footer fails this.
#[test]
fn rrd_is_deterministic_up_to_rerun_s_footer() {
    let (a, b) = (out_dir("det-rrd-a"), out_dir("det-rrd-b"));
    run_plate(&a);
    run_plate(&b);
    let a = std::fs::read(a.join("plate.rrd")).unwrap();
    let b = std::fs::read(b.join("plate.rrd")).unwrap();
    let (data_a, manifests_a) = rrd_parts(&a);
    let (data_b, manifests_b) = rrd_parts(&b);
    assert!(
        data_a.len() > a.len() / 2,
        "{} of {} bytes",
        data_a.len(),
        a.len()
    );
    let first_difference = data_a.iter().zip(data_b).position(|(x, y)| x != y);
    assert!(
        data_a.len() == data_b.len() && first_difference.is_none(),
        "{} and {} bytes before the footer, first difference at {first_difference:?}",
        data_a.len(),
        data_b.len()
    );
    assert_eq!(manifests_a.len(), 2, "the recording's and the layout's");
    assert!(manifests_a == manifests_b, "the footers' manifests differ");
}

/// One store's manifest in an `.rrd` footer: store id, schema hash, chunk table (protobuf
/// fields 1, 3 and 4 of `RrdManifest`; field 2, the schema itself, lists its fields in
/// hash-map order and is left out: its hash stands for it).
type Manifest = (Vec<u8>, Vec<u8>, Vec<u8>);

/// An `.rrd` file split into everything before its footer frame and the footer's manifests,
/// sorted. The file ends with a 32-byte stream footer whose first 16 bytes are the footer
/// payload's offset and length (little-endian); a 16-byte frame header precedes the payload.
fn rrd_parts(file: &[u8]) -> (&[u8], Vec<Manifest>) {
    let word = |at: usize| u64::from_le_bytes(file[at..at + 8].try_into().unwrap()) as usize;
    let tail = file.len() - 32;
    assert_eq!(&file[tail + 20..tail + 28], b"RRF2FOOT", "a stream footer");
    let (start, len) = (word(tail), word(tail + 8));
    let mut manifests: Vec<Manifest> = protobuf_fields(&file[start..start + len])
        .into_iter()
        .filter(|(field, _)| *field == 1)
        .map(|(_, manifest)| {
            let parts = protobuf_fields(manifest);
            let get = |f: u64| parts.iter().find(|p| p.0 == f).unwrap().1.to_vec();
            (get(1), get(3), get(4))
        })
        .collect();
    manifests.sort();
    (&file[..start - 16], manifests)
}

/// The length-delimited fields of a protobuf message as (field number, bytes); varint fields
/// are skipped (the footer has none at these levels).
fn protobuf_fields(mut b: &[u8]) -> Vec<(u64, &[u8])> {
    let varint = |b: &mut &[u8]| {
        let (mut value, mut shift) = (0u64, 0);
        loop {
            let byte = b[0];
            *b = &b[1..];
            value |= u64::from(byte & 0x7f) << shift;
            shift += 7;
            if byte < 0x80 {
                return value;
            }
        }
    };
    let mut out = Vec::new();
    while !b.is_empty() {
        let key = varint(&mut b);
        match key & 7 {
            2 => {
                let n = varint(&mut b) as usize;
                out.push((key >> 3, &b[..n]));
                b = &b[n..];
            }
            0 => {
                varint(&mut b);
            }
            wire => panic!("protobuf wire type {wire} in an rrd footer"),
        }
    }
    out
}

#[test]
fn csv_history_has_a_row_per_step_and_columns_per_finger() {
    let dir = out_dir("csv");
    let records = run_plate(&dir);
    let text = std::fs::read_to_string(dir.join("plate.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "time_s");
    assert!(header.contains(&"f3_normal_force_n") && header.contains(&"f1_slip_fraction"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), records.len());
    let col = header
        .iter()
        .position(|h| *h == "f3_normal_force_n")
        .unwrap();
    let last: Vec<&str> = rows.last().unwrap().split(',').collect();
    assert_eq!(
        last[col].parse::<f64>().unwrap(),
        records.last().unwrap().normal_force_n("f3")
    );
}

#[test]
fn rerun_cli_accepts_the_mcap_and_the_rrd() {
    let Some(cli) = support::rerun_cli() else {
        return;
    };
    let dir = out_dir("rerun");
    run_plate(&dir);
    check_rrd_chunks(&cli, &dir);
    for args in [vec!["mcap", "check"], vec!["rrd", "verify"]] {
        let file = if args[0] == "mcap" {
            "plate.mcap"
        } else {
            "plate.rrd"
        };
        let out = Process::new(&cli)
            .args(&args)
            .arg(dir.join(file))
            .env("CI", "1")
            .output()
            .expect("run rerun CLI");
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.status.success(),
            "rerun {} {file} failed:\n{text}",
            args.join(" ")
        );
        if args[0] == "mcap" {
            assert!(
                text.contains(FINGERS_TOPIC) && text.contains(PATCHES_TOPIC),
                "{text}"
            );
            assert!(!text.to_lowercase().contains("error"), "{text}");
        }
    }
}

/// The recording's rows are sent in chunks of at most `FLUSH_EVERY_STEPS` steps (memory does
/// not grow with the run), with the same chunk and row ids on every run.
fn check_rrd_chunks(cli: &Path, dir: &Path) {
    let print = |file: &Path, verbose: &str| {
        let out = Process::new(cli)
            .args(["rrd", "print", verbose])
            .arg(file)
            .env("CI", "1")
            .output()
            .expect("run rerun CLI");
        assert!(out.status.success(), "{out:?}");
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let text = print(&dir.join("plate.rrd"), "-v");
    let rows: Vec<usize> = text
        .lines()
        .filter(|l| l.contains("/plots/normal_force/f1 -") && l.contains("Scalars"))
        .map(|l| {
            l.split(" with ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap()
        })
        .collect();
    let every = grasp_transfer::FLUSH_EVERY_STEPS;
    assert!(rows.len() >= 2, "one chunk for 200 steps: {rows:?}");
    assert!(rows.iter().all(|&n| n <= every), "{rows:?}");
    assert_eq!(rows.iter().sum::<usize>(), 200, "{rows:?}");
    let again = out_dir("rerun-again");
    run_plate(&again);
    assert_eq!(
        print(&dir.join("plate.rrd"), "-vvv"),
        print(&again.join("plate.rrd"), "-vvv"),
        "chunk and row ids differ between two runs"
    );
}

/// The summary as it was computed from every record before it was folded step by step (the
/// reference the streamed summary must equal).
fn reference_summary(records: &[StepRecord], names: &[String]) -> TransferSummary {
    let ok: Vec<&StepRecord> = records
        .iter()
        .filter(|r| r.solution.status.has_forces())
        .collect();
    let loaded =
        |r: &StepRecord, n: &str| r.normal_force_n(n) > LOADED_FRACTION * r.solution.load_scale_n;
    let (mut releasing, mut receiving) = (Vec::new(), Vec::new());
    if let (Some(first), Some(last)) = (ok.first(), ok.last()) {
        for n in names {
            match (loaded(first, n), loaded(last, n)) {
                (true, false) => releasing.push(n.clone()),
                (false, true) => receiving.push(n.clone()),
                _ => {}
            }
        }
    }
    let sum = |r: &StepRecord, set: &[String]| set.iter().map(|n| r.normal_force_n(n)).sum::<f64>();
    let half = ok
        .iter()
        .find(|r| {
            !receiving.is_empty()
                && !releasing.is_empty()
                && sum(r, &receiving) > 0.0
                && sum(r, &receiving) >= sum(r, &releasing)
        })
        .map(|r| r.time_s);
    let full = ok
        .iter()
        .find(|r| !releasing.is_empty() && releasing.iter().all(|n| !loaded(r, n)))
        .map(|r| r.time_s);
    let (mut peak, mut peak_t) = (0.0_f64, 0.0);
    let mut margin: Option<SlipMargin> = None;
    let mut not_counted: Option<SlipMargin> = None;
    let mut worst = 0.0_f64;
    for r in &ok {
        let total: f64 = r.solution.fingers.iter().map(|f| f.normal_force_n).sum();
        if total > peak {
            (peak, peak_t) = (total, r.time_s);
        }
        // The slip-margin rule: a frictional finger counts while its contact force (normal and
        // friction together) is at least 5 % of the load scale; a lighter loaded one is
        // reported apart.
        let scale = r.solution.load_scale_n;
        for f in &r.solution.fingers {
            let q = f.tangential_force_n;
            let force = (f.normal_force_n.powi(2) + q.iter().map(|c| c * c).sum::<f64>()).sqrt();
            let frictional = f.friction_coefficient > 0.0;
            let slot = if frictional && f.normal_force_n > 0.0 && force >= 0.05 * scale {
                &mut margin
            } else if frictional && f.normal_force_n > LOADED_FRACTION * scale {
                &mut not_counted
            } else {
                continue;
            };
            let m = 1.0 - f.friction_utilization;
            if slot.as_ref().is_none_or(|x| m < x.margin) {
                *slot = Some(SlipMargin {
                    margin: m,
                    time_s: r.time_s,
                    finger: f.name.clone(),
                });
            }
        }
        if let Some(res) = &r.solution.residuals {
            worst = worst.max(res.equilibrium_relative);
        }
    }
    let failed: Vec<_> = records
        .iter()
        .filter(|r| !r.solution.status.has_forces())
        .map(|r| FailedStep {
            step: r.index,
            time_s: r.time_s,
            reason: r.solution.reason.clone().unwrap_or_default(),
        })
        .collect();
    let seq: Vec<_> = records
        .iter()
        .filter_map(|r| r.solution.sequential)
        .collect();
    TransferSummary {
        steps: records.len(),
        failed_step_count: failed.len(),
        failed_steps: failed,
        releasing,
        receiving,
        half_transfer_time_s: half,
        full_transfer_time_s: full,
        peak_squeeze_n: peak,
        peak_squeeze_time_s: peak_t,
        smallest_slip_margin: margin,
        smallest_slip_margin_not_counted: not_counted,
        slip_margin_rule: grasp_transfer::SLIP_MARGIN_RULE,
        worst_equilibrium_residual: worst,
        total_wall_time_s: records.iter().map(|r| r.wall_time_s).sum(),
        total_iterations: records
            .iter()
            .map(|r| r.solution.solver.iterations as u64)
            .sum(),
        total_factorizations: records
            .iter()
            .map(|r| r.solution.solver.factorizations as u64)
            .sum(),
        total_inner_iterations: records
            .iter()
            .map(|r| r.solution.solver.inner_iterations as u64)
            .sum(),
        compliance: {
            let mut paths = records.iter().map(|r| r.solution.solver.compliance);
            let first = paths.next().unwrap_or_default();
            match paths.all(|p| p == first) {
                true => first,
                false => grasp_model::CompliancePath::Mixed,
            }
        },
        answered_by_native: records
            .iter()
            .filter(|r| r.solution.solver.solver == grasp_model::SolverKind::Native)
            .count(),
        answered_by_clarabel: records
            .iter()
            .filter(|r| r.solution.solver.solver == grasp_model::SolverKind::Clarabel)
            .count(),
        fallbacks: Fallbacks {
            steps: records
                .iter()
                .filter(|r| r.solution.solver.fallback.is_some())
                .count(),
            first_reason: records
                .iter()
                .find_map(|r| r.solution.solver.fallback.clone()),
        },
        warm_steps: records.iter().filter(|r| r.reused_program).count(),
        sequential: (!seq.is_empty()).then(|| grasp_transfer::SequentialTotals {
            convex_solves: seq.iter().map(|s| s.iterations as u64).sum(),
            most_in_a_step: seq.iter().map(|s| s.iterations).max().unwrap_or(0),
            warm_started_steps: seq.iter().filter(|s| s.warm_started).count(),
            cold_restarts: seq.iter().map(|s| s.cold_restarts).sum(),
        }),
        // The first step of the smallest margin (an unbounded one above every number, an
        // undetermined one at the lower bound it held to).
        least_safe_step: records
            .iter()
            .filter_map(|r| r.margin.as_ref().map(|m| (r, m)))
            .fold(
                None,
                |best: Option<(&_, &grasp_transfer::StepMargin)>, (r, m)| match best {
                    Some((_, b)) if ordering_n(b) <= ordering_n(m) => best,
                    _ => Some((r, m)),
                },
            )
            .map(|(r, m)| grasp_transfer::LeastSafeStep {
                step: r.index,
                time_s: r.time_s,
                margin_n: m.smallest_n,
                held_to_n: m.held_to_n,
                undetermined: m.undetermined.clone(),
                direction: m.direction,
                failing_finger: m.failing_finger.clone(),
                bounded: m.bounded,
            }),
        margin_cost: records.iter().filter_map(|r| r.margin.as_ref()).fold(
            MarginCost::default(),
            |c, m| MarginCost {
                solves: c.solves + m.solves as u64,
                wall_time_s: c.wall_time_s + m.time_s,
            },
        ),
        other_equilibria: {
            let found: Vec<_> = records
                .iter()
                .filter_map(|r| {
                    let o = r.margin.as_ref()?.other_equilibrium.clone()?;
                    Some((r.index, r.time_s, o))
                })
                .collect();
            grasp_transfer::OtherEquilibria {
                // The runs compared ask for no margins.
                probed: None,
                steps: found.len(),
                first: found.into_iter().next(),
            }
        },
        held_relaxation: held_relaxation(records, names),
        margin_below_threshold: None,
        // The warnings' tally reads one step at a time by its nature: fed every record.
        warnings: {
            let mut tally = grasp_model::WarningTally::new();
            for r in records {
                let at = grasp_model::SolveAt {
                    index: r.index,
                    time_s: Some(r.time_s),
                };
                tally.add(at, &r.solution.warnings);
            }
            tally.warnings()
        },
        warnings_not_listed: 0,
    }
}

/// Per finger, the largest fall of its normal force over a run of solved steps with one
/// unchanged held (or approach) command, from the largest force since that run began.
fn held_relaxation(
    records: &[grasp_transfer::StepRecord],
    names: &[String],
) -> Vec<grasp_transfer::HeldRelaxation> {
    use grasp_transfer::Command;
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let solved: Vec<_> = records
            .iter()
            .filter(|r| r.solution.status.has_forces())
            .collect();
        let mut best: Option<grasp_transfer::HeldRelaxation> = None;
        for (j, r) in solved.iter().enumerate() {
            let c = r.commands[i].command;
            if !matches!(c, Command::Held | Command::Approach(_)) {
                continue;
            }
            // The run of the same command ending at step j, and its largest force (the latest
            // one of equal forces wins: a fall is measured from where it starts).
            let run_start = (0..=j)
                .rev()
                .take_while(|&m| solved[m].commands[i].command == c)
                .last()
                .unwrap();
            let (peak_n, peak_t) = solved[run_start..=j]
                .iter()
                .map(|s| (s.normal_force_n(name), s.time_s))
                .fold(
                    (f64::NEG_INFINITY, 0.0),
                    |a, b| if b.0 >= a.0 { b } else { a },
                );
            let p = r.normal_force_n(name);
            let fraction = if peak_n > 0.0 { 1.0 - p / peak_n } else { 0.0 };
            if fraction > 1e-9 && best.as_ref().is_none_or(|b| fraction > b.fraction) {
                best = Some(grasp_transfer::HeldRelaxation {
                    finger: name.clone(),
                    from_n: peak_n,
                    from_time_s: peak_t,
                    to_n: p,
                    to_time_s: r.time_s,
                    fraction,
                    position_controlled: matches!(c, Command::Approach(_)),
                });
            }
        }
        out.extend(best);
    }
    out
}

#[test]
fn streamed_summary_equals_the_summary_of_all_records() {
    for name in ["plate_transfer", "disc_transfer", "plate_handoff_coulomb"] {
        let (scene, schedule) = support::transfer_example(name);
        let names = scene.finger_names();
        let mut records = Vec::new();
        let (summary, last) = grasp_transfer::run(
            &scene,
            &schedule,
            TransferOptions::default(),
            &mut [],
            |r| records.push(r.clone()),
        )
        .unwrap();
        assert_eq!(last.as_ref(), records.last(), "{name}");
        let reference = reference_summary(&records, &names);
        assert_eq!(summary, reference, "{name}");
        // Beyond MAX_FOLDED_FINGERS the accumulator keeps the forces instead: same summary.
        let mut kept = grasp_transfer::SummaryAccumulator::with_folded_fingers(&names, 0);
        records.iter().for_each(|r| kept.add(r));
        assert_eq!(kept.finish(), reference, "{name}");
        assert!(
            summary.half_transfer_time_s.is_some(),
            "{name}: {summary:?}"
        );
    }
}

/// Reads RFC 4180 CSV: quoted fields may hold commas, doubled quotes and line breaks.
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let (mut rows, mut row, mut field) = (Vec::new(), Vec::new(), String::new());
    let mut chars = text.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => field.push(c),
        }
    }
    rows
}

#[test]
fn csv_quotes_finger_names_by_rfc_4180() {
    let (mut scene, _) = support::transfer_example("plate_transfer");
    let odd = "f,\"1\"\nx";
    scene.fingers[0].name = odd.to_string();
    let names = scene.finger_names();
    let text = r#"{"time": {"times": [0, 1, 2]}, "fingers": {"f3": [{"held": {}}]}}"#;
    let schedule = grasp_transfer::Schedule::from_json_str(text, &names, Path::new(".")).unwrap();
    let dir = out_dir("quote");
    let mut c = CsvSink::create(&dir.join("q.csv")).unwrap();
    let (records, _) =
        grasp_transfer::run_collect(&scene, &schedule, TransferOptions::default(), &mut [&mut c])
            .unwrap();
    let rows = parse_csv(&std::fs::read_to_string(dir.join("q.csv")).unwrap());
    assert_eq!(rows.len(), records.len() + 1);
    assert!(rows.iter().all(|r| r.len() == rows[0].len()), "{rows:?}");
    assert_eq!(rows[0][3], format!("{odd}_normal_force_n"));
    let p: f64 = rows[1][3].parse().unwrap();
    assert_eq!(p, records[0].normal_force_n(odd));
}

/// A step margin for ordering steps, N: unbounded above every number, undetermined at the
/// lower bound it held to.
fn ordering_n(m: &grasp_transfer::StepMargin) -> f64 {
    match (m.smallest_n, &m.undetermined) {
        (Some(v), _) => v,
        (None, None) => f64::INFINITY,
        (None, Some(_)) => m.held_to_n,
    }
}
