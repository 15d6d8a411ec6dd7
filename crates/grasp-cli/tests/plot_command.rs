//! `grasp plot`: the force diagram's content (both views, every finger named, one blue
//! normal-force arrow and one orange friction arrow per loaded finger and view, the weight),
//! the PNG form of the same picture, and the output rules (no overwrite without --force,
//! .svg or .png only).

use std::path::PathBuf;
use std::process::Command;

fn grasp() -> Command {
    Command::new(env!("CARGO_BIN_EXE_grasp"))
}

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn out_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-plot-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `grasp plot` of cube A into `out`.
fn plot_cube_a(out: impl AsRef<std::path::Path>) -> std::process::Output {
    grasp()
        .arg("plot")
        .arg(example("cube_a.json"))
        .arg("--out")
        .arg(out.as_ref())
        .output()
        .unwrap()
}

/// Polylines drawn in `color` (plotters writes `stroke="#RRGGBB"`).
fn strokes(svg: &str, color: &str) -> usize {
    svg.matches(&format!("stroke=\"{color}\"")).count()
}

#[test]
fn the_diagram_shows_every_finger_force_in_both_views() {
    // (scene, fingers, normal arrows, friction arrows) over both views; a force along a
    // view's line of sight is not drawn there. Gravity is -z, so both views hold z upright:
    // y-z and x-z (the contacts spread most along y). Cube A: f1, f2 push along y (y-z only),
    // f3 along z (both); f1's and f2's friction has x and z components, f3's x and y: each
    // shows in both views. Box pinch: both jaws push along y (y-z only), their friction is
    // vertical (both views).
    let cases = [
        ("cube_a.json", ["f1", "f2", "f3"].as_slice(), 4, 6),
        ("box_pinch.json", ["left", "right"].as_slice(), 2, 4),
    ];
    let dir = out_dir("content");
    for (scene, fingers, normal, friction) in cases {
        let out = dir.join(scene.replace(".json", ".svg"));
        let st = grasp()
            .arg("plot")
            .arg(example(scene))
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        let svg = std::fs::read_to_string(&out).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains(&format!("{scene}: solved")));
        assert_eq!(svg.matches("view onto").count(), 2);
        for f in fingers {
            // In the header's resultants and beside the contact in each view.
            assert!(svg.matches(f).count() >= 3, "{f}");
        }
        // Each arrow is a shaft and two head strokes.
        assert_eq!(
            strokes(&svg, "#1F64C8"),
            3 * normal,
            "normal arrows of {scene}"
        );
        assert_eq!(
            strokes(&svg, "#F08C14"),
            3 * friction,
            "friction arrows of {scene}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn existing_pictures_are_kept_and_only_svg_or_png_is_written() {
    let dir = out_dir("rules");
    let out = dir.join("mine.svg");
    std::fs::write(&out, "mine").unwrap();
    let st = plot_cube_a(&out);
    assert_eq!(st.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine");
    let st = plot_cube_a(dir.join("x.pdf"));
    assert_eq!(st.status.code(), Some(1));
    let err = String::from_utf8_lossy(&st.stderr);
    assert!(
        err.contains("--out") && err.contains(".svg or .png"),
        "{err}"
    );
    assert!(!dir.join("x.pdf").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// Pixels of exactly this colour in an RGB image.
fn pixels_of(rgb: &[u8], c: [u8; 3]) -> usize {
    rgb.chunks_exact(3).filter(|p| *p == c).count()
}

#[test]
fn a_png_diagram_is_the_same_picture_rasterised() {
    let dir = out_dir("png");
    let out = dir.join("cube_a.png");
    let st = plot_cube_a(&out);
    assert!(st.status.success(), "{st:?}");
    let bytes = std::fs::read(&out).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut rgb).unwrap();
    // The SVG's canvas size, 8-bit RGB.
    assert_eq!((info.width, info.height), (1100, 620));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    // The arrows are drawn in the diagram's blue (normal) and orange (friction), 2 px wide:
    // cube A shows four normal and six friction arrows over its two views, so each colour
    // covers many pixels; the background is white.
    let blue = pixels_of(&rgb, [31, 100, 200]);
    let orange = pixels_of(&rgb, [240, 140, 20]);
    assert!(blue > 200 && orange > 50, "blue {blue}, orange {orange}");
    assert!(pixels_of(&rgb, [255, 255, 255]) > rgb.len() / 3 / 2);
    std::fs::remove_dir_all(&dir).ok();
}

/// The segments `((x0, y0), (x1, y1))` of the 2 px polylines drawn in `color`, in drawing
/// order.
fn segments(svg: &str, color: &str) -> Vec<((f64, f64), (f64, f64))> {
    let mut out = Vec::new();
    for line in svg.lines().filter(|l| {
        l.starts_with("<polyline")
            && l.contains(&format!("stroke=\"{color}\""))
            && l.contains("stroke-width=\"2\"")
    }) {
        let points = line
            .split("points=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let xy: Vec<(f64, f64)> = points
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        out.push((xy[0], xy[xy.len() - 1]));
    }
    out
}

fn length(((x0, y0), (x1, y1)): ((f64, f64), (f64, f64))) -> f64 {
    (x1 - x0).hypot(y1 - y0)
}

/// The force diagram had no scale: its arrows' lengths could not be read. Each view now has
/// a scale arrow labelled with its force (`2 N`), drawn at the view's scale of the force
/// arrows: every normal-force arrow's shaft is its finger's normal force (from `grasp solve
/// --json`) times the scale arrow's pixels per newton, across the page and up it alike.
#[test]
fn the_force_diagram_has_a_scale_arrow_at_its_force_arrows_scale() {
    let dir = out_dir("scale");
    let (svg_path, json) = (dir.join("cube_a.svg"), dir.join("cube_a.json"));
    assert!(plot_cube_a(&svg_path).status.success());
    let st = grasp()
        .arg("solve")
        .arg(example("cube_a.json"))
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    assert!(st.status.success());
    let solution: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let mut loads: Vec<f64> = solution["fingers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["normal_force_n"].as_f64().unwrap())
        .collect();
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    // Each arrow is its shaft, then two head strokes.
    let shafts = |c: &str| -> Vec<((f64, f64), (f64, f64))> {
        segments(&svg, c).into_iter().step_by(3).collect()
    };
    let scales = shafts("#3C3C3C");
    assert_eq!(scales.len(), 2, "one scale arrow per view");
    let lines: Vec<&str> = svg.lines().collect();
    let labels: Vec<f64> = lines
        .windows(2)
        .filter(|w| w[0].starts_with("<text"))
        .filter_map(|w| w[1].trim().strip_suffix(" N")?.parse().ok())
        .collect();
    assert_eq!(labels.len(), 2, "{labels:?}");
    // Cube A, view y-z (left of 550 px): all three normal forces lie in it (f1, f2 across,
    // f3 up); view x-z: f3's.
    loads.sort_by(f64::total_cmp);
    let normals = shafts("#1F64C8");
    for (view, (scale, force_n)) in scales.iter().zip(&labels).enumerate() {
        let px_per_n = length(*scale) / force_n;
        assert!(
            length(*scale) >= 20.0 && length(*scale) <= 90.0,
            "{scale:?}"
        );
        let mut drawn: Vec<f64> = normals
            .iter()
            .filter(|s| ((s.0).0 < 550.0) == (view == 0))
            .map(|s| length(*s))
            .collect();
        drawn.sort_by(f64::total_cmp);
        let expected: Vec<f64> = match view {
            0 => loads.clone(),
            _ => vec![solution["fingers"][2]["normal_force_n"].as_f64().unwrap()],
        };
        assert_eq!(drawn.len(), expected.len(), "view {view}: {drawn:?}");
        for (px, p) in drawn.iter().zip(&expected) {
            // Each end is rounded to a pixel, the scale arrow's length too.
            let tol = 1.0 + 0.5 * px / length(*scale) + 0.01;
            assert!(
                (px - p * px_per_n).abs() <= tol,
                "view {view}: a {p} N arrow is {px} px, the scale says {} px",
                p * px_per_n
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
