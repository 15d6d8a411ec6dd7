//! Tactile readings at every step of a hand-off (`examples/plate_transfer_taxels.json`: the
//! thesis's plate hand-off with 4 x 2 taxels of 2.5 mm in every pad): each step's record has
//! the readings of its active sensor fingers, taxels at the surface carry each finger's
//! resultant at every step, and the MCAP's `/grasp/tactile` topic and the Rerun recording carry
//! them, accepted by the `rerun` CLI.

mod support;

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
    let checked = support::rerun_on(&cli, &["mcap", "check"], &mcap);
    assert!(checked.contains(TACTILE_TOPIC), "{checked}");
    support::rerun_on(&cli, &["rrd", "verify"], &rrd);
    let text = support::rerun_on(&cli, &["rrd", "print"], &rrd);
    assert!(text.contains("world/tactile/f1/taxels"), "{text}");
}

/// `examples/cattaneo_markers.json` along its schedule (Q ramped to 0.9 mu P in eight steps,
/// the coulomb law carrying the slip history from step to step): at every step the markers
/// (on element centres, where the read-out is exact for the element forces) that move with
/// the central one (to 1e-6 of its shift) fill a circle whose area-equivalent
/// radius is Cattaneo's `c = a (1 - Q/(mu P))^(1/3)` within one marker pitch (the markers'
/// resolution), the central shift is Mindlin's per body (Johnson eq. 7.42, half of it between
/// equal steels) within 1 % (the tolerance; `tests/marker_readings.rs` measures 0.1 to
/// 0.2 % at single loads), and the circle never grows as Q does.
#[test]
fn markers_follow_incipient_slip_step_by_step() {
    use grasp_model::closed_form::{cattaneo_stick_radius_m, mindlin_displacement_m, HertzSphere};
    let (scene, schedule) = support::transfer_example("cattaneo_markers");
    let records = steps(&scene, &schedule, &mut []);
    // The markers sit on element centres, seven elements apart (the example's 64 x 64 over 2.4 a).
    let (mu, p, e, nu) = (0.3, 10.0, 210e9, 0.3);
    let pitch = 7.0 * 2.078e-4 / 64.0;
    // Two equal steels: E* = E / (2 (1 - nu^2)).
    let a = HertzSphere::new(p, 0.01, e / (2.0 * (1.0 - nu * nu))).contact_radius_m;
    let g = e / (2.0 * (1.0 + nu));
    let markers = |r: &StepRecord| r.sensors[0].markers.clone().unwrap();
    let start = markers(&records[0]);
    let mut last_stuck = usize::MAX;
    for r in &records[1..] {
        let q = r.external_force_n[0];
        let m = markers(r);
        let u: Vec<[f64; 2]> = m
            .displacement_m
            .iter()
            .zip(&start.displacement_m)
            .map(|(a, b)| [a[1] - b[1], a[2] - b[2]])
            .collect();
        let centre = u[u.len() / 2];
        let stuck = u
            .iter()
            .filter(|v| (v[0] - centre[0]).hypot(v[1] - centre[1]) <= 1e-6 * centre[0])
            .count();
        let c_markers = (stuck as f64 * pitch * pitch / std::f64::consts::PI).sqrt();
        let c = cattaneo_stick_radius_m(a, q, mu, p);
        let shift = mindlin_displacement_m(a, 2.0 * (2.0 - nu) / g, q, mu, p) / 2.0;
        let at = format!("t = {} s, Q = {q} N", r.time_s);
        println!(
            "{at}: {stuck} markers stick, radius {:.3} a (c = {:.3} a), shift {:.2} % off",
            c_markers / a,
            c / a,
            100.0 * (centre[0] - shift).abs() / shift
        );
        assert!(
            (c_markers - c).abs() <= pitch,
            "{at}: stick radius {c_markers} vs {c}"
        );
        assert!(
            (centre[0] - shift).abs() <= 0.01 * shift,
            "{at}: {} vs {shift}",
            centre[0]
        );
        assert!(stuck <= last_stuck, "{at}: the stick circle grew");
        last_stuck = stuck;
    }
    assert!(
        last_stuck < 81,
        "the slip annulus reaches the markers at 0.9 mu P"
    );
}

/// The CSV has each sensor finger's columns (`sinks/sensor_columns.rs`): at every step the
/// taxels' normal sum, shear and largest force equal the record's readings' (the cells are the
/// shortest round-trip text of the same float64), empty where the finger is released.
#[test]
fn the_csv_carries_each_steps_sensor_summary() {
    let (scene, schedule) = plate_with_taxels_at(5e-4);
    let dir = std::env::temp_dir().join(format!("grasp-tactile-csv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("t.csv");
    let mut c = grasp_transfer::CsvSink::create(&csv).unwrap();
    let records = steps(&scene, &schedule, &mut [&mut c]);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let mut empty = 0;
    for (line, rec) in lines.zip(&records) {
        let cells: Vec<&str> = line.split(',').collect();
        for finger in ["f1", "f3"] {
            let cell = |col: &str| cells[column(&format!("{finger}_taxels_{col}"))];
            match rec.sensors.iter().find(|s| s.finger == finger) {
                Some(s) => {
                    let t = s.taxels.as_ref().unwrap();
                    let [s1, s2] = t.total_shear_n();
                    assert_eq!(cell("normal_n").parse::<f64>().unwrap(), t.total_normal_n());
                    assert_eq!(cell("shear_n").parse::<f64>().unwrap(), s1.hypot(s2));
                    assert_eq!(cell("largest_n").parse::<f64>().unwrap(), t.largest().1);
                }
                None => {
                    assert!(cell("normal_n").is_empty() && cell("largest_n").is_empty());
                    empty += 1;
                }
            }
        }
    }
    assert!(empty > 0, "a released finger's cells are empty");
    std::fs::remove_dir_all(&dir).ok();
}
