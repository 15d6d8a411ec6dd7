//! The contact maps of one solve (`grasp solve --plot`, SVG or PNG): one row per finger, titled
//! by its name, with its contact pressure over the patch (white at 0 to dark red at the peak,
//! a colour bar labelled in Pa, kPa or MPa from 0 to the peak) beside its contact state
//! (stick, slip, no contact; a frictionless finger's contact neither sticks nor slips and its
//! panel says so), the patch axes `x` along `t1`, `y` along `t2` in mm.
//!
//! One rectangle is drawn per element up to [`MAX_CELLS`] a side; a finer patch is drawn in
//! square blocks of elements so that at most [`MAX_CELLS`] a side remain (a 1024 x 1024 patch
//! in 16 x 16 blocks): a block's pressure is its largest (the peak stays on the map and at the
//! colour bar's top) and its state the one most of its elements have (on a tie slip, then
//! stick, then frictionless contact, then no contact). The picture's size thus stays bounded (at most about 0.7 MB
//! of SVG a finger) however fine the patch. Cells at zero pressure are the background's white
//! and not drawn on the pressure map.

use anyhow::Result;
use grasp_model::{ElementState, FingerSolution, ModelKind, Solution};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::pictures::picture::{draw_err, Picture};

/// Most cells drawn along a side of a patch.
pub const MAX_CELLS: usize = 64;

/// The state map's colours: stick, slip, no contact (separated or facing no surface), in
/// contact without friction.
pub const STICK_RGB: RGBColor = RGBColor(44, 160, 44);
pub const SLIP_RGB: RGBColor = RGBColor(214, 39, 40);
pub const NO_CONTACT_RGB: RGBColor = RGBColor(215, 215, 215);
pub const FRICTIONLESS_RGB: RGBColor = RGBColor(31, 119, 180);

/// Width of the picture, px.
const WIDTH_PX: u32 = 1000;
/// Height of the title band, px.
const HEAD_PX: u32 = 44;
/// Height of one finger's row, px.
const ROW_PX: u32 = 340;
/// Width of the column right of each map (colour bar, legend), px.
const SIDE_PX: u32 = 130;

/// What one finger's maps show: its patch and its solution.
pub struct FingerPatch<'a> {
    /// Side lengths `[Lx, Ly]` along `t1`, `t2`, m.
    pub size_m: [f64; 2],
    /// Elements `[nx, ny]` along `t1`, `t2`.
    pub grid: [usize; 2],
    /// True when the finger has no friction (`mu = 0` at every load).
    pub frictionless: bool,
    /// The finger's solution (its elements row-major, `k = i ny + j`).
    pub solution: &'a FingerSolution,
}

/// The contact maps of a solve.
pub struct ContactMaps<'a> {
    /// The solution's status, model and fingers.
    pub solution: &'a Solution,
    /// The contact law solved.
    pub model: ModelKind,
    /// Each finger's patch, in the solution's order.
    pub fingers: Vec<FingerPatch<'a>>,
    /// Title (the scene file's name).
    pub title: &'a str,
}

/// The state of a drawn cell.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CellState {
    Stick,
    Slip,
    NoContact,
    Frictionless,
}

impl CellState {
    fn of(s: ElementState) -> CellState {
        match s {
            ElementState::Stick => CellState::Stick,
            ElementState::Slip => CellState::Slip,
            ElementState::Separated | ElementState::OffSurface => CellState::NoContact,
            ElementState::Frictionless => CellState::Frictionless,
        }
    }

    fn colour(self) -> RGBColor {
        match self {
            CellState::Stick => STICK_RGB,
            CellState::Slip => SLIP_RGB,
            CellState::NoContact => NO_CONTACT_RGB,
            CellState::Frictionless => FRICTIONLESS_RGB,
        }
    }
}

/// One drawn cell: its extent in patch coordinates (mm), its largest pressure (Pa) and its
/// state.
struct Cell {
    x_mm: [f64; 2],
    y_mm: [f64; 2],
    pressure_pa: f64,
    state: CellState,
}

impl Picture for ContactMaps<'_> {
    fn size(&self) -> (u32, u32) {
        (
            WIDTH_PX,
            HEAD_PX + ROW_PX * self.fingers.len().max(1) as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(draw_err)?;
        let (head, body) = root.split_vertically(HEAD_PX);
        let title = format!(
            "Contact maps: {} ({}, {} model)",
            self.title,
            self.solution.status.as_str(),
            model_name(self.model)
        );
        head.draw(&Text::new(title, (16, 12), ("sans-serif", 17)))
            .map_err(draw_err)?;
        let rows = body.split_evenly((self.fingers.len().max(1), 1));
        for (finger, row) in self.fingers.iter().zip(&rows) {
            let cells = cells(finger);
            let (left, right) = row.split_horizontally(WIDTH_PX / 2);
            pressure_map(&left, finger, &cells)?;
            state_map(&right, finger, &cells, self.model)?;
        }
        Ok(())
    }
}

/// The model's name as scenes write it.
fn model_name(m: ModelKind) -> &'static str {
    match m {
        ModelKind::Energy => "energy",
        ModelKind::Coulomb => "coulomb",
    }
}

/// The cells drawn for `f`: its elements, or blocks of them on a patch finer than
/// [`MAX_CELLS`] a side (module doc).
fn cells(f: &FingerPatch) -> Vec<Cell> {
    let [nx, ny] = f.grid;
    let block = nx.max(ny).div_ceil(MAX_CELLS).max(1);
    let (bx, by) = (nx.div_ceil(block), ny.div_ceil(block));
    let (dx, dy) = (1e3 * f.size_m[0] / nx as f64, 1e3 * f.size_m[1] / ny as f64);
    // Per block: extent, largest pressure, and its elements' states counted.
    let mut acc: Vec<Option<(Cell, [usize; 4])>> = (0..bx * by).map(|_| None).collect();
    for e in &f.solution.elements {
        let [i, j] = e.index;
        let (x, y) = (1e3 * e.local_m[0], 1e3 * e.local_m[1]);
        let state = CellState::of(e.state);
        let slot = &mut acc[(i / block) * by + j / block];
        let (cell, counts) = slot.get_or_insert_with(|| {
            let cell = Cell {
                x_mm: [x - dx / 2.0, x + dx / 2.0],
                y_mm: [y - dy / 2.0, y + dy / 2.0],
                pressure_pa: e.pressure_pa,
                state,
            };
            (cell, [0; 4])
        });
        cell.x_mm = [
            cell.x_mm[0].min(x - dx / 2.0),
            cell.x_mm[1].max(x + dx / 2.0),
        ];
        cell.y_mm = [
            cell.y_mm[0].min(y - dy / 2.0),
            cell.y_mm[1].max(y + dy / 2.0),
        ];
        cell.pressure_pa = cell.pressure_pa.max(e.pressure_pa);
        counts[state as usize] += 1;
    }
    acc.into_iter()
        .flatten()
        .map(|(mut cell, counts)| {
            cell.state = most_frequent(counts);
            cell
        })
        .collect()
}

/// The state most elements of a block have (`counts` indexed by [`CellState`]); on a tie slip,
/// then stick, then frictionless contact, then no contact.
fn most_frequent(counts: [usize; 4]) -> CellState {
    let order = [
        CellState::Slip,
        CellState::Stick,
        CellState::Frictionless,
        CellState::NoContact,
    ];
    let mut best = order[0];
    for s in order {
        if counts[s as usize] > counts[best as usize] {
            best = s;
        }
    }
    best
}

/// The patch's extent in mm, padded so that a millimetre is as long across as up a map of
/// `w_px` by `h_px` pixels.
fn extent_mm(
    f: &FingerPatch,
    (w_px, h_px): (f64, f64),
) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let (lx, ly) = (1e3 * f.size_m[0], 1e3 * f.size_m[1]);
    let mm_per_px = (lx / w_px).max(ly / h_px);
    let (hx, hy) = (0.5 * mm_per_px * w_px, 0.5 * mm_per_px * h_px);
    // The patch is centred on its contact point (local coordinates about 0).
    (-hx..hx, -hy..hy)
}

/// A chart of the patch on `area`, captioned `caption`, with `right_px` left free on its right.
fn patch_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    f: &FingerPatch,
    caption: String,
    right_px: u32,
) -> Result<
    ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
> {
    let (w, h) = area.dim_in_pixel();
    // The plot area: the row less margins, labels, caption and the side column.
    let plot = (
        f64::from(w.saturating_sub(right_px + 10 + 56)).max(10.0),
        f64::from(h.saturating_sub(10 + 10 + 36 + 24)).max(10.0),
    );
    let (xr, yr) = extent_mm(f, plot);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(10)
        .margin_right(right_px)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d(xr, yr)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .x_desc("x along t1 [mm]")
        .y_desc("y along t2 [mm]")
        .disable_mesh()
        .draw()
        .map_err(draw_err)?;
    Ok(chart)
}

/// The finger's pressure map and its colour bar.
fn pressure_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    f: &FingerPatch,
    cells: &[Cell],
) -> Result<()> {
    let peak = f.solution.peak_pressure_pa.max(0.0);
    let caption = format!("{}: contact pressure", f.solution.name);
    let mut chart = patch_chart(area, f, caption, SIDE_PX)?;
    let drawn = cells.iter().filter(|c| c.pressure_pa > 0.0).map(|c| {
        let colour = pressure_colour(c.pressure_pa / peak.max(f64::MIN_POSITIVE));
        Rectangle::new(
            [(c.x_mm[0], c.y_mm[0]), (c.x_mm[1], c.y_mm[1])],
            colour.filled(),
        )
    });
    chart.draw_series(drawn).map_err(draw_err)?;
    outline(&mut chart, f)?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    colour_bar(area, (xs.end + 24, ys), peak)
}

/// The patch's outline.
fn outline<DB: DrawingBackend>(
    chart: &mut ChartContext<
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    f: &FingerPatch,
) -> Result<()> {
    let (hx, hy) = (0.5e3 * f.size_m[0], 0.5e3 * f.size_m[1]);
    let corners = vec![(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)];
    chart
        .draw_series(std::iter::once(PathElement::new(corners, BLACK)))
        .map_err(draw_err)?;
    Ok(())
}

/// Steps of the colour bar's gradient.
const BAR_STEPS: i32 = 50;

/// The colour bar at pixel column `x0` (of the whole row), from the plot area's bottom (0) to
/// its top (`peak_pa`), labelled at 0, half and the peak in the unit the peak reads best in.
fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x0, ys): (i32, std::ops::Range<i32>),
    peak_pa: f64,
) -> Result<()> {
    let base = area.get_base_pixel();
    let (x0, top, bottom) = (x0 - base.0, ys.start - base.1, ys.end - base.1);
    let height = bottom - top;
    for k in 0..BAR_STEPS {
        let y1 = bottom - height * k / BAR_STEPS;
        let y0 = bottom - height * (k + 1) / BAR_STEPS;
        let colour = pressure_colour((f64::from(k) + 0.5) / f64::from(BAR_STEPS));
        area.draw(&Rectangle::new([(x0, y0), (x0 + 16, y1)], colour.filled()))
            .map_err(draw_err)?;
    }
    area.draw(&Rectangle::new([(x0, top), (x0 + 16, bottom)], BLACK))
        .map_err(draw_err)?;
    let (scale, unit) = pressure_unit(peak_pa);
    let font = ("sans-serif", 12).into_font();
    let left = TextStyle::from(font).pos(Pos::new(HPos::Left, VPos::Center));
    let labels = [
        (bottom, "0".to_owned()),
        (top + height / 2, significant5(0.5 * peak_pa / scale)),
        (
            top,
            format!("{} {unit} (peak)", significant5(peak_pa / scale)),
        ),
    ];
    for (y, text) in labels {
        area.draw(&Text::new(text, (x0 + 20, y), left.clone()))
            .map_err(draw_err)?;
    }
    let caption =
        TextStyle::from(("sans-serif", 12).into_font()).pos(Pos::new(HPos::Left, VPos::Bottom));
    area.draw(&Text::new(
        format!("pressure [{unit}]"),
        (x0, top - 12),
        caption,
    ))
    .map_err(draw_err)?;
    Ok(())
}

/// The unit a pressure of `pa` reads best in: its size in pascals and its name.
pub fn pressure_unit(pa: f64) -> (f64, &'static str) {
    match pa.abs() {
        p if p >= 1e6 => (1e6, "MPa"),
        p if p >= 1e3 => (1e3, "kPa"),
        _ => (1.0, "Pa"),
    }
}

/// `v` to five significant digits, fixed point (`73.996`, `0.12346`, `1234.6`).
pub fn significant5(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return "0".to_owned();
    }
    let digits = (4 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{v:.digits$}")
}

/// The colour of a pressure `s` of the peak (0 white, 1 dark red: white, yellow, orange, red,
/// dark red in equal steps).
fn pressure_colour(s: f64) -> RGBColor {
    const STOPS: [[f64; 3]; 5] = [
        [255.0, 255.0, 255.0],
        [254.0, 217.0, 118.0],
        [253.0, 141.0, 60.0],
        [227.0, 26.0, 28.0],
        [128.0, 0.0, 38.0],
    ];
    let s = s.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (s.floor() as usize).min(STOPS.len() - 2);
    let t = s - k as f64;
    let c = |n: usize| (STOPS[k][n] + t * (STOPS[k + 1][n] - STOPS[k][n])).round() as u8;
    RGBColor(c(0), c(1), c(2))
}

/// The finger's state map and its legend; a frictionless finger's says it has no stick or
/// slip.
fn state_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    f: &FingerPatch,
    cells: &[Cell],
    model: ModelKind,
) -> Result<()> {
    let caption = format!(
        "{}: contact state ({} model)",
        f.solution.name,
        model_name(model)
    );
    let mut chart = patch_chart(area, f, caption, SIDE_PX)?;
    let drawn = cells.iter().map(|c| {
        Rectangle::new(
            [(c.x_mm[0], c.y_mm[0]), (c.x_mm[1], c.y_mm[1])],
            c.state.colour().filled(),
        )
    });
    chart.draw_series(drawn).map_err(draw_err)?;
    outline(&mut chart, f)?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let entries: &[(CellState, &str)] = match f.frictionless {
        true => &[
            (CellState::Frictionless, "in contact"),
            (CellState::NoContact, "no contact"),
        ],
        false => &[
            (CellState::Stick, "stick"),
            (CellState::Slip, "slip"),
            (CellState::NoContact, "no contact"),
        ],
    };
    let base = area.get_base_pixel();
    let (x0, y0) = (xs.end + 16 - base.0, ys.start - base.1);
    let font =
        TextStyle::from(("sans-serif", 12).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (k, (state, label)) in entries.iter().enumerate() {
        let y = y0 + 8 + 18 * k as i32;
        // A circle, so that the map's cells are its only rectangles of these colours.
        area.draw(&Circle::new((x0 + 6, y), 6, state.colour().filled()))
            .map_err(draw_err)?;
        area.draw(&Text::new(label.to_string(), (x0 + 18, y), font.clone()))
            .map_err(draw_err)?;
    }
    if f.frictionless {
        let note = ["frictionless (mu = 0):", "no stick or slip"];
        for (k, line) in note.iter().enumerate() {
            let y = y0 + 8 + 18 * (entries.len() as i32 + 1 + k as i32);
            area.draw(&Text::new(line.to_string(), (x0, y), font.clone()))
                .map_err(draw_err)?;
        }
    }
    Ok(())
}
