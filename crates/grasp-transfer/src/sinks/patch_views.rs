//! Each finger's contact patch seen flat in the Rerun recording, beside the 3-D view where a
//! patch is a few pixels at the default zoom: per step, per finger with at most
//! [`FLAT_VIEW_ELEMENTS`] elements,
//!
//! - `patches/<name>/pressure`: a `Tensor` of the element pressures in kPa, rows along `t2`
//!   (up), columns along `t1` (right), its colour scale fixed to `[0, the step's largest
//!   pressure of any finger]` so that the fingers' maps compare; the tensor view draws the
//!   colour bar with its values;
//! - `patches/<name>/state`: an RGB image of the element states, stick green, slip orange,
//!   separated grey (the 3-D view's colours), with the key at `patches/key`.
//!
//! A released finger's maps are cleared. The layout gives each finger its pair of views
//! ([`super::rerun_layout`]).

use grasp_model::{FingerModel, FingerSolution};
use rerun::datatypes::{TensorBuffer, TensorData};
use rerun::{Image, Tensor, TextDocument};

use super::colour_key::{state_rgb, FORCE_KEY, STATE_KEY};
use super::element_maps::raster;

/// Patches with more elements than this (256 x 256) get no flat views: their maps would add
/// 7 bytes an element a step to the recording, and the 3-D view shows them as images already.
pub const FLAT_VIEW_ELEMENTS: usize = 256 * 256;

/// True when finger `fm`'s patch has flat views.
pub fn has_flat_views(fm: &FingerModel) -> bool {
    fm.patch().len() <= FLAT_VIEW_ELEMENTS
}

/// The pressure map of finger `fm` (kPa), its colour scale `[0, p_max_pa]` (Pa).
pub fn pressure_tensor(fm: &FingerModel, f: &FingerSolution, p_max_pa: f64) -> Tensor {
    let (nx, ny) = (fm.patch().grid.nx, fm.patch().grid.ny);
    let kpa: Vec<f32> = f
        .elements
        .iter()
        .map(|e| (e.pressure_pa * 1e-3) as f32)
        .collect();
    let data = TensorData::new(
        vec![ny as u64, nx as u64],
        TensorBuffer::F32(raster(&kpa, nx, ny).into()),
    );
    Tensor::new(data)
        .with_dim_names(["t2", "t1"])
        .with_value_range([0.0, p_max_pa * 1e-3])
}

/// The state map of finger `fm`.
pub fn state_image(fm: &FingerModel, f: &FingerSolution) -> Image {
    let (nx, ny) = (fm.patch().grid.nx, fm.patch().grid.ny);
    let rgb: Vec<[u8; 3]> = f.elements.iter().map(|e| state_rgb(e.state)).collect();
    let bytes: Vec<u8> = raster(&rgb, nx, ny).into_iter().flatten().collect();
    Image::from_rgb24(bytes, [nx as u32, ny as u32])
}

/// The key of the state maps' colours (static, at `patches/key`).
pub fn state_key() -> TextDocument {
    TextDocument::from_markdown(format!(
        "**Patches, seen from the object.** Left of each pair: pressure in kPa (colour bar: \
         0 to the step's largest pressure of any finger). Right: element state, {STATE_KEY}. \
         `t1` points right, `t2` up. In the 3-D view the same state colours sit behind each \
         patch, and the arrows are {FORCE_KEY}."
    ))
}
