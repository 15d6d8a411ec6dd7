//! A large patch's per-element fields as compact maps: one flat array per field instead of one
//! record per element, which is how the recordings carry patches of more than
//! [`COMPACT_ABOVE_ELEMENTS`] elements (MCAP: [`super::patch_maps_message`], Rerun:
//! [`super::rerun_grid_maps`]).
//!
//! Arrays are in element order `k = i ny + j` (`i` along `t1`, as the solution's elements), f32
//! for numbers (each value rounded to the nearest f32: within `2^-24` of its magnitude, values
//! below f32's smallest normal number `1.2e-38` to within that number) and u8 for the state
//! ([`state_code`]). [`raster`] reorders an array as an image with `t1` to the right and `t2` up.

use grasp_model::{ElementState, FingerSolution};

/// Patches with more elements than this (64 x 64) are recorded as compact maps; up to it every
/// element is its own record (MCAP JSON object, Rerun point), as before fine patches existed.
///
/// At 64 x 64 a patch's element records cost about 1 MB of JSON per step (about 250 bytes an
/// element) and a Rerun point cloud of 20 bytes an element; the maps cost 4 bytes an element
/// and field. Up to this size the readable records stay (every scene that recorded before
/// fine patches records byte for byte as before: the CLI refused larger patches then); it is
/// also the size above which `--compliance auto` takes the FFT operator.
pub const COMPACT_ABOVE_ELEMENTS: usize = 64 * 64;

/// Whether a patch of `elements` elements is recorded as compact maps.
pub fn is_compact(elements: usize) -> bool {
    elements > COMPACT_ABOVE_ELEMENTS
}

/// The state's code in the maps: 0 stick, 1 slip, 2 separated, 3 off the surface, 4 in
/// contact on a frictionless finger.
pub fn state_code(s: ElementState) -> u8 {
    match s {
        ElementState::Stick => 0,
        ElementState::Slip => 1,
        ElementState::Separated => 2,
        ElementState::OffSurface => 3,
        ElementState::Frictionless => 4,
    }
}

/// One finger's element fields as flat arrays in element order (`k = i ny + j`); two-component
/// fields interleaved (`[t1 of k, t2 of k]` at `2k`, `2k + 1`).
#[derive(Debug, Clone, PartialEq)]
pub struct ElementMaps {
    /// Normal force `F_k`, N.
    pub normal_force_n: Vec<f32>,
    /// Mean pressure `F_k / A`, Pa.
    pub pressure_pa: Vec<f32>,
    /// Tangential force `G_k` along `[t1, t2]`, N, interleaved.
    pub tangential_force_n: Vec<f32>,
    /// Gap after loading, m.
    pub gap_m: Vec<f32>,
    /// Accumulated slip along `[t1, t2]`, m, interleaved.
    pub slip_m: Vec<f32>,
    /// This step's slip along `[t1, t2]`, m, interleaved.
    pub step_slip_m: Vec<f32>,
    /// [`state_code`] of each element.
    pub state: Vec<u8>,
}

impl ElementMaps {
    /// The maps of a finger's solution.
    pub fn of(f: &FingerSolution) -> Self {
        let pair = |v: [f64; 2]| [v[0] as f32, v[1] as f32];
        let e = &f.elements;
        ElementMaps {
            normal_force_n: e.iter().map(|e| e.normal_force_n as f32).collect(),
            pressure_pa: e.iter().map(|e| e.pressure_pa as f32).collect(),
            tangential_force_n: e.iter().flat_map(|e| pair(e.tangential_force_n)).collect(),
            gap_m: e.iter().map(|e| e.gap_m as f32).collect(),
            slip_m: e.iter().flat_map(|e| pair(e.slip_m)).collect(),
            step_slip_m: e.iter().flat_map(|e| pair(e.step_slip_m)).collect(),
            state: e.iter().map(|e| state_code(e.state)).collect(),
        }
    }
}

/// The bytes of `values`, each little-endian.
pub fn little_endian(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A per-element array (element order `k = i ny + j`, one value an element) as an image of
/// `nx` columns and `ny` rows, row-major from the top row: column `i` along `t1`, row
/// `ny - 1 - j` (so `t2` points up, and `t1`, `t2` and the image's normal are right-handed as
/// the finger's frame).
pub fn raster<T: Copy>(values: &[T], nx: usize, ny: usize) -> Vec<T> {
    let mut out = Vec::with_capacity(nx * ny);
    for row in 0..ny {
        let j = ny - 1 - row;
        out.extend((0..nx).map(|i| values[i * ny + j]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names of the state codes, by code.
    const STATE_NAMES: [&str; 5] = ["stick", "slip", "separated", "off_surface", "frictionless"];

    #[test]
    fn the_threshold_is_64_by_64_elements() {
        assert!(!is_compact(64 * 64));
        assert!(is_compact(64 * 64 + 1));
        assert!(!is_compact(27));
    }

    #[test]
    fn raster_puts_t1_right_and_t2_up() {
        // nx = 3 along t1, ny = 2 along t2: element k = i ny + j holds 10 i + j.
        let v: Vec<u32> = (0..3)
            .flat_map(|i| (0..2).map(move |j| 10 * i + j))
            .collect();
        // Top row is j = 1, bottom row j = 0; i grows to the right.
        assert_eq!(raster(&v, 3, 2), vec![1, 11, 21, 0, 10, 20]);
    }

    #[test]
    fn little_endian_bytes_read_back_with_from_le_bytes() {
        let v = [1.5_f32, -2.0e-7, 3.4e38];
        let b = little_endian(&v);
        assert_eq!(b.len(), 12);
        assert_eq!(&b[0..4], &[0x00, 0x00, 0xc0, 0x3f]); // 1.5 = 0x3fc00000
        let back: Vec<f32> = b
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(back, v);
    }

    #[test]
    fn state_codes_follow_their_names() {
        let all = [
            ElementState::Stick,
            ElementState::Slip,
            ElementState::Separated,
            ElementState::OffSurface,
            ElementState::Frictionless,
        ];
        for s in all {
            let name = serde_json::to_value(s).unwrap();
            assert_eq!(name, STATE_NAMES[state_code(s) as usize]);
        }
    }
}
