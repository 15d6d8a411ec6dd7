//! A gel image at every step of a hand-off (`examples/ridged_gel.json` along its schedule: a
//! ridged sphere pressed harder on a gel sensor): each step's image meets the sphere where
//! they touch (compatibility), the MCAP's `foxglove.RawImage` topics carry each step's image
//! and height map as the records hold them, and the Rerun recording has both images,
//! accepted by the `rerun` CLI.

mod support;

use grasp_model::{GraspModel, HeightPath, LoadedScene};
use grasp_transfer::{McapSink, RerunSink, Schedule, Sink, StepRecord, TransferOptions};
use serde_json::Value;
use support::example_path;

/// The example with an oblong image (90 x 60 pixels, one an element, rows 15 to 74 of the
/// patch's 90 along `t2`: an oblong image catches a width and height swapped), and its
/// schedule.
fn ridged_gel() -> (LoadedScene, Schedule) {
    let mut v = support::example_json("ridged_gel.json");
    v["fingers"][0]["sensor"]["gel"] =
        serde_json::json!({"image_px": [90, 60], "field_of_view_m": [0.0036, 0.0024]});
    let scene = LoadedScene::from_json_str(&v.to_string()).unwrap();
    let dir = std::path::PathBuf::from(example_path(""));
    let text = std::fs::read_to_string(dir.join("ridged_gel.schedule.json")).unwrap();
    let schedule = Schedule::from_json_str(&text, &scene.finger_names(), &dir).unwrap();
    (scene, schedule)
}

fn steps(scene: &LoadedScene, schedule: &Schedule, sinks: &mut [&mut dyn Sink]) -> Vec<StepRecord> {
    grasp_transfer::run_collect(scene, schedule, TransferOptions::default(), sinks)
        .unwrap()
        .0
}

/// At every step, every pixel on an element in contact reads the approach less the
/// element's initial gap (the sphere's profile with its ridges): the surfaces meet there.
/// To 1e-7 of the approach (the single-solve test, tests/gel_images.rs, measures 2e-15).
/// The approach is the sphere's sinking (the finger is held); it grows with the push.
#[test]
fn each_steps_image_meets_the_ridged_sphere_where_they_touch() {
    let (scene, schedule) = ridged_gel();
    let model = GraspModel::from_loaded(&scene).unwrap();
    let gap0 = &model.fingers()[0].patch().gap_m;
    let records = steps(&scene, &schedule, &mut []);
    assert_eq!(records.len(), 5);
    let mut last = 0.0;
    for r in &records {
        let image = r.sensors[0].gel.as_ref().expect("a gel image");
        assert_eq!(image.path, HeightPath::Lattice);
        let approach = -r.solution.rigid_displacement.unwrap().translation_m[2];
        assert!(approach > last, "step {}", r.index);
        last = approach;
        let mut touching = 0;
        for e in &r.solution.fingers[0].elements {
            if e.normal_force_n <= 0.0 {
                continue;
            }
            let [i, j] = e.index;
            if !(15..75).contains(&j) {
                continue;
            }
            touching += 1;
            let k = i * 90 + j;
            let off = image.height_m[i * 60 + j - 15] - (approach - gap0[k]);
            assert!(
                off.abs() < 1e-7 * approach,
                "step {} element {k}: {off:e}",
                r.index
            );
        }
        assert!(touching > 100, "step {}: {touching}", r.index);
    }
}

/// Base64 `data` of an image message.
fn data(v: &Value) -> Vec<u8> {
    use base64::Engine as _;
    let text = v["data"].as_str().unwrap();
    base64::engine::general_purpose::STANDARD
        .decode(text)
        .unwrap()
}

/// The record's image in the camera's order (docs/guide/tactile.md: columns along the image's
/// first side, rows along the second), 8-bit colours or float32 heights.
fn camera_bytes(image: &grasp_model::GelImage, colour: bool) -> Vec<u8> {
    let [nx, ny] = image.count;
    let mut out = Vec::new();
    for row in 0..ny {
        for column in 0..nx {
            let k = column * ny + row;
            match colour {
                true => out.extend(image.rgb[k].map(|c| (255.0 * c).round() as u8)),
                false => out.extend((image.height_m[k] as f32).to_le_bytes()),
            }
        }
    }
    out
}

/// Both topics have one `foxglove.RawImage` message a step, 90 wide (along `t1`) and 60 high,
/// the colour image and the heights (float32) the record's in the camera's order, byte for
/// byte, stamped with the step's time; the `rerun` CLI accepts the MCAP and the recording,
/// which has both images.
#[test]
fn the_mcap_and_the_recording_carry_each_steps_image() {
    let (scene, schedule) = ridged_gel();
    let dir = std::env::temp_dir().join(format!("grasp-gel-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (mcap, rrd) = (dir.join("g.mcap"), dir.join("g.rrd"));
    let mut m = McapSink::create(&mcap).unwrap();
    let mut r = RerunSink::create(&rrd).unwrap();
    let records = steps(&scene, &schedule, &mut [&mut m, &mut r]);
    let bytes = std::fs::read(&mcap).unwrap();
    let mut seen = [0usize; 2];
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        let kind = match msg.channel.topic.as_str() {
            "/grasp/tactile/gel/gel" => 0,
            "/grasp/tactile/gel/gel_height" => 1,
            _ => continue,
        };
        assert_eq!(
            msg.channel.schema.as_ref().unwrap().name,
            "foxglove.RawImage"
        );
        let v: Value = serde_json::from_slice(&msg.data).unwrap();
        let rec = &records[seen[kind]];
        let image = rec.sensors[0].gel.as_ref().unwrap();
        assert_eq!(
            (v["width"].as_u64(), v["height"].as_u64()),
            (Some(90), Some(60))
        );
        assert_eq!(v["frame_id"], "gel/gel");
        let ns = (rec.time_s * 1e9).round() as u64;
        assert_eq!(
            v["timestamp"]["sec"].as_u64().unwrap() * 1_000_000_000
                + v["timestamp"]["nsec"].as_u64().unwrap(),
            ns
        );
        let want = camera_bytes(image, kind == 0);
        assert_eq!(v["encoding"], ["rgb8", "32FC1"][kind]);
        assert_eq!(v["step"].as_u64(), Some(90 * [3, 4][kind]));
        assert_eq!(data(&v), want, "step {} topic {kind}", rec.index);
        seen[kind] += 1;
    }
    assert_eq!(seen, [records.len(); 2]);
    let Some(cli) = support::rerun_cli() else {
        return;
    };
    let checked = support::rerun_on(&cli, &["mcap", "check"], &mcap);
    assert!(
        checked.contains("/grasp/tactile/gel/gel_height"),
        "{checked}"
    );
    support::rerun_on(&cli, &["rrd", "verify"], &rrd);
    let text = support::rerun_on(&cli, &["rrd", "print"], &rrd);
    assert!(text.contains("tactile/gel/gel_height"), "{text}");
    assert!(text.contains("tactile/gel/gel"), "{text}");
}
