//! `grasp plot`: the force diagram of one solve (SVG or PNG, drawn with plotters). Two orthographic
//! views (the coordinate planes that show the contacts best, gravity down the page when it
//! lies along an axis): the object's outline (its shape's silhouette, or the box around the
//! contacts), each finger's contact point and name (at its normal arrow's tail), its
//! normal force (blue) and friction force (orange) as arrows pushing on the object at the
//! centre of pressure, its friction cone (grey, half-angle `atan(mu)` about the normal), and
//! the weight at the centre of mass (black). Arrows: the load scale drawn as 0.3 of the scene;
//! each view's scale arrow (a round force, `2 N`, at the top right) shows how long a newton is.
//! The names are placed so that none covers another or an arrow (a thin line leads back to the
//! arrow's tail when a name had to move).

use anyhow::Result;
use grasp_model::{GraspModel, Scene, Solution};
use grasp_transfer::{arrow_scale_m_per_n, FRICTION_FORCE_RGB, NORMAL_FORCE_RGB};
use nalgebra::Vector3;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::pictures::label_placement::{place_labels, LabelBox};
use crate::pictures::picture::{draw_err as plot_err, Picture};

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

const AXES: [&str; 3] = ["x", "y", "z"];
/// The arrows' colours: the key of every output (`grasp_transfer::NORMAL_FORCE_RGB`,
/// `grasp_transfer::FRICTION_FORCE_RGB`).
const NORMAL: RGBColor = key_colour(NORMAL_FORCE_RGB);
const FRICTION: RGBColor = key_colour(FRICTION_FORCE_RGB);

/// A colour of the key as plotters'.
const fn key_colour([r, g, b]: [u8; 3]) -> RGBColor {
    RGBColor(r, g, b)
}

/// What a view draws, in world coordinates.
struct Drawing<'a> {
    scene: &'a Scene,
    model: &'a GraspModel,
    solution: &'a Solution,
    /// Metres per newton of the arrows.
    m_per_n: f64,
    /// Length of the cone edges, m.
    cone_m: f64,
}

/// The force diagram of `solution` (of `model`, built from `scene`), titled `title`.
pub struct ForceDiagram<'a> {
    pub scene: &'a Scene,
    pub model: &'a GraspModel,
    pub solution: &'a Solution,
    pub title: &'a str,
}

impl Picture for ForceDiagram<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 620)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (scene, model, solution) = (self.scene, self.model, self.solution);
        let points = outline_points(model);
        let (lo, hi) = bounds(&points);
        let size = (hi - lo).norm().max(1e-3);
        let d = Drawing {
            scene,
            model,
            solution,
            m_per_n: arrow_scale_m_per_n(size, model.scales().load_n),
            cone_m: 0.15 * size,
        };
        // The views show the object and every arrow's far end.
        let mut reach = points.clone();
        reach.extend(arrow_ends(&d));
        let (lo, hi) = bounds(&reach);
        let [first, second] = view_axes(model, scene.object.gravity);
        root.fill(&WHITE).map_err(plot_err)?;
        let (head, body) = root.split_vertically(80);
        header(&head, self.title, solution)?;
        let (left, right) = body.split_horizontally(550);
        for (area, (u, v)) in [(&left, first), (&right, second)] {
            view(area, &d, &points, (u, v), (lo, hi))?;
        }
        Ok(())
    }
}

/// Points whose silhouette is the object: its shape's surface, or the corners of the box
/// around the contact points and centre of mass.
fn outline_points(model: &GraspModel) -> Vec<Vector3<f64>> {
    if let Some(surface) = model.object_surface() {
        return surface
            .vertices_m
            .iter()
            .map(|v| Vector3::from(*v))
            .collect();
    }
    let mut pts: Vec<Vector3<f64>> = model.fingers().iter().map(|f| f.frame().origin_m).collect();
    pts.push(model.center_of_mass_m());
    let (lo, hi) = bounds(&pts);
    let pad = (hi - lo).norm().max(1e-3) * 0.02;
    (0..8)
        .map(|i| {
            Vector3::from_fn(|k, _| {
                if (i >> k) & 1 == 1 {
                    hi[k] + pad
                } else {
                    lo[k] - pad
                }
            })
        })
        .collect()
}

/// The far ends of the force arrows (tails) and of the weight (head), world.
fn arrow_ends(d: &Drawing) -> Vec<Vector3<f64>> {
    let mut ends = Vec::new();
    for f in &d.solution.fingers {
        if let Some(m) = d.model.fingers().iter().find(|m| m.name() == f.name) {
            let cop = Vector3::from(f.center_of_pressure_m);
            ends.push(cop - m.frame().normal * (f.normal_force_n * d.m_per_n));
            ends.push(cop - Vector3::from(f.tangential_force_n) * d.m_per_n);
            ends.push(m.frame().origin_m - m.frame().normal * d.cone_m);
        }
    }
    let o = &d.scene.object;
    ends.push(
        d.model.center_of_mass_m() + Vector3::from(o.gravity).normalize() * (o.weight * d.m_per_n),
    );
    ends
}

fn bounds(points: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    let first = points.first().copied().unwrap_or_else(Vector3::zeros);
    points
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

/// The axes `(across, up the page)` of the two views. Gravity along a coordinate axis (within
/// about 25 degrees) is drawn down the page in both views: the views are onto that axis and
/// each other one, the one the contacts spread along most first. Otherwise `[a, b, c]`, `a`
/// the axis along which the contacts spread most, `b` the next, draws (a, b) and (a, c).
fn view_axes(model: &GraspModel, gravity: [f64; 3]) -> [(usize, usize); 2] {
    let pts: Vec<Vector3<f64>> = model.fingers().iter().map(|f| f.frame().origin_m).collect();
    let (lo, hi) = bounds(&pts);
    let spread = hi - lo;
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| spread[j].total_cmp(&spread[i]).then(i.cmp(&j)));
    match gravity_axis(gravity) {
        Some(k) => {
            let mut across = order.into_iter().filter(|&i| i != k);
            let (u1, u2) = (across.next().unwrap_or(0), across.next().unwrap_or(1));
            [(u1, k), (u2, k)]
        }
        None => [(order[0], order[1]), (order[0], order[2])],
    }
}

fn header<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    s: &Solution,
) -> Result<()> {
    let style = ("sans-serif", 18).into_font();
    area.draw(&Text::new(
        format!("{title}: {}", s.status.as_str()),
        (20, 10),
        style,
    ))
    .map_err(plot_err)?;
    let key = "blue: normal force, orange: friction force (pushing on the object at the centre of pressure); grey: friction cone; black: weight at the centre of mass; top right of each view: the arrows' scale";
    area.draw(&Text::new(key, (20, 58), ("sans-serif", 12).into_font()))
        .map_err(plot_err)?;
    let line: Vec<String> = s
        .fingers
        .iter()
        .map(|f| {
            format!(
                "{} P {} N, |Q| {} N",
                f.name,
                fixed3(f.normal_force_n),
                fixed3(f.tangential_magnitude_n)
            )
        })
        .collect();
    let small = ("sans-serif", 13).into_font();
    area.draw(&Text::new(line.join(";  "), (20, 40), small))
        .map_err(plot_err)?;
    Ok(())
}

/// `v` with three decimals, without the sign of a value that rounds to zero (solver noise).
fn fixed3(v: f64) -> String {
    let s = format!("{v:.3}");
    match s.as_str() {
        "-0.000" => "0.000".to_owned(),
        _ => s,
    }
}

/// One orthographic view onto the axes `(u, v)`.
fn view<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    d: &Drawing,
    outline: &[Vector3<f64>],
    (u, v): (usize, usize),
    (lo, hi): (Vector3<f64>, Vector3<f64>),
) -> Result<()> {
    // Gravity along +v would point up the page: the page's up is then -v.
    let s = if d.scene.object.gravity[v] > 0.0 && gravity_axis(d.scene.object.gravity) == Some(v) {
        -1.0
    } else {
        1.0
    };
    let up = if s < 0.0 {
        format!("-{}", AXES[v])
    } else {
        AXES[v].to_owned()
    };
    let (cu, cv) = ((lo[u] + hi[u]) / 2.0, s * (lo[v] + hi[v]) / 2.0);
    let half = 0.5 * (hi[u] - lo[u]).max(hi[v] - lo[v]).max(1e-3) * 1.1;
    let caption = format!("view onto {}-{up} [m]", AXES[u]);
    let (band, body) = (
        area,
        area.titled(&caption, ("sans-serif", 15))
            .map_err(plot_err)?,
    );
    let area = &body;
    // The plot area (the body less the margins and label areas below) gets ranges in its own
    // proportions, so that a metre, and a newton of the arrows, is as long across as up.
    let (w, h) = area.dim_in_pixel();
    let (pw, ph) = (
        (f64::from(w) - 2.0 * 12.0 - 56.0).max(1.0),
        (f64::from(h) - 2.0 * 12.0 - 32.0).max(1.0),
    );
    let (hu, hv) = match pw >= ph {
        true => (half * pw / ph, half),
        false => (half, half * ph / pw),
    };
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(32)
        .y_label_area_size(56)
        .build_cartesian_2d(cu - hu..cu + hu, cv - hv..cv + hv)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(AXES[u])
        .y_desc(up.as_str())
        .max_light_lines(0)
        .draw()
        .map_err(plot_err)?;
    let p2 = |p: &Vector3<f64>| (p[u], s * p[v]);
    let hull = convex_hull(outline.iter().map(p2).collect());
    chart
        .draw_series(std::iter::once(Polygon::new(
            hull,
            RGBColor(200, 200, 210).mix(0.5),
        )))
        .map_err(plot_err)?;
    draw_weight(&mut chart, d, &p2)?;
    for f in &d.solution.fingers {
        draw_finger(&mut chart, d, f, &p2)?;
    }
    // Pixels per newton of this view's arrows (pixels per metre, the same across and up).
    let (xs, _) = chart.plotting_area().get_pixel_range();
    let px_per_n = f64::from(xs.end - xs.start) / (2.0 * hu) * d.m_per_n;
    draw_scale_arrow(band, px_per_n)?;
    draw_names(area, &chart, d, &p2)
}

/// The scale arrow's colour (dark grey: apart from the forces' colours and the weight's black).
pub const SCALE_ARROW: RGBColor = RGBColor(60, 60, 60);

/// Longest drawn scale arrow, px.
const SCALE_ARROW_MAX_PX: f64 = 90.0;

/// A scale arrow in the view's caption band (`band`: the whole view), at its right: a round force (1, 2 or 5 times a
/// power of ten newtons) drawn at `px_per_n`, the view's scale of the force arrows, labelled
/// with its value (`2 N`), at most [`SCALE_ARROW_MAX_PX`] long; none when the scale is not
/// finite and positive.
fn draw_scale_arrow<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    px_per_n: f64,
) -> Result<()> {
    let Some(force_n) = round_force_below(SCALE_ARROW_MAX_PX / px_per_n) else {
        return Ok(());
    };
    let length = (force_n * px_per_n).round() as i32;
    let label = format!("{} N", force_text(force_n));
    let font = TextStyle::from(("sans-serif", 12).into_font());
    let (w, _) = area.dim_in_pixel();
    let (label_w, label_h) = area.estimate_text_size(&label, &font).map_err(plot_err)?;
    let y = 12;
    let end = w as i32 - 14 - label_w as i32 - 6;
    let start = end - length;
    let style = ShapeStyle::from(&SCALE_ARROW).stroke_width(2);
    area.draw(&PathElement::new(vec![(start, y), (end, y)], style))
        .map_err(plot_err)?;
    for wing in [-1, 1] {
        area.draw(&PathElement::new(
            vec![(end, y), (end - 6, y + 3 * wing)],
            style,
        ))
        .map_err(plot_err)?;
    }
    area.draw(&Text::new(label, (end + 6, y - label_h as i32 / 2), font))
        .map_err(plot_err)
}

/// The largest of 1, 2 and 5 times a power of ten at most `limit_n` (N), if `limit_n` is finite
/// and positive.
fn round_force_below(limit_n: f64) -> Option<f64> {
    if !(limit_n.is_finite() && limit_n > 0.0) {
        return None;
    }
    let decade = 10f64.powf(limit_n.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&f| f <= limit_n * (1.0 + 1e-12))
}

/// A round force as its label writes it: `2`, `0.05`, `5000`.
fn force_text(force_n: f64) -> String {
    let decimals = (-force_n.log10().floor()).max(0.0) as usize;
    format!("{force_n:.decimals$}")
}

/// The coordinate axis `gravity` points along (within about 25 degrees), if any.
fn gravity_axis(gravity: [f64; 3]) -> Option<usize> {
    let g = Vector3::from(gravity);
    (0..3)
        .max_by(|&i, &j| g[i].abs().total_cmp(&g[j].abs()))
        .filter(|&k| g.norm() > 0.0 && g[k].abs() >= 0.9 * g.norm())
}

/// Size of the finger names, px.
const NAME_PX: u32 = 13;

/// Each finger's name just beyond the tail of its normal-force arrow (outside the object along
/// the normal, so each arrow says whose it is; an unloaded finger's just beyond its contact)
/// where that spot is free, else at the nearest free spot ([`place_labels`]: no two names
/// overlap, and none covers a contact point, the centre of mass or an arrow), with a thin line
/// back to the arrow's tail when it had to move.
fn draw_names<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    d: &Drawing,
    p2: &dyn Fn(&Vector3<f64>) -> (f64, f64),
) -> Result<()> {
    let font = TextStyle::from(("sans-serif", NAME_PX).into_font());
    let base = area.get_base_pixel();
    // Pixels of this area (the backend's, shifted to the area's corner).
    let px = |p: &Vector3<f64>| {
        let (x, y) = chart.backend_coord(&p2(p));
        (f64::from(x - base.0), f64::from(y - base.1))
    };
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let bounds = LabelBox {
        x: f64::from(xs.start - base.0),
        y: f64::from(ys.start - base.1),
        w: f64::from(xs.end - xs.start),
        h: f64::from(ys.end - ys.start),
    };
    let mut names = Vec::new();
    for f in &d.solution.fingers {
        let (w, h) = area.estimate_text_size(&f.name, &font).map_err(plot_err)?;
        let size = (f64::from(w), f64::from(h));
        if let Some((tail, anchor)) = name_spot(d, f, &px, size) {
            names.push((f.name.as_str(), tail, anchor, size));
        }
    }
    let anchors: Vec<(f64, f64)> = names.iter().map(|n| n.2).collect();
    let sizes: Vec<(f64, f64)> = names.iter().map(|n| n.3).collect();
    // The contact points, the centre of mass and the arrows stay uncovered.
    let dot = |p: (f64, f64)| LabelBox {
        x: p.0 - 4.0,
        y: p.1 - 4.0,
        w: 8.0,
        h: 8.0,
    };
    let mut keep_clear: Vec<LabelBox> = d
        .model
        .fingers()
        .iter()
        .map(|m| dot(px(&m.frame().origin_m)))
        .collect();
    keep_clear.push(dot(px(&d.model.center_of_mass_m())));
    for (a, b) in arrow_segments(d, &px) {
        keep_clear.extend(segment_boxes(a, b));
    }
    let boxes = place_labels(&anchors, &sizes, bounds, 3.0, &keep_clear);
    for ((name, tail, anchor, _), b) in names.iter().zip(&boxes) {
        let centre = (b.x + b.w / 2.0, b.y + b.h / 2.0);
        if (centre.0 - anchor.0).hypot(centre.1 - anchor.1) > b.h {
            let edge = (tail.0.clamp(b.x, b.x + b.w), tail.1.clamp(b.y, b.y + b.h));
            let at = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
            area.draw(&PathElement::new(
                vec![at(*tail), at(edge)],
                RGBColor(150, 150, 150),
            ))
            .map_err(plot_err)?;
        }
        let corner = (b.x.round() as i32, b.y.round() as i32);
        area.draw(&Text::new(name.to_string(), corner, font.clone()))
            .map_err(plot_err)?;
    }
    Ok(())
}

/// Where finger `f`'s name goes, in pixels: its normal arrow's tail (its contact when
/// unloaded) and the centre of a box of `size` just beyond it, outward along the arrow (along
/// the normal when the arrow is too short to show a direction; to the right when the normal
/// points along the view).
fn name_spot(
    d: &Drawing,
    f: &grasp_model::FingerSolution,
    px: &dyn Fn(&Vector3<f64>) -> (f64, f64),
    (w, h): (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let m = d.model.fingers().iter().find(|m| m.name() == f.name)?;
    let (n, cop) = (m.frame().normal, Vector3::from(f.center_of_pressure_m));
    let head = px(&cop);
    let tail = px(&(cop - n * (f.normal_force_n * d.m_per_n)));
    let unit = |(x, y): (f64, f64)| {
        let len = x.hypot(y);
        (len > 2.0).then(|| (x / len, y / len))
    };
    let out = unit((tail.0 - head.0, tail.1 - head.1))
        .or_else(|| {
            let far = px(&(cop - n * d.cone_m));
            unit((far.0 - head.0, far.1 - head.1))
        })
        .unwrap_or((1.0, 0.0));
    // From the box's centre to its edge along `out`, and a gap of 4 px.
    let reach = (0.5 * w / out.0.abs().max(1e-9)).min(0.5 * h / out.1.abs().max(1e-9)) + 4.0;
    Some((tail, (tail.0 + out.0 * reach, tail.1 + out.1 * reach)))
}

/// The drawn arrows as pixel segments: each finger's normal and friction arrow (tail to head)
/// and the weight.
fn arrow_segments(
    d: &Drawing,
    px: &dyn Fn(&Vector3<f64>) -> (f64, f64),
) -> Vec<((f64, f64), (f64, f64))> {
    let mut segments = Vec::new();
    for f in &d.solution.fingers {
        if let Some(m) = d.model.fingers().iter().find(|m| m.name() == f.name) {
            let cop = Vector3::from(f.center_of_pressure_m);
            let normal = m.frame().normal * (f.normal_force_n * d.m_per_n);
            let friction = Vector3::from(f.tangential_force_n) * d.m_per_n;
            segments.push((px(&(cop - normal)), px(&cop)));
            segments.push((px(&(cop - friction)), px(&cop)));
        }
    }
    let com = d.model.center_of_mass_m();
    let o = &d.scene.object;
    if let Some(down) = Vector3::from(o.gravity).try_normalize(0.0) {
        segments.push((px(&com), px(&(com + down * (o.weight * d.m_per_n)))));
    }
    segments
}

/// Small boxes (4 px) every 3 px along the segment from `a` to `b`, pixels.
fn segment_boxes(a: (f64, f64), b: (f64, f64)) -> Vec<LabelBox> {
    let n = ((b.0 - a.0).hypot(b.1 - a.1) / 3.0).ceil().max(1.0) as usize;
    (0..=n)
        .map(|i| {
            let s = i as f64 / n as f64;
            LabelBox {
                x: a.0 + s * (b.0 - a.0) - 2.0,
                y: a.1 + s * (b.1 - a.1) - 2.0,
                w: 4.0,
                h: 4.0,
            }
        })
        .collect()
}

fn draw_weight<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    d: &Drawing,
    p2: &dyn Fn(&Vector3<f64>) -> (f64, f64),
) -> Result<()> {
    let com = d.model.center_of_mass_m();
    let o = &d.scene.object;
    let w = Vector3::from(o.gravity).normalize() * o.weight;
    chart
        .draw_series(std::iter::once(Circle::new(p2(&com), 4, BLACK.filled())))
        .map_err(plot_err)?;
    arrow(chart, p2(&com), p2(&(com + w * d.m_per_n)), &BLACK)
}

fn draw_finger<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    d: &Drawing,
    f: &grasp_model::FingerSolution,
    p2: &dyn Fn(&Vector3<f64>) -> (f64, f64),
) -> Result<()> {
    let Some(m) = d.model.fingers().iter().find(|m| m.name() == f.name) else {
        return Ok(());
    };
    let (n, cop) = (m.frame().normal, Vector3::from(f.center_of_pressure_m));
    cone(chart, d, &n, f.friction_coefficient, &cop, p2)?;
    let normal = n * f.normal_force_n * d.m_per_n;
    let friction = Vector3::from(f.tangential_force_n) * d.m_per_n;
    arrow(chart, p2(&(cop - normal)), p2(&cop), &NORMAL)?;
    arrow(chart, p2(&(cop - friction)), p2(&cop), &FRICTION)?;
    chart
        .draw_series(std::iter::once(Circle::new(
            p2(&m.frame().origin_m),
            3,
            BLACK.filled(),
        )))
        .map_err(plot_err)?;
    Ok(())
}

/// The friction cone's two edges in the view: lines from the contact outward (against the
/// push) at `atan(mu)` either side of the normal, in the plane of the normal and the view's
/// in-plane direction across it. Skipped when the normal points along the view.
fn cone<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    d: &Drawing,
    n: &Vector3<f64>,
    mu: f64,
    at: &Vector3<f64>,
    p2: &dyn Fn(&Vector3<f64>) -> (f64, f64),
) -> Result<()> {
    let (nu, nv) = {
        let (a, b) = p2(n);
        (a, b)
    };
    let len = (nu * nu + nv * nv).sqrt();
    if mu <= 0.0 || len < 0.3 {
        return Ok(());
    }
    let (cu, cv) = p2(at);
    let alpha = mu.atan();
    let edge = |s: f64| {
        let (c, si) = (alpha.cos(), s * alpha.sin());
        let (du, dv) = ((nu * c - nv * si) / len, (nv * c + nu * si) / len);
        vec![(cu, cv), (cu - du * d.cone_m, cv - dv * d.cone_m)]
    };
    for s in [-1.0, 1.0] {
        chart
            .draw_series(LineSeries::new(edge(s), RGBColor(120, 120, 120)))
            .map_err(plot_err)?;
    }
    Ok(())
}

/// An arrow from `tail` to `head` with a two-stroke head.
fn arrow<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    tail: (f64, f64),
    head: (f64, f64),
    color: &RGBColor,
) -> Result<()> {
    let (du, dv) = (head.0 - tail.0, head.1 - tail.1);
    let len = (du * du + dv * dv).sqrt();
    if len < 1e-12 {
        return Ok(());
    }
    let style = ShapeStyle::from(color).stroke_width(2);
    chart
        .draw_series(LineSeries::new(vec![tail, head], style))
        .map_err(plot_err)?;
    let (bu, bv) = (-du / len * 0.25 * len, -dv / len * 0.25 * len);
    for s in [-0.4, 0.4] {
        let wing = (head.0 + bu - s * bv, head.1 + bv + s * bu);
        chart
            .draw_series(LineSeries::new(vec![head, wing], style))
            .map_err(plot_err)?;
    }
    Ok(())
}

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise.
fn convex_hull(mut points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64)> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pictures::picture::{render, Format};
    use grasp_model::{GraspSolver, SolveOptions, StepInputs};
    use plotters_backend::BackendTextStyle;

    /// The force diagram of a bundled example, as SVG text.
    fn diagram_svg(name: &str) -> (String, Vec<String>) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples")
            .join(name);
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = grasp_io::scene_from_json_str(&text, &grasp_io::base_dir_of(&path)).unwrap();
        let model = GraspModel::from_loaded(&scene).unwrap();
        let solution = GraspSolver::new(model.clone(), SolveOptions::default())
            .solve(&StepInputs::of_scene(&model))
            .unwrap();
        let diagram = ForceDiagram {
            scene: &scene,
            model: &model,
            solution: &solution,
            title: name,
        };
        let svg = String::from_utf8(render(&diagram, Format::Svg).unwrap()).unwrap();
        let names = scene.finger_names();
        (svg, names)
    }

    /// The finger names as the SVG sets them, with their boxes measured in the font the
    /// pictures use: `(name, box)`, in drawing order.
    fn name_boxes(svg: &str, names: &[String]) -> Vec<(String, LabelBox)> {
        crate::pictures::font::use_shipped_font().unwrap();
        let font = TextStyle::from(("sans-serif", NAME_PX).into_font());
        let attr = |tag: &str, key: &str| -> f64 {
            let key = format!(" {key}=\"");
            let start = tag.find(&key).unwrap() + key.len();
            tag[start..].split('"').next().unwrap().parse().unwrap()
        };
        let lines: Vec<&str> = svg.lines().collect();
        let mut out = Vec::new();
        for (k, line) in lines.iter().enumerate() {
            let content = lines.get(k + 1).map_or("", |l| l.trim());
            if line.starts_with("<text") && names.iter().any(|n| n == content) {
                let ((x0, y0), (x1, y1)) = font.layout_box(content).unwrap();
                let b = LabelBox {
                    x: attr(line, "x"),
                    y: attr(line, "y"),
                    w: f64::from(x1 - x0),
                    h: f64::from(y1 - y0),
                };
                out.push((content.to_string(), b));
            }
        }
        out
    }

    /// The arrows as the SVG draws them (strokes of width 2 in the arrows' colours, shafts
    /// and heads): their segments, pixels.
    fn arrow_strokes(svg: &str) -> Vec<((f64, f64), (f64, f64))> {
        let stroke = |c: RGBColor| format!("stroke=\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2);
        let colours = [stroke(NORMAL), stroke(FRICTION), stroke(BLACK)];
        let mut out = Vec::new();
        for line in svg.lines().filter(|l| l.starts_with("<polyline")) {
            if !line.contains("stroke-width=\"2\"") || !colours.iter().any(|c| line.contains(c)) {
                continue;
            }
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
            out.extend(xy.windows(2).map(|w| (w[0], w[1])));
        }
        out
    }

    /// Whether the segment passes through the box's interior (sampled every 0.25 px).
    fn crosses(b: &LabelBox, (a, e): ((f64, f64), (f64, f64))) -> bool {
        let n = ((e.0 - a.0).hypot(e.1 - a.1) * 4.0).ceil().max(1.0) as usize;
        (0..=n).any(|i| {
            let s = i as f64 / n as f64;
            let (x, y) = (a.0 + s * (e.0 - a.0), a.1 + s * (e.1 - a.1));
            x > b.x && x < b.x + b.w && y > b.y && y < b.y + b.h
        })
    }

    /// Each finger's name sits clear of every arrow: none is written across a shaft (before,
    /// the mug's names lay on its arrows), and a loaded finger's name stays near its normal
    /// arrow's tail.
    #[test]
    fn finger_names_sit_clear_of_the_arrows() {
        for example in [
            "mug_power_grasp.json",
            "cube_a.json",
            "plate_four_fingers.json",
            "sphere_three_fingers.json",
            "cylinder_handoff.json",
        ] {
            let (svg, names) = diagram_svg(example);
            let strokes = arrow_strokes(&svg);
            assert!(!strokes.is_empty(), "{example}: no arrows found");
            for (name, b) in name_boxes(&svg, &names) {
                let hit = strokes.iter().find(|s| crosses(&b, **s));
                assert!(hit.is_none(), "{example}: `{name}` {b:?} lies on {hit:?}");
            }
        }
    }

    /// The mug's six fingers sit close together (before, "little" overprinted "ring" and
    /// "middle" "index"): in each view every name is set once and no two names' boxes
    /// share a pixel.
    #[test]
    fn finger_names_do_not_overlap() {
        for example in [
            "mug_power_grasp.json",
            "cube_a.json",
            "plate_four_fingers.json",
        ] {
            let (svg, names) = diagram_svg(example);
            let boxes = name_boxes(&svg, &names);
            assert_eq!(boxes.len(), 2 * names.len(), "{example}: {boxes:?}");
            // The left view ends at x = 550 px (ForceDiagram::draw's split).
            for left in [true, false] {
                let view: Vec<&(String, LabelBox)> = boxes
                    .iter()
                    .filter(|(_, b)| (b.x < 550.0) == left)
                    .collect();
                assert_eq!(view.len(), names.len(), "{example}: {view:?}");
                for i in 0..view.len() {
                    for j in i + 1..view.len() {
                        assert!(
                            !view[i].1.overlaps(&view[j].1),
                            "{example}: `{}` and `{}` overlap: {:?} {:?}",
                            view[i].0,
                            view[j].0,
                            view[i].1,
                            view[j].1
                        );
                    }
                }
            }
        }
    }
}
