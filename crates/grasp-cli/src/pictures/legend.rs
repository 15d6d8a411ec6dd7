//! Legends beside the plot area, never over the data: the chart leaves a column on its right
//! ([`LEGEND_COLUMN_PX`], through `ChartBuilder::margin_right`) and the legend is drawn there,
//! on the whole picture's area, level with the plot area's top (plotters' own series labels
//! stay inside the plot area, over the curves).

use std::ops::Range;

use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::pictures::picture::draw_err;

/// Width of the column the legend takes right of the plot area, px.
pub const LEGEND_COLUMN_PX: u32 = 180;

/// Gap between the plot area and the legend, px.
const GAP_PX: i32 = 14;

/// Height of one entry, px.
const ROW_PX: i32 = 16;

/// How an entry's sample is drawn: a line, solid or dashed, with a marker (filled or
/// hollow) on it or none.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// The series' colour.
    pub color: RGBColor,
    /// A dashed line.
    pub dashed: bool,
    /// `Some(filled)`: a marker circle on the line.
    pub marker: Option<bool>,
}

/// Draws `entries` (label, sample) in a box in the column right of the plot area whose pixel
/// ranges are `plot` (`chart.plotting_area().get_pixel_range()`), on `root`, the whole
/// picture.
pub fn legend_beside<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: (Range<i32>, Range<i32>),
    entries: &[(String, Sample)],
) -> Result<()> {
    if entries.is_empty() {
        return Ok(());
    }
    let (x0, y0) = (plot.0.end + GAP_PX, plot.1.start);
    let width = LEGEND_COLUMN_PX as i32 - GAP_PX - 6;
    let corner = [
        (x0, y0),
        (x0 + width, y0 + ROW_PX * entries.len() as i32 + 8),
    ];
    root.draw(&Rectangle::new(corner, WHITE.filled()))
        .map_err(draw_err)?;
    root.draw(&Rectangle::new(corner, BLACK))
        .map_err(draw_err)?;
    for (i, (label, s)) in entries.iter().enumerate() {
        let y = y0 + 4 + ROW_PX * i as i32 + ROW_PX / 2;
        let style = ShapeStyle::from(&s.color).stroke_width(2);
        let pieces = if s.dashed {
            vec![(x0 + 6, x0 + 14), (x0 + 18, x0 + 26)]
        } else {
            vec![(x0 + 6, x0 + 26)]
        };
        for (a, b) in pieces {
            root.draw(&PathElement::new(vec![(a, y), (b, y)], style))
                .map_err(draw_err)?;
        }
        if let Some(filled) = s.marker {
            let marker = if filled { style.filled() } else { style };
            root.draw(&Circle::new((x0 + 16, y), 4, marker))
                .map_err(draw_err)?;
        }
        let font = ("sans-serif", 12).into_font();
        root.draw(&Text::new(label.clone(), (x0 + 34, y - 6), font))
            .map_err(draw_err)?;
    }
    Ok(())
}
