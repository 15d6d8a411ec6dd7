//! The font every picture's text is set in: a DejaVu Sans subset shipped with the CLI
//! (`assets/fonts`, made by `scripts/make-font.sh`), so no system font is needed.

use std::sync::OnceLock;

use anyhow::{bail, Result};
use plotters::style::FontStyle;

/// The shipped font (DejaVu Sans: Latin, Greek, punctuation, arrows, mathematical operators).
pub const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// Registers the shipped font as `sans-serif` (once per process; every call reports how that
/// went).
pub(super) fn use_shipped_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok()
    });
    match ok {
        true => Ok(()),
        false => bail!("the shipped font assets/fonts/DejaVuSans-subset.ttf cannot be read"),
    }
}
