//! The height map of a gel image: at each pixel's centre the normal displacement of the pad's
//! surface relative to the finger's core, m, positive into the pad (toward the camera), under
//! the finger's solved element forces, each a uniform traction over its element.
//!
//! It is a marker's normal reading at every pixel (`super::marker_readings`: the exact
//! rectangle integrals of Boussinesq's and Cerruti's surface displacements, Johnson eqs.
//! 3.22c and 3.86a-c, with the finger's `E`, `nu` alone and the object rigid), read one of
//! two ways:
//! - **on the element lattice** (the image unturned, its pixel pitch the elements', its
//!   pixels on element centres, and the lattice's kernel table less work than the dense sum:
//!   `GelSpec::lattice`): the displacement at every lattice point
//!   is a 2-D convolution of the element forces with the kernel table of the lattice, one
//!   product of the FFT compliance operator (`crate::model::compliance_operator`) on the
//!   lattice that holds the patch and the image together; `O(L log L)` for `L` points;
//! - **densely** otherwise: per pixel, the sum over the loaded elements.
//!
//! Both read the same rectangle integrals, so they agree to round-off
//! (tests/gel_images.rs). Inside the contact a pixel on an element centre reads the
//! indenter's profile minus the approach (compatibility, thesis eq. 7 with the gap closed).

use rayon::prelude::*;

use crate::error::OutOfMemory;
use crate::model::compliance_operator::ComplianceOperator;
use crate::model::influence::{BlockKernels, GridSpec, KernelTable, PairConstants};
use crate::model::material::Material;
use crate::scene::gel_spec::{GelSpec, Lattice};
use crate::scene::sensor_kind::SensorKind;
use crate::sensors::marker_readings::{loaded_elements, surface_displacement};
use crate::solve::solution::ElementSolution;

/// How a height map was read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeightPath {
    /// One FFT convolution on the element lattice.
    Lattice,
    /// Per pixel, the sum over the loaded elements.
    Dense,
    /// Nothing to read: a rigid finger or no loaded element (every pixel 0).
    Flat,
}

/// The height map of `spec`'s pixels (row-major, `k = i ny + j`), m, over a finger of material
/// `finger` with solved `elements` on the element grid `patch`, and how it was read;
/// [`OutOfMemory`] when the lattice's spectra cannot be allocated.
pub fn height_map(
    spec: &GelSpec,
    finger: &Material,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> Result<(Vec<f64>, HeightPath), OutOfMemory> {
    let loaded = loaded_elements(elements);
    if matches!(finger, Material::Rigid) || loaded.is_empty() {
        return Ok((vec![0.0; spec.pixel_count()], HeightPath::Flat));
    }
    let pair = PairConstants::new(finger, &Material::Rigid);
    if let Some(lattice) = spec.lattice(&patch.element_grid()) {
        let depth = on_lattice(spec, &lattice, &pair, patch, &loaded)?;
        return Ok((depth, HeightPath::Lattice));
    }
    let kernels = BlockKernels::new(patch, &pair);
    let depth = spec
        .layout()
        .points_m()
        .par_iter()
        .map(|p| surface_displacement(*p, &kernels, patch, &loaded)[0])
        .collect();
    Ok((depth, HeightPath::Dense))
}

/// The height map read on `lattice`: the loaded elements' forces placed on it, one product
/// of the lattice's compliance (the finger's half-space against a rigid object), the pixels'
/// points picked out.
fn on_lattice(
    spec: &GelSpec,
    lattice: &Lattice,
    pair: &PairConstants,
    patch: &GridSpec,
    loaded: &[&ElementSolution],
) -> Result<Vec<f64>, OutOfMemory> {
    let grid = GridSpec {
        nx: lattice.size[0],
        ny: lattice.size[1],
        hx: patch.hx,
        hy: patch.hy,
    };
    let n = grid.len();
    let sheared = loaded.iter().any(|e| e.tangential_force_n != [0.0; 2]);
    let n_tangential = if sheared { 2 } else { 0 };
    let dim = 1 + n_tangential;
    let mut forces = crate::allocation::filled(dim * n, 0.0)?;
    for e in loaded {
        let k = grid.index(
            lattice.element0[0] + e.index[0],
            lattice.element0[1] + e.index[1],
        );
        for (c, f) in e.force_n().iter().take(dim).enumerate() {
            forces[c * n + k] = *f;
        }
    }
    let table = KernelTable::half_space(&grid, pair)?;
    let operator = ComplianceOperator::new(&table, n_tangential)?;
    let mut out = crate::allocation::filled(dim * n, 0.0)?;
    operator.apply(&forces, &mut out);
    let [px, py] = spec.image_px;
    let mut depth = Vec::with_capacity(px * py);
    for i in 0..px {
        let row = grid.index(lattice.pixel0[0] + i, lattice.pixel0[1]);
        depth.extend_from_slice(&out[row..row + py]);
    }
    Ok(depth)
}
