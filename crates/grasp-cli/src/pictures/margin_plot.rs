//! The picture of `grasp margin --plot` (SVG or PNG, drawn with plotters): polar panels of
//! the pure-force directions in each coordinate plane (`--directions planes:K` fills them),
//! then one bar per direction; the smallest margin in red, unbounded ones pale (hollow in the
//! panels, drawn at the cap).

use anyhow::Result;
use grasp_model::GraspModel;
use grasp_model::MotionPlane;
use grasp_model::{DirectionMargin, MarginReport, WrenchDirection};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::pictures::picture::{draw_err, Picture};

const BLUE: RGBColor = RGBColor(31, 119, 180);
const PALE: RGBColor = RGBColor(174, 199, 232);
const RED: RGBColor = RGBColor(214, 39, 40);
const GRID: RGBColor = RGBColor(221, 221, 221);

/// Height of the title and panel band, pixels; each bar row below takes [`ROW`].
const PANELS_PX: u32 = 270;
const ROW: u32 = 18;
const WIDTH: u32 = 800;

/// A short label of a direction: its nonzero components (`F[...]` in N, `T[...]` in N m).
pub fn label(d: &WrenchDirection) -> String {
    let part = |v: &[f64; 3], unit: &str| -> Option<String> {
        (v.iter().any(|c| c.abs() > 1e-12)).then(|| {
            // A component that rounds to zero prints as +0.00, never -0.00.
            let c = |x: f64| if x.abs() < 0.005 { 0.0 } else { x };
            format!("{unit}[{:+.2},{:+.2},{:+.2}]", c(v[0]), c(v[1]), c(v[2]))
        })
    };
    [part(&d.force, "F"), part(&d.torque, "T")]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The margins of `report` (of `model`) as polar panels and bars.
pub struct MarginPlot<'a> {
    pub model: &'a GraspModel,
    pub report: &'a MarginReport,
}

impl Picture for MarginPlot<'_> {
    fn size(&self) -> (u32, u32) {
        let n = self.report.directions.len() as u32;
        (WIDTH, PANELS_PX + 40 + ROW * n)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let r = self.report;
        root.fill(&WHITE).map_err(draw_err)?;
        let title = format!(
            "Disturbance margins (N; a couple is the margin times L = {:.4} m)",
            r.length_m
        );
        root.draw(&Text::new(title, (10, 4), ("sans-serif", 13)))
            .map_err(draw_err)?;
        let (top, bottom) = root.split_vertically(PANELS_PX);
        let r_max = rim_margin(r);
        let top = top.margin(24, 0, 10, 0);
        for (k, plane) in panel_planes(self.model).iter().enumerate() {
            let x0 = 260 * k as i32;
            let area = top.clone().shrink((x0, 0), (240, 230));
            polar_panel(&area, r, plane, r_max)?;
        }
        bars(&bottom, r)
    }
}

/// The margin drawn at the panels' rim: the largest bounded one (or the largest of all when
/// none is bounded), N.
fn rim_margin(r: &MarginReport) -> f64 {
    let bounded_max = r
        .directions
        .iter()
        .filter(|d| d.bounded)
        .map(|d| d.held_to_n)
        .fold(0.0_f64, f64::max);
    if bounded_max > 0.0 {
        return bounded_max;
    }
    r.directions
        .iter()
        .map(|d| d.held_to_n)
        .fold(f64::MIN_POSITIVE, f64::max)
}

/// A polar panel: its title, its in-plane axes `a` (to the right) and `b` (up) as world
/// unit vectors, and their names as the panel labels them.
struct PanelPlane {
    title: String,
    a: [f64; 3],
    b: [f64; 3],
    names: [String; 2],
}

/// The coordinate planes of the polar panels (3-D: `xy`, `yz`, `zx`; planar: the plane of
/// motion, its axes `e1`, `e2` named by the world axis they lie along, or given as vectors),
/// each titled with its axes: `+x right, +y up`.
fn panel_planes(model: &GraspModel) -> Vec<PanelPlane> {
    const X: [f64; 3] = [1.0, 0.0, 0.0];
    const Y: [f64; 3] = [0.0, 1.0, 0.0];
    const Z: [f64; 3] = [0.0, 0.0, 1.0];
    let plane = |title: &str, a: [f64; 3], b: [f64; 3]| PanelPlane {
        title: title.to_string(),
        a,
        b,
        names: [axis_name(&a, "e1"), axis_name(&b, "e2")],
    };
    match model.plane() {
        None => vec![
            plane("force in the x-y plane", X, Y),
            plane("force in the y-z plane", Y, Z),
            plane("force in the z-x plane", Z, X),
        ],
        Some(MotionPlane { e1, e2, .. }) => {
            let (a, b) = ([e1.x, e1.y, e1.z], [e2.x, e2.y, e2.z]);
            vec![plane("force in the plane of motion", a, pointing_up(b))]
        }
    }
}

/// The panel's up axis `b`, or its opposite when `b` points down (its largest component
/// negative): a plane of motion whose `e2` is `-z` is drawn with `+z` up, as a reader expects
/// (the panel is then the plane seen from its other side).
fn pointing_up(b: [f64; 3]) -> [f64; 3] {
    let largest = b
        .iter()
        .copied()
        .fold(0.0_f64, |m, v| if v.abs() > m.abs() { v } else { m });
    match largest < 0.0 {
        true => b.map(|v| -v),
        false => b,
    }
}

/// `+x`, `-z`, ... for a world axis direction; `name [a, b, c]` otherwise.
fn axis_name(v: &[f64; 3], name: &str) -> String {
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let others = (0..3).filter(|&j| j != k).all(|j| v[j].abs() < 1e-12);
        if others && (v[k].abs() - 1.0).abs() < 1e-12 {
            return format!("{}{axis}", if v[k] > 0.0 { "+" } else { "-" });
        }
    }
    format!("{name} [{:.2}, {:.2}, {:.2}]", v[0], v[1], v[2])
}

/// A point of a polar panel: angle (rad), radius (fraction of the rim), bounded, index.
type PolarPoint = (f64, f64, bool, usize);

/// The pure-force directions lying in the plane `(a, b)`, by angle.
fn in_plane_points(r: &MarginReport, a: &[f64; 3], b: &[f64; 3], r_max: f64) -> Vec<PolarPoint> {
    let dot = |u: &[f64; 3], v: &[f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let mut pts: Vec<PolarPoint> = Vec::new();
    for (i, d) in r.directions.iter().enumerate() {
        let f = d.direction.force;
        let (fa, fb) = (dot(&f, a), dot(&f, b));
        let pure = d.direction.torque.iter().all(|t| *t == 0.0);
        if pure && (fa * fa + fb * fb - 1.0).abs() < 1e-9 {
            let m = if d.bounded {
                d.held_to_n.min(r_max)
            } else {
                r_max
            };
            pts.push((fb.atan2(fa), m / r_max, d.bounded, i));
        }
    }
    pts.sort_by(|p, q| p.0.total_cmp(&q.0));
    pts
}

/// One polar panel: rings at quarters of the rim margin, the in-plane directions at their
/// angle with radius proportional to the margin, joined into a polygon.
fn polar_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    r: &MarginReport,
    plane: &PanelPlane,
    r_max: f64,
) -> Result<()> {
    let (a, b) = (plane.a, plane.b);
    // The title and the axes' names on two lines, then a square plotting area: rings stay
    // circles.
    let (head, rest) = area.split_vertically(30);
    let font = TextStyle::from(("sans-serif", 11).into_font());
    let axes = format!("{} right, {} up", plane.names[0], plane.names[1]);
    for (k, line) in [plane.title.as_str(), axes.as_str()]
        .into_iter()
        .enumerate()
    {
        head.draw(&Text::new(line, (0, 14 * k as i32), font.clone()))
            .map_err(draw_err)?;
    }
    let (w, h) = rest.dim_in_pixel();
    let side = w.min(h);
    let offset = (((w - side) / 2) as i32, ((h - side) / 2) as i32);
    let square = rest.shrink(offset, (side, side));
    let mut chart = ChartBuilder::on(&square)
        .build_cartesian_2d(-1.1..1.1, -1.1..1.1)
        .map_err(draw_err)?;
    let ring = |k: f64| {
        (0..=72)
            .map(move |i| i as f64 * 5f64.to_radians())
            .map(move |t| (k * t.cos(), k * t.sin()))
    };
    for k in 1..=4 {
        chart
            .draw_series(LineSeries::new(ring(k as f64 / 4.0), GRID))
            .map_err(draw_err)?;
    }
    let rim = Text::new(
        format!("{} N", crate::report::significant(r_max, 4)),
        (0.1, 1.06),
        ("sans-serif", 11)
            .into_font()
            .color(&RGBColor(136, 136, 136)),
    );
    chart.draw_series(std::iter::once(rim)).map_err(draw_err)?;
    // The panel's axes through the centre (named above).
    for ends in [[(-1.0, 0.0), (1.0, 0.0)], [(0.0, -1.0), (0.0, 1.0)]] {
        chart
            .draw_series(LineSeries::new(ends, GRID))
            .map_err(draw_err)?;
    }
    let pts = in_plane_points(r, &a, &b, r_max);
    let xy = |p: &PolarPoint| (p.1 * p.0.cos(), p.1 * p.0.sin());
    if pts.len() >= 3 {
        let poly: Vec<(f64, f64)> = pts.iter().map(xy).collect();
        chart
            .draw_series(std::iter::once(Polygon::new(poly.clone(), BLUE.mix(0.15))))
            .map_err(draw_err)?;
        let closed = poly.iter().chain(poly.first()).copied();
        chart
            .draw_series(LineSeries::new(closed, BLUE))
            .map_err(draw_err)?;
    }
    for p in &pts {
        let colour = if p.3 == r.smallest { RED } else { BLUE };
        let style = if p.2 {
            colour.filled()
        } else {
            colour.stroke_width(1)
        };
        chart
            .draw_series(std::iter::once(Circle::new(xy(p), 3.5, style)))
            .map_err(draw_err)?;
    }
    Ok(())
}

/// One bar per direction, scaled to the largest bounded margin (unbounded ones fill the row,
/// their value marked ">").
fn bars<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, r: &MarginReport) -> Result<()> {
    let (left, width) = (260_i32, 420.0);
    let max = r
        .directions
        .iter()
        .filter(|d| d.bounded)
        .map(|d| d.held_to_n)
        .fold(0.0_f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let font = TextStyle::from(("sans-serif", 11).into_font());
    area.draw(&Text::new("margin per direction", (10, 4), font.clone()))
        .map_err(draw_err)?;
    let right = font.pos(Pos::new(HPos::Right, VPos::Center));
    let after = font.pos(Pos::new(HPos::Left, VPos::Center));
    for (i, d) in r.directions.iter().enumerate() {
        let y = 26 + (ROW as i32) * i as i32;
        let len = if d.bounded {
            width * d.held_to_n / max
        } else {
            width
        };
        let fill = match (i == r.smallest, d.bounded) {
            (true, _) => RED,
            (false, true) => BLUE,
            (false, false) => PALE,
        };
        let mid = y + (ROW as i32 - 4) / 2;
        area.draw(&Text::new(
            label(&d.direction),
            (left - 6, mid),
            right.clone(),
        ))
        .map_err(draw_err)?;
        let end = left + len.round() as i32;
        area.draw(&Rectangle::new(
            [(left, y), (end, y + ROW as i32 - 4)],
            fill.filled(),
        ))
        .map_err(draw_err)?;
        let value = margin_cell(d);
        area.draw(&Text::new(value, (end + 4, mid), after.clone()))
            .map_err(draw_err)?;
    }
    Ok(())
}

/// A direction's margin as the table shows it: the margin, `>cap` when the grasp held at the
/// search's cap (unbounded), `>=held` when undetermined above what held.
pub fn margin_cell(m: &DirectionMargin) -> String {
    match m.margin_n {
        Some(v) => crate::report::significant(v, 5),
        None if m.is_unbounded() => format!(">{}", crate::report::significant(m.held_to_n, 4)),
        None => format!(">={}", crate::report::significant(m.held_to_n, 4)),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_label_never_shows_minus_zero() {
        let d = WrenchDirection {
            force: [-0.0, -1.0, -1e-9],
            torque: [0.0; 3],
        };
        assert_eq!(super::label(&d), "F[+0.00,-1.00,+0.00]");
    }

    use super::*;

    /// A panel axis along a world axis is named by it (with its sign); any other by its
    /// vector.
    #[test]
    fn panel_axes_are_named_by_the_world_axis_they_lie_along() {
        assert_eq!(axis_name(&[1.0, 0.0, 0.0], "e1"), "+x");
        assert_eq!(axis_name(&[0.0, 0.0, -1.0], "e2"), "-z");
        assert_eq!(axis_name(&[0.6, 0.8, 0.0], "e1"), "e1 [0.60, 0.80, 0.00]");
        assert_eq!(
            axis_name(&[0.0, 1.0 + 1e-9, 0.0], "e2"),
            "e2 [0.00, 1.00, 0.00]"
        );
    }
}
