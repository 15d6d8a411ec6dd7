//! Pictures drawn with plotters and written as SVG or PNG, chosen by the output file's
//! extension. Text is set in a subset of DejaVu Sans shipped with the crate
//! (`assets/fonts`, made by `scripts/make-font.sh`), so a PNG looks the same on every machine
//! and needs no system fonts; SVG text names the `sans-serif` family and is measured with the
//! same font.

use std::path::Path;

use anyhow::{anyhow, bail, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::bitmap_text::BaselineText;
use super::font::use_shipped_font;

/// A file format for pictures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Svg,
    Png,
}

impl Format {
    /// The format named by `path`'s extension; `option` names the command-line option in the
    /// error (e.g. `--out`).
    pub fn of(path: &Path, option: &str) -> Result<Format> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_lowercase);
        match ext.as_deref() {
            Some("svg") => Ok(Format::Svg),
            Some("png") => Ok(Format::Png),
            _ => bail!(
                "{option} {}: give a file ending in .svg or .png",
                path.display()
            ),
        }
    }
}

/// Something plotters can draw onto any backend.
pub trait Picture {
    /// Width and height, pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the picture on `root` (the whole canvas).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// The picture encoded as `format` (SVG text, or an 8-bit RGB PNG whose text sits on one
/// baseline: [`BaselineText`]).
pub fn render(picture: &impl Picture, format: Format) -> Result<Vec<u8>> {
    use_shipped_font()?;
    let (w, h) = picture.size();
    match format {
        Format::Svg => {
            let mut out = String::new();
            {
                let root = SVGBackend::with_string(&mut out, (w, h)).into_drawing_area();
                picture.draw(&root)?;
                root.present().map_err(draw_err)?;
            }
            Ok(out.into_bytes())
        }
        Format::Png => {
            let mut rgb = vec![0u8; w as usize * h as usize * 3];
            {
                let bitmap = BitMapBackend::with_buffer(&mut rgb, (w, h));
                let root = BaselineText(bitmap).into_drawing_area();
                picture.draw(&root)?;
                root.present().map_err(draw_err)?;
            }
            encode_png(&rgb, (w, h))
        }
    }
}

/// A drawing error as an `anyhow` error.
pub fn draw_err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("drawing the picture: {e}")
}

/// PNG bytes of an RGB buffer, row by row from the top.
pub fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| anyhow!("PNG: {e}"))?;
        writer
            .write_image_data(rgb)
            .map_err(|e| anyhow!("PNG: {e}"))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Square;

    impl Picture for Square {
        fn size(&self) -> (u32, u32) {
            (40, 30)
        }
        fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
            root.fill(&WHITE).map_err(draw_err)?;
            let red = ShapeStyle::from(&RED).filled();
            root.draw(&Rectangle::new([(10, 10), (20, 20)], red))
                .map_err(draw_err)?;
            root.draw(&Text::new("Pμ", (22, 2), ("sans-serif", 12).into_font()))
                .map_err(draw_err)
        }
    }

    #[test]
    fn the_format_follows_the_extension_and_others_are_refused() {
        assert_eq!(
            Format::of(Path::new("a/b.SVG"), "--out").unwrap(),
            Format::Svg
        );
        assert_eq!(
            Format::of(Path::new("b.png"), "--out").unwrap(),
            Format::Png
        );
        let e = Format::of(Path::new("b.pdf"), "--plot")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--plot b.pdf") && e.contains(".svg or .png"),
            "{e}"
        );
    }

    #[test]
    fn a_png_holds_the_pixels_that_were_drawn() {
        let bytes = render(&Square, Format::Png).unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (40, 30));
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let px = |x: usize, y: usize| &buf[(y * 40 + x) * 3..(y * 40 + x) * 3 + 3];
        assert_eq!(px(15, 15), [255, 0, 0], "inside the square");
        assert_eq!(px(5, 25), [255, 255, 255], "background");
        // The text was set in the shipped font: some pixels right of the square are dark.
        let inked = (22..40)
            .flat_map(|x| (2..16).map(move |y| (x, y)))
            .filter(|&(x, y)| px(x, y)[0] < 128)
            .count();
        assert!(inked > 5, "text drew {inked} dark pixels");
    }
}
