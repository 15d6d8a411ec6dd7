//! The font every picture's text is set in: a DejaVu Sans subset shipped with the CLI
//! (`assets/fonts`, made by `scripts/make-font.sh`), so no system font is needed.

/// The shipped font (DejaVu Sans: Latin, Greek, punctuation, arrows, mathematical operators).
pub const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");
