//! Sensor non-idealities (`fingers[i].sensor.<kind>.response`): off, the readings are the
//! ideal ones bit for bit; the noise and the gains have the statistics asked for, on a real
//! read-out; saturation and quantisation bound and round every reading; a hand-off draws new
//! noise at every step and the same noise on every run; and bad numbers are refused by name.

mod support;
use support::*;

use grasp_model::{sensor_readings, sensor_readings_drawn, GraspModel, SensorReadings};
use serde_json::{json, Value};

/// examples/hertz_markers.json (a rigid sphere on a gel, 0.1 N) with 64 x 64 markers over
/// 2.4 mm, their response `response`.
fn markers_with(response: Option<Value>) -> Value {
    let mut v = example_json("hertz_markers.json");
    let mut m = json!({"count": [64, 64], "pitch_m": 2.4e-3 / 64.0});
    if let Some(r) = response {
        m["response"] = r;
    }
    v["fingers"][0]["sensor"] = json!({ "markers": m });
    v
}

/// The readings of `v`, read-out `draw`.
fn read(v: &Value, draw: u64) -> Vec<SensorReadings> {
    let loaded = scene(v);
    let model = GraspModel::from_loaded(&loaded).expect("model");
    let solution = grasp_model::solve(&model).expect("solve");
    sensor_readings_drawn(&loaded.scene, &model, &solution, draw).expect("readings")
}

/// Every marker component, flat.
fn components(r: &[SensorReadings]) -> Vec<f64> {
    let m = r[0].markers.as_ref().unwrap();
    m.displacement_m.iter().flatten().copied().collect()
}

/// Mean and standard deviation.
fn moments(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

#[test]
fn a_response_of_no_departure_is_the_ideal_reading() {
    let ideal = read(&markers_with(None), 0);
    let none = read(&markers_with(Some(json!({"seed": 5}))), 3);
    assert_eq!(components(&ideal), components(&none));
    // One solve is read-out 0.
    let v = markers_with(None);
    let loaded = scene(&v);
    let model = GraspModel::from_loaded(&loaded).unwrap();
    let solution = grasp_model::solve(&model).unwrap();
    assert_eq!(
        sensor_readings(&loaded.scene, &model, &solution).unwrap(),
        ideal
    );
}

#[test]
fn the_noise_has_the_spread_asked_for() {
    // 12,288 components of noise sigma = 1 um: the mean of (noisy - ideal) within 4 standard
    // errors (4 sigma / sqrt(n) = 0.036 um) of 0 and its standard deviation within 4 of its
    // standard errors (4 sigma sqrt(1 / (2 n)) = 0.026 um) of sigma.
    let sigma = 1e-6;
    let ideal = components(&read(&markers_with(None), 0));
    let noisy = components(&read(&markers_with(Some(json!({"noise_std": sigma}))), 0));
    let d: Vec<f64> = noisy.iter().zip(&ideal).map(|(a, b)| a - b).collect();
    let (mean, std) = moments(&d);
    let n = d.len() as f64;
    println!("noise: mean {mean:.3e} m, std {std:.4e} m over {n} components");
    assert!(mean.abs() < 4.0 * sigma / n.sqrt(), "{mean:e}");
    assert!(
        (std - sigma).abs() < 4.0 * sigma / (2.0 * n).sqrt(),
        "{std:e}"
    );
}

#[test]
fn each_point_has_one_gain_of_the_spread_asked_for() {
    // Without noise each marker's three components are scaled by its own gain: their ratios
    // to the ideal agree at a point (to round-off), and over the 4,096 markers the gains have
    // mean 1 and standard deviation 0.05 within 4 standard errors (0.0031 and 0.0022).
    let g = 0.05;
    let ideal = read(&markers_with(None), 0);
    let scaled = read(&markers_with(Some(json!({"gain_std": g, "seed": 9}))), 0);
    let (a, b) = (
        &ideal[0].markers.as_ref().unwrap(),
        &scaled[0].markers.as_ref().unwrap(),
    );
    let mut gains = Vec::new();
    for (u, v) in a.displacement_m.iter().zip(&b.displacement_m) {
        let gain = v[0] / u[0];
        for c in 1..3 {
            if u[c].abs() > 1e-3 * u[0].abs() {
                assert!((v[c] / u[c] - gain).abs() < 1e-12, "{u:?} {v:?}");
            }
        }
        gains.push(gain);
    }
    let (mean, std) = moments(&gains);
    let n = gains.len() as f64;
    println!("gains: mean {mean:.5}, std {std:.5}");
    assert!((mean - 1.0).abs() < 4.0 * g / n.sqrt(), "{mean}");
    assert!((std - g).abs() < 4.0 * g / (2.0 * n).sqrt(), "{std}");
}

#[test]
fn saturation_and_quantisation_bound_and_round_every_reading() {
    // examples/hertz_taxels.json: 5 x 5 taxels at a/2 under 10 N; the central one reads
    // 0.79 N. Saturated at 0.5 N and read in steps of 0.05 N: every reading a multiple of
    // the step (to round-off), none above 0.5 N, and the ideal readings within half a step
    // where they do not saturate.
    let mut v = example_json("hertz_taxels.json");
    let ideal = read(&v, 0);
    v["fingers"][0]["sensor"]["taxels"]["response"] =
        json!({"saturation": [-0.5, 0.5], "quantum": 0.05});
    let read_out = read(&v, 0);
    let (t, r) = (
        ideal[0].taxels.as_ref().unwrap(),
        read_out[0].taxels.as_ref().unwrap(),
    );
    let mut saturated = 0;
    for (x, y) in t.force_n.iter().flatten().zip(r.force_n.iter().flatten()) {
        let steps = y / 0.05;
        assert!((steps - steps.round()).abs() < 1e-9, "{y}");
        assert!(y.abs() <= 0.5 + 1e-12, "{y}");
        match x.abs() > 0.5 {
            true => saturated += 1,
            false => assert!((x - y).abs() <= 0.025 + 1e-12, "{x} {y}"),
        }
    }
    assert!(saturated > 0, "the central taxels saturate");
}

#[test]
fn a_hand_off_draws_new_noise_at_every_step_and_the_same_on_every_run() {
    // examples/ridged_gel.json along its schedule with camera noise on the gel image: each
    // step's image departs from the ideal one by a different draw; a second run reads the
    // same bits.
    let run = |noise: bool| {
        let mut v = example_json("ridged_gel.json");
        if noise {
            v["fingers"][0]["sensor"]["gel"]["response"] =
                json!({"noise_std": 0.02, "quantum": 1.0 / 255.0, "seed": 3});
        }
        let scene = grasp_model::LoadedScene::from_json_str(&v.to_string()).unwrap();
        let dir = std::path::PathBuf::from(example_path(""));
        let text = std::fs::read_to_string(dir.join("ridged_gel.schedule.json")).unwrap();
        let schedule =
            grasp_transfer::Schedule::from_json_str(&text, &scene.finger_names(), &dir).unwrap();
        let options = grasp_transfer::TransferOptions::default();
        let records = grasp_transfer::run_collect(&scene, &schedule, options, &mut [])
            .unwrap()
            .0;
        records
            .into_iter()
            .map(|r| r.sensors[0].gel.clone().unwrap())
            .collect::<Vec<_>>()
    };
    let (ideal, a, b) = (run(false), run(true), run(true));
    assert_eq!(a, b, "the same seed reads the same images");
    let noise = |k: usize| -> Vec<f64> {
        let (x, y) = (&ideal[k].rgb, &a[k].rgb);
        x.iter()
            .flatten()
            .zip(y.iter().flatten())
            .map(|(p, q)| q - p)
            .collect()
    };
    let (first, second) = (noise(0), noise(1));
    assert_ne!(first, second, "each step draws its own noise");
    let (_, std) = moments(&first);
    // 24,300 channels of sigma 0.02, quantised to 1/255 (adds 1/255^2/12 of variance) and
    // clipped to [0, 1] nowhere here (the image's channels lie in 0.3-0.7): within 5 %.
    let expected = (0.02f64.powi(2) + (1.0f64 / 255.0).powi(2) / 12.0).sqrt();
    println!("gel camera noise: std {std:.5} (expected {expected:.5})");
    assert!((std - expected).abs() < 0.05 * expected, "{std}");
}

#[test]
fn bad_response_numbers_are_named_with_their_path() {
    let p = "fingers[0].sensor.markers.response";
    let with = |r: Value| markers_with(Some(r));
    assert_refused(
        &with(json!({"gain_std": 2.0})),
        &format!("{p}.gain_std"),
        "outside",
    );
    assert_refused(
        &with(json!({"noise_std": -1.0})),
        &format!("{p}.noise_std"),
        "outside",
    );
    assert_refused(
        &with(json!({"saturation": [1.0, 1.0]})),
        &format!("{p}.saturation"),
        "low below high",
    );
    assert_refused(
        &with(json!({"quantum": 0.0})),
        &format!("{p}.quantum"),
        "outside",
    );
    assert_refused(
        &with(json!({"seed": 9007199254740993u64})),
        &format!("{p}.seed"),
        "above 2^53",
    );
    let problems = problems(&with(json!({"noise": 1.0})));
    assert!(
        problems.iter().any(|m| m.contains("noise")),
        "{problems:#?}"
    );
}
