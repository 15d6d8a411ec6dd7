//! Recordings of a hand-off with fine patches: `examples/plate_transfer_fine.json` (the
//! receivers on 128 x 128 elements) on its schedule with 1.99 s steps instead of 0.1 s (11
//! steps over the whole hand-off instead of 200, for CI time), written to MCAP and Rerun.
//!
//! - the MCAP's compact maps (`/grasp/patch_maps`), decoded here with a base64 decoder of the
//!   test's own, equal the solver's element values (f32 rounding: within `2^-24 |v|`, or
//!   `2^-149` below f32's normal range) and give the element positions (within 1e-15 m);
//! - the files grow by at most the bytes a 200-step run of two 128 x 128 patches may spend per
//!   element and step to stay within 100 MB;
//! - the same inputs give the same MCAP, and the same `.rrd` up to Rerun's footer;
//! - `rerun mcap check` and `rerun rrd verify` accept both, and `rerun rrd print` finds the
//!   large patches as `GridMap` images and the small ones as points.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command as Process;
use std::sync::OnceLock;

use grasp_transfer::{
    state_code, McapSink, RerunSink, Sink, StepRecord, TransferOptions, PATCHES_TOPIC,
    PATCH_MAPS_SCHEMA, PATCH_MAPS_TOPIC,
};

/// The size bound of fine-patch recordings: each file of a 200-step hand-off with two
/// 128 x 128 patches at most 100 MB.
const FILE_LIMIT_BYTES: f64 = 100e6;
const FULL_RUN_ELEMENT_STEPS: f64 = 200.0 * 2.0 * 128.0 * 128.0;

fn out_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-fine-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the fine hand-off into `dir` (fine.mcap, fine.rrd).
fn run_fine(dir: &Path) -> Vec<StepRecord> {
    let path = PathBuf::from(support::example_path(""));
    let text = std::fs::read_to_string(path.join("plate_transfer_fine.json")).unwrap();
    let scene = grasp_model::LoadedScene::from_json_str(&text).unwrap();
    let names = scene.finger_names();
    let text = std::fs::read_to_string(path.join("plate_transfer.schedule.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["time"]["step"] = 1.99.into();
    let schedule = grasp_transfer::Schedule::from_json_str(&v.to_string(), &names, &path).unwrap();
    let mut m = McapSink::create(&dir.join("fine.mcap")).unwrap();
    let mut r = RerunSink::create(&dir.join("fine.rrd")).unwrap();
    let mut sinks: Vec<&mut dyn Sink> = vec![&mut m, &mut r];
    let (records, _) =
        grasp_transfer::run_collect(&scene, &schedule, TransferOptions::default(), &mut sinks)
            .unwrap();
    records
}

/// One run shared by the tests of this file.
fn fine() -> &'static (PathBuf, Vec<StepRecord>) {
    static RUN: OnceLock<(PathBuf, Vec<StepRecord>)> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = out_dir("shared");
        let records = run_fine(&dir);
        (dir, records)
    })
}

/// Standard base64 (RFC 4648, with padding), written here independently of the encoder.
fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    assert_eq!(text.len() % 4, 0, "padded to whole quads");
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    for quad in text.as_bytes().chunks(4) {
        let pad = quad.iter().filter(|&&c| c == b'=').count();
        let mut n = 0u32;
        for &c in quad {
            n = (n << 6) | u32::from(if c == b'=' { 0 } else { value(c) });
        }
        out.extend_from_slice(&n.to_be_bytes()[1..4 - pad]);
    }
    out
}

fn f32s(v: &serde_json::Value) -> Vec<f32> {
    let bytes = base64_decode(v.as_str().unwrap());
    assert_eq!(bytes.len() % 4, 0);
    bytes
        .chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// `decoded` is `exact` rounded to the nearest f32.
fn rounded(decoded: f32, exact: f64) -> bool {
    let bound = (exact.abs() * 2f64.powi(-24)).max(2f64.powi(-149));
    (f64::from(decoded) - exact).abs() <= bound
}

fn patch_maps(file: &Path) -> Vec<serde_json::Value> {
    let bytes = std::fs::read(file).unwrap();
    let mut out = Vec::new();
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        match msg.channel.topic.as_str() {
            PATCH_MAPS_TOPIC => {
                assert_eq!(msg.channel.schema.as_ref().unwrap().name, PATCH_MAPS_SCHEMA);
                out.push(serde_json::from_slice(&msg.data).unwrap());
            }
            PATCHES_TOPIC => {
                // The element records hold the small patches only.
                let v: serde_json::Value = serde_json::from_slice(&msg.data).unwrap();
                for p in v["patches"].as_array().unwrap() {
                    assert!(["f1", "f2"].contains(&p["name"].as_str().unwrap()), "{p}");
                }
            }
            _ => {}
        }
    }
    out
}

/// Every map of one patch against the solver's elements.
fn check_patch(p: &serde_json::Value, f: &grasp_model::FingerSolution) {
    let n = f.elements.len();
    let [nx, ny] = [0, 1].map(|i| p["grid"][i].as_u64().unwrap() as usize);
    assert_eq!((nx, ny, n), (128, 128, 128 * 128));
    let maps = [
        "normal_force_n",
        "pressure_pa",
        "tangential_force_n",
        "gap_m",
    ];
    let [fn_, pa, t, gap] = maps.map(|k| f32s(&p[k]));
    let [slip, step_slip] = ["slip_m", "step_slip_m"].map(|k| f32s(&p[k]));
    let state = base64_decode(p["state"].as_str().unwrap());
    assert_eq!([fn_.len(), pa.len(), gap.len(), state.len()], [n; 4]);
    assert_eq!([t.len(), slip.len(), step_slip.len()], [2 * n; 3]);
    let v3 = |key: &str| nalgebra::Vector3::from_fn(|i, _| p[key][i].as_f64().unwrap());
    let (origin, t1, t2) = (v3("origin_m"), v3("t1"), v3("t2"));
    let [hx, hy] = [0, 1].map(|i| p["element_size_m"][i].as_f64().unwrap());
    for (k, e) in f.elements.iter().enumerate() {
        let pairs = [
            (fn_[k], e.normal_force_n),
            (pa[k], e.pressure_pa),
            (gap[k], e.gap_m),
        ];
        let pairs2 = (0..2).flat_map(|c| {
            let at = 2 * k + c;
            [
                (t[at], e.tangential_force_n[c]),
                (slip[at], e.slip_m[c]),
                (step_slip[at], e.step_slip_m[c]),
            ]
        });
        for (d, x) in pairs.into_iter().chain(pairs2) {
            assert!(rounded(d, x), "{} element {k}: {d:e} for {x:e}", f.name);
        }
        assert_eq!(state[k], state_code(e.state), "{} element {k}", f.name);
        let (i, j) = (k / ny, k % ny);
        let x = (i as f64 + 0.5) * hx - 0.5 * nx as f64 * hx;
        let y = (j as f64 + 0.5) * hy - 0.5 * ny as f64 * hy;
        let at = origin + t1 * x + t2 * y;
        let d = (at - nalgebra::Vector3::from(e.position_m)).norm();
        assert!(
            d <= 1e-15,
            "{} element {k}: position off by {d:e} m",
            f.name
        );
    }
}

#[test]
fn compact_maps_decode_to_the_solver_s_element_values() {
    let (dir, records) = fine();
    let maps = patch_maps(&dir.join("fine.mcap"));
    assert_eq!(maps.len(), records.len());
    let mut checked = 0;
    for (m, r) in maps.iter().zip(records) {
        assert_eq!(m["step"].as_u64(), Some(r.index as u64));
        let fine: Vec<_> = ["f3", "f4"]
            .iter()
            .filter_map(|n| r.solution.finger(n))
            .collect();
        let patches = m["patches"].as_array().unwrap();
        assert_eq!(patches.len(), fine.len(), "step {}", r.index);
        for (p, f) in patches.iter().zip(fine) {
            assert_eq!(p["name"], f.name.as_str());
            check_patch(p, f);
            checked += 1;
        }
    }
    // f3 and f4 from the second step on (released in the first).
    assert_eq!(checked, 2 * (records.len() - 1));
}

/// The bytes of a file per active large-patch element and step, overheads included.
fn bytes_per_element_step(file: &Path, records: &[StepRecord]) -> f64 {
    let element_steps: usize = records
        .iter()
        .flat_map(|r| &r.solution.fingers)
        .filter(|f| f.elements.len() > grasp_transfer::COMPACT_ABOVE_ELEMENTS)
        .map(|f| f.elements.len())
        .sum();
    std::fs::metadata(file).unwrap().len() as f64 / element_steps as f64
}

#[test]
fn files_stay_within_100_mb_for_200_steps_of_two_128x128_patches() {
    let (dir, records) = fine();
    let limit = FILE_LIMIT_BYTES / FULL_RUN_ELEMENT_STEPS;
    for file in ["fine.mcap", "fine.rrd"] {
        let per = bytes_per_element_step(&dir.join(file), records);
        let projected_mb = per * FULL_RUN_ELEMENT_STEPS / 1e6;
        println!("fine-patch recording: {file} {per:.2} bytes an element and step (limit {limit:.2}), 200 steps x 2 x 128 x 128: {projected_mb:.1} MB");
        assert!(per <= limit, "{file}: {per:.2} bytes an element and step");
    }
}

#[test]
fn fine_recordings_are_deterministic() {
    let (dir, _) = fine();
    let again = out_dir("again");
    run_fine(&again);
    let read = |d: &Path, f: &str| std::fs::read(d.join(f)).unwrap();
    assert!(
        read(dir, "fine.mcap") == read(&again, "fine.mcap"),
        "MCAP bytes differ"
    );
    // The `.rrd` up to its footer (whose manifests Rerun lists in hash-map order): the footer
    // payload's offset is the first word of the file's last 32 bytes, after a 16-byte header.
    let before_footer = |b: Vec<u8>| {
        let at = b.len() - 32;
        assert_eq!(&b[at + 20..at + 28], b"RRF2FOOT");
        let start = u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize;
        b[..start - 16].to_vec()
    };
    let (a, b) = (read(dir, "fine.rrd"), read(&again, "fine.rrd"));
    assert!(before_footer(a) == before_footer(b), ".rrd bytes differ");
}

#[test]
fn rerun_cli_accepts_the_fine_patch_recordings() {
    let Some(cli) = support::rerun_cli() else {
        return;
    };
    let (dir, _) = fine();
    let run = |args: &[&str], file: &str| {
        let out = Process::new(&cli)
            .args(args)
            .arg(dir.join(file))
            .env("CI", "1")
            .output()
            .expect("run the rerun CLI");
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(out.status.success(), "rerun {args:?} {file}:\n{text}");
        text
    };
    let check = run(&["mcap", "check"], "fine.mcap");
    assert!(check.contains(PATCH_MAPS_TOPIC), "{check}");
    assert!(!check.to_lowercase().contains("error"), "{check}");
    run(&["rrd", "verify"], "fine.rrd");
    let print = run(&["rrd", "print", "-v"], "fine.rrd");
    let chunk_of = |entity: &str| {
        print
            .lines()
            .find(|l| l.contains(&format!(" - {entity} - ")))
            .unwrap_or_else(|| panic!("no chunk of {entity}:\n{print}"))
            .to_owned()
    };
    for name in ["f3", "f4"] {
        let line = chunk_of(&format!("/world/patches/{name}/pressure"));
        assert!(line.contains("GridMap:data"), "{line}");
        assert!(chunk_of(&format!("/world/patches/{name}")).contains("Transform3D:mat3x3"));
    }
    assert!(chunk_of("/world/patches/f1/state").contains("Points3D:positions"));
}
