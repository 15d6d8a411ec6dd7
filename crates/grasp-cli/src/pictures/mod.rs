//! Pictures drawn with plotters, written as SVG or PNG by the file's extension.

pub mod bitmap_text;
pub mod contact_maps;
pub mod font;
pub mod force_diagram;
pub mod force_history;
pub mod gel_picture;
pub mod label_placement;
pub mod legend;
pub mod margin_plot;
pub mod picture;
pub mod plan_margins;
