//! Tactile readings at every step of a hand-off (`examples/plate_transfer_taxels.json`: the
//! thesis's plate hand-off with 4 x 2 taxels of 2.5 mm in every pad): each step's record has
//! the readings of its active sensor fingers, taxels at the surface carry each finger's
//! resultant at every step, and the MCAP's `/grasp/tactile` topic and the Rerun recording carry
//! them, accepted by the `rerun` CLI.

mod support;

use std::process::Command as Process;

use grasp_model::{GraspModel, LoadedScene};
use grasp_transfer::{
    McapSink, RerunSink, Schedule, Sink, StepRecord, TransferOptions, TACTILE_SCHEMA, TACTILE_TOPIC,
};
use serde_json::Value;
use support::{example_json, example_path};

/// The example scene with its taxels at `depth_m`, and its schedule.
fn plate_with_taxels_at(depth_m: f64) -> (LoadedScene, Schedule) {
    let mut v = example_json("plate_transfer_taxels.json");
    for f in v["fingers"].as_array_mut().unwrap() {
        f["sensor"]["taxels"]["depth_m"] = depth_m.into();
    }
    let scene = LoadedScene::from_json_str(&v.to_string()).unwrap();
    let dir = std::path::PathBuf::from(example_path(""));
    let text = std::fs::read_to_string(dir.join("plate_transfer_taxels.schedule.json")).unwrap();
    let schedule = Schedule::from_json_str(&text, &scene.finger_names(), &dir).unwrap();
    (scene, schedule)
}

fn steps(scene: &LoadedScene, schedule: &Schedule, sinks: &mut [&mut dyn Sink]) -> Vec<StepRecord> {
    grasp_transfer::run_collect(scene, schedule, TransferOptions::default(), sinks)
        .unwrap()
        .0
}

/// Taxels at `d = 0` bin the surface tractions, and the 4 x 2 taxels of 2.5 mm tile the
/// 10 mm x 5 mm patch exactly: at every step their normal forces sum to the finger's `P` and
/// their shear to its `|Q|`, to 1e-12 of the load scale (the sums' round-off). Every step that
/// found forces has readings for exactly its active fingers (all carry a sensor), in scene
/// order.
#[test]
fn surface_taxels_carry_each_fingers_forces_at_every_step() {
    let (scene, schedule) = plate_with_taxels_at(0.0);
    let load = GraspModel::from_loaded(&scene).unwrap().scales().load_n;
    let records = steps(&scene, &schedule, &mut []);
    assert_eq!(records.len(), 200);
    let mut released = 0;
    for r in &records {
        assert!(r.solution.status.has_forces(), "step {}", r.index);
        let active: Vec<&str> = r.solution.fingers.iter().map(|f| f.name.as_str()).collect();
        let read: Vec<&str> = r.sensors.iter().map(|s| s.finger.as_str()).collect();
        assert_eq!(read, active, "step {}", r.index);
        released += usize::from(active.len() < 4);
        for s in &r.sensors {
            let f = r.solution.finger(&s.finger).unwrap();
            let t = s.taxels.as_ref().unwrap();
            let [s1, s2] = t.total_shear_n();
            let at = format!("step {} {}", r.index, s.finger);
            assert!(
                (t.total_normal_n() - f.normal_force_n).abs() < 1e-12 * load,
                "{at}: {} N against P = {} N",
                t.total_normal_n(),
                f.normal_force_n
            );
            assert!(
                (s1.hypot(s2) - f.tangential_magnitude_n).abs() < 1e-12 * load,
                "{at}: {} N against |Q| = {} N",
                s1.hypot(s2),
                f.tangential_magnitude_n
            );
        }
    }
    assert!(released > 0, "the releasing pair is let go at the end");
}

/// `/grasp/tactile` has one message a step (schema `grasp.TactileReadings`), and each carries
/// the step's readings as the records hold them (at the example's depth, 0.5 mm); the
/// `rerun` CLI accepts the MCAP and the recording (with its `world/tactile` arrows).
#[test]
fn the_mcap_and_the_recording_carry_the_readings() {
    let (scene, schedule) = plate_with_taxels_at(5e-4);
    let dir = std::env::temp_dir().join(format!("grasp-tactile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (mcap, rrd) = (dir.join("t.mcap"), dir.join("t.rrd"));
    let mut m = McapSink::create(&mcap).unwrap();
    let mut r = RerunSink::create(&rrd).unwrap();
    let records = steps(&scene, &schedule, &mut [&mut m, &mut r]);
    let bytes = std::fs::read(&mcap).unwrap();
    let mut seen = 0;
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        if msg.channel.topic != TACTILE_TOPIC {
            continue;
        }
        let schema = msg.channel.schema.as_ref().unwrap();
        assert_eq!(schema.name, TACTILE_SCHEMA);
        let v: Value = serde_json::from_slice(&msg.data).unwrap();
        let rec = &records[seen];
        assert_eq!(v["step"], rec.index);
        let sensors = v["sensors"].as_array().unwrap();
        assert_eq!(sensors.len(), rec.sensors.len());
        for (got, want) in sensors.iter().zip(&rec.sensors) {
            assert_eq!(got["finger"], want.finger.as_str());
            assert!(got["markers"].is_null());
            let forces = &want.taxels.as_ref().unwrap().force_n;
            let written: Vec<[f64; 3]> =
                serde_json::from_value(got["taxels"]["force_n"].clone()).unwrap();
            assert_eq!(&written, forces, "step {}", rec.index);
        }
        seen += 1;
    }
    assert_eq!(seen, records.len());
    let Some(cli) = support::rerun_cli() else {
        return;
    };
    for (args, file) in [(["mcap", "check"], &mcap), (["rrd", "verify"], &rrd)] {
        let out = Process::new(&cli)
            .args(args)
            .arg(file)
            .env("CI", "1")
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "rerun {args:?}: {text}");
        if args[0] == "mcap" {
            assert!(text.contains(TACTILE_TOPIC), "{text}");
        }
    }
    let out = Process::new(&cli)
        .args(["rrd", "print"])
        .arg(&rrd)
        .env("CI", "1")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("world/tactile/f1/taxels"), "{text}");
}
