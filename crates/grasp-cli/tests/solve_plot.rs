//! `grasp solve --plot`: the contact maps of a single solve (a solve used to draw no picture of
//! its pressures or its stick and slip). Each finger gets a pressure map whose colour bar tops
//! at the peak pressure the JSON reports, and a state map with one cell per element in the
//! state the JSON counts; a frictionless finger says it has no stick or slip; a fine patch is
//! drawn in blocks, so the picture stays small; an existing file is kept without --force.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn grasp() -> Command {
    Command::new(env!("CARGO_BIN_EXE_grasp"))
}

fn example(name: &str) -> PathBuf {
    PathBuf::from(common::example(name))
}

fn out_dir(tag: &str) -> PathBuf {
    common::tmp("solve-plot", tag)
}

/// `grasp solve SCENE --json J --plot P`: the SVG text and the JSON.
fn solve_with_plot(scene: &Path, dir: &Path) -> (String, serde_json::Value) {
    let (json, svg) = (dir.join("s.json"), dir.join("s.svg"));
    let st = grasp()
        .arg("solve")
        .arg(scene)
        .arg("--json")
        .arg(&json)
        .arg("--plot")
        .arg(&svg)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let svg = std::fs::read_to_string(&svg).unwrap();
    let json = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    (svg, json)
}

/// The texts the SVG sets, in drawing order (plotters writes each on the line after its
/// `<text ...>` tag).
fn texts(svg: &str) -> Vec<String> {
    let lines: Vec<&str> = svg.lines().collect();
    lines
        .windows(2)
        .filter(|w| w[0].starts_with("<text"))
        .map(|w| w[1].trim().to_owned())
        .collect()
}

/// The SVG from the line of `start`'s text to the next `end`'s text (or the end).
fn section<'a>(svg: &'a str, start: &str, end: Option<&str>) -> &'a str {
    let a = svg.find(&format!("\n{start}\n")).expect(start);
    let b = end.map_or(svg.len(), |e| {
        a + svg[a..].find(&format!("\n{e}\n")).expect(e)
    });
    &svg[a..b]
}

/// Rectangles filled with `rgb` (`#RRGGBB`) in `svg`.
fn rects(svg: &str, rgb: &str) -> usize {
    svg.lines()
        .filter(|l| l.starts_with("<rect") && l.contains(&format!("fill=\"{rgb}\"")))
        .count()
}

/// A pressure label `73.996 kPa (peak)` in pascals.
fn label_pa(text: &str) -> f64 {
    let mut words = text.split_whitespace();
    let value: f64 = words.next().unwrap().parse().unwrap();
    let scale = match words.next().unwrap() {
        "MPa" => 1e6,
        "kPa" => 1e3,
        "Pa" => 1.0,
        u => panic!("unit {u}"),
    };
    value * scale
}

const STICK: &str = "#2CA02C";
const SLIP: &str = "#D62728";
const NO_CONTACT: &str = "#D7D7D7";
const FRICTIONLESS: &str = "#1F77B4";

#[test]
fn solve_plot_draws_each_fingers_pressure_up_to_its_peak_and_its_states_as_counted() {
    for scene in ["cube_a.json", "mug_power_grasp.json", "edge_pinch.json"] {
        let dir = out_dir(&scene.replace(".json", ""));
        let (svg, json) = solve_with_plot(&example(scene), &dir);
        let fingers = json["fingers"].as_array().unwrap();
        let all = texts(&svg);
        let peaks: Vec<&String> = all.iter().filter(|t| t.ends_with("(peak)")).collect();
        assert_eq!(
            peaks.len(),
            fingers.len(),
            "{scene}: one colour bar per finger"
        );
        for (k, f) in fingers.iter().enumerate() {
            let name = f["name"].as_str().unwrap();
            let pressure = format!("{name}: contact pressure");
            let state = format!("{name}: contact state (energy model)");
            assert_eq!(all.iter().filter(|t| **t == pressure).count(), 1, "{scene}");
            // The colour bar's top label is the JSON's peak, to its five digits.
            let peak = f["peak_pressure_pa"].as_f64().unwrap();
            let drawn = label_pa(peaks[k]);
            assert!(
                (drawn - peak).abs() <= 5e-5 * peak,
                "{scene} {name}: bar tops at {drawn} Pa, the peak is {peak} Pa"
            );
            // The state map: one cell per element, in the state the JSON counts.
            let next = fingers
                .get(k + 1)
                .map(|g| format!("{}: contact pressure", g["name"].as_str().unwrap()));
            let panel = section(&svg, &state, next.as_deref());
            let count = |key: &str| f[key].as_u64().unwrap_or(0) as usize;
            assert_eq!(
                rects(panel, STICK),
                count("stick_count"),
                "{scene} {name} stick"
            );
            assert_eq!(
                rects(panel, SLIP),
                count("slip_count"),
                "{scene} {name} slip"
            );
            assert_eq!(
                rects(panel, NO_CONTACT),
                count("separated_count") + count("off_surface_count"),
                "{scene} {name} no contact"
            );
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}

#[test]
fn solve_plot_of_a_frictionless_finger_says_it_has_no_stick_or_slip() {
    let dir = out_dir("frictionless");
    let (svg, json) = solve_with_plot(&example("hertz_sphere_on_flat.json"), &dir);
    let f = &json["fingers"][0];
    let all = texts(&svg);
    assert!(all.iter().any(|t| t == "no stick or slip"), "{all:?}");
    assert!(!all.iter().any(|t| t == "stick" || t == "slip"), "{all:?}");
    let panel = section(&svg, "tip: contact state (energy model)", None);
    assert_eq!(rects(panel, STICK) + rects(panel, SLIP), 0);
    assert_eq!(
        rects(panel, FRICTIONLESS),
        f["frictionless_count"].as_u64().unwrap() as usize
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn solve_plot_of_a_fine_patch_is_drawn_in_blocks_and_stays_small() {
    let dir = out_dir("fine");
    let text = std::fs::read_to_string(example("hertz_sphere_on_flat.json")).unwrap();
    let fine = text.replace("\"grid\": [21, 21]", "\"grid\": [200, 200]");
    assert_ne!(fine, text);
    let scene = dir.join("hertz_200.json");
    std::fs::write(&scene, fine).unwrap();
    let (svg, json) = solve_with_plot(&scene, &dir);
    // 200 elements a side in blocks of 4: 50 x 50 cells, each no contact or in contact.
    let panel = section(&svg, "tip: contact state (energy model)", None);
    assert_eq!(
        rects(panel, FRICTIONLESS) + rects(panel, NO_CONTACT),
        50 * 50
    );
    // The largest block pressure is the peak: the colour bar still tops at it.
    let peak = json["fingers"][0]["peak_pressure_pa"].as_f64().unwrap();
    let top = texts(&svg)
        .into_iter()
        .find(|t| t.ends_with("(peak)"))
        .unwrap();
    assert!(
        (label_pa(&top) - peak).abs() <= 5e-5 * peak,
        "{top} against {peak}"
    );
    assert!(svg.len() < 600_000, "{} bytes", svg.len());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn solve_plot_keeps_an_existing_file_and_takes_only_svg_or_png() {
    let dir = out_dir("rules");
    let out = dir.join("mine.svg");
    std::fs::write(&out, "mine").unwrap();
    let run = |plot: &Path| {
        grasp()
            .arg("solve")
            .arg(example("cube_a.json"))
            .arg("--plot")
            .arg(plot)
            .output()
            .unwrap()
    };
    let st = run(&out);
    assert_eq!(st.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine");
    let st = run(&dir.join("x.pdf"));
    assert_eq!(st.status.code(), Some(1));
    let err = String::from_utf8_lossy(&st.stderr);
    assert!(
        err.contains("--plot") && err.contains(".svg or .png"),
        "{err}"
    );
    assert!(!dir.join("x.pdf").exists());
    std::fs::remove_dir_all(&dir).ok();
}
