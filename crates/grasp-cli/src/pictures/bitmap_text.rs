//! Text on a bitmap (PNG) set on one baseline. plotters 0.3.7 places each glyph of a bitmap
//! text at `trunc(size / 2 + top of the glyph)` pixels, and `trunc` rounds toward zero: at odd
//! font sizes a glyph that rises above that line (a digit) moves down half a pixel and one
//! that stays below it (a full stop, a comma) moves up, so "1.753" reads "1·753". This
//! backend sets text itself, every glyph at the same baseline (`size / 2` below the text's
//! top, as plotters has it, with ab_glyph's sub-pixel placement), in the shipped font; every
//! other drawing goes to the wrapped backend unchanged. SVG text is set by the viewer and
//! needs none of this.

use ab_glyph::{point, Font, FontRef, ScaleFont};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};

/// A backend that sets its text on one baseline (see the module documentation).
pub struct BaselineText<DB>(pub DB);

type Drawn<DB> = Result<(), DrawingErrorKind<<DB as DrawingBackend>::ErrorType>>;

impl<DB: DrawingBackend> DrawingBackend for BaselineText<DB> {
    type ErrorType = DB::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }
    fn ensure_prepared(&mut self) -> Drawn<DB> {
        self.0.ensure_prepared()
    }
    fn present(&mut self) -> Drawn<DB> {
        self.0.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Drawn<DB> {
        self.0.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(&mut self, a: BackendCoord, b: BackendCoord, s: &S) -> Drawn<DB> {
        self.0.draw_line(a, b, s)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Drawn<DB> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Drawn<DB> {
        self.0.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Drawn<DB> {
        self.0.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Drawn<DB> {
        self.0.fill_polygon(vert, style)
    }
    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> Drawn<DB> {
        self.0.blit_bitmap(pos, size, src)
    }
    fn estimate_text_size<T: BackendTextStyle>(
        &self,
        text: &str,
        style: &T,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        self.0.estimate_text_size(text, style)
    }

    /// `text` at `pos` as plotters lays it out (anchor, rotation), each glyph on the baseline.
    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Drawn<DB> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let font = FontRef::try_from_slice(super::font::FONT)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match anchor.v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let transform = style.transform();
        let (w, h) = self.get_size();
        let scaled = font.as_scaled(style.size() as f32);
        let baseline = style.size() as f32 / 2.0;
        let (mut pen, mut previous) = (0.0_f32, None);
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                pen += scaled.kern(p, id);
            }
            previous = Some(id);
            let glyph = id.with_scale_and_position(scaled.scale(), point(pen, baseline));
            pen += scaled.h_advance(id);
            let Some(outline) = scaled.outline_glyph(glyph) else {
                continue; // a space
            };
            let corner = outline.px_bounds().min;
            let mut pixels = Vec::new();
            outline.draw(|x, y, coverage| pixels.push((x, y, coverage)));
            for (x, y, coverage) in pixels {
                let x = corner.x as i32 + x as i32 + dx - min_x;
                let y = corner.y as i32 + y as i32 + dy - min_y;
                let (tx, ty) = transform.transform(x, y);
                let (px, py) = (pos.0 + tx, pos.1 + ty);
                if px >= 0 && py >= 0 && (px as u32) < w && (py as u32) < h {
                    let alpha = color.alpha * f64::from(coverage.min(1.0));
                    self.0
                        .draw_pixel((px, py), BackendColor { alpha, ..color })?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lowest row with any ink of each run of inked columns of a `w x h` grey buffer (a glyph
    /// standing on the baseline touches the row the baseline crosses, whatever its shape).
    fn bottoms(grey: &[u8], (w, h): (usize, usize)) -> Vec<usize> {
        let inked = |x: usize, y: usize| grey[y * w + x] < 255;
        let column_bottom = |x: usize| (0..h).rev().find(|&y| inked(x, y));
        let mut out = Vec::new();
        let mut run: Option<usize> = None;
        for x in 0..w {
            match (column_bottom(x), run) {
                (Some(b), Some(r)) => run = Some(r.max(b)),
                (Some(b), None) => run = Some(b),
                (None, Some(r)) => {
                    out.push(r);
                    run = None;
                }
                (None, None) => {}
            }
        }
        out.extend(run);
        out
    }

    /// "1 . 7" (spaced, so each glyph is its own run of inked columns) in black at `size` px
    /// on white, as grey levels.
    fn render(size: u32) -> (Vec<u8>, (usize, usize)) {
        crate::pictures::font::use_shipped_font().unwrap();
        let (w, h) = (80_usize, 40_usize);
        let mut rgb = vec![0u8; w * h * 3];
        {
            let backend = BaselineText(BitMapBackend::with_buffer(&mut rgb, (80, 40)));
            let root = backend.into_drawing_area();
            root.fill(&WHITE).unwrap();
            let font = ("sans-serif", size).into_font().color(&BLACK);
            root.draw(&Text::new("1 . 7", (4, 8), font)).unwrap();
            root.present().unwrap();
        }
        (rgb.chunks(3).map(|p| p[0]).collect(), (w, h))
    }

    /// The full stop stands on the digits' baseline at every size, odd ones included (where
    /// plotters' own bitmap text lifts it by a pixel).
    #[test]
    fn a_full_stop_sits_on_the_baseline_of_the_digits() {
        for size in 9..=20 {
            let (grey, dim) = render(size);
            let b = bottoms(&grey, dim);
            assert_eq!(b.len(), 3, "size {size}: three glyphs, got bottoms {b:?}");
            assert!(b[0] == b[1] && b[1] == b[2], "size {size}: bottoms {b:?}");
        }
    }
}
