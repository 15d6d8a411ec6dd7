//! The memory budget of a solve, the one owner of every memory estimate and check of the
//! model crate: the memory a scene's solve needs, estimated from its unknowns before anything
//! is allocated (pure arithmetic; a front end compares it with its limit, `grasp_io`'s
//! `MemoryLimit`); the check of the dense compliance blocks against
//! [`MAX_COMPLIANCE_BYTES`] (validation's and the model builder's); and the checks that a
//! finger's compliance and a solve's working vectors can be allocated now
//! ([`crate::allocation::check_room`]), before they are.
//!
//! Finger `i` with `N_i` elements and `c_i` tangential components (0 for a frictionless finger,
//! 1 in a planar scene, 2 in 3-D) has `n_i = N_i (1 + c_i)` unknowns. A dense patch compliance
//! is an `n_i x n_i` block of `f64`, `B_i = 8 n_i^2` bytes, and the estimate is
//!
//! ```text
//!   dense:  (DENSE_COPIES + SPARSE_ALLOWANCE) * 8 n_i^2   bytes
//! ```
//!
//! The FFT operator keeps one spectrum of `2 nx_i (ny_i + 1)` complex numbers (16 bytes) per
//! kernel (`k_i` = 1, 3 or 6 for `c_i` = 0, 1, 2), an apply needs `c_i + 3` more, its
//! preconditioner keeps `k_i` spectra a quarter that size (and holds as many again while it is
//! built; an apply of it needs `c_i + 3` of them), the
//! conjugate-gradient solves keep [`FFT_VECTORS`] vectors of `n_i` numbers plus
//! [`FFT_VECTORS_PER_ROW`] per equality row (`m = 6 + fingers` at most: the columns `Et'` and
//! `M^-1 Et'`), and the build holds a table of 48 bytes per padded grid point:
//!
//! ```text
//!   fft:    FFT_SAFETY * (16 (k_i + c_i + 3 + (2 k_i + c_i + 3) / 4) 2 nx_i (ny_i + 1)
//!                         + 8 (FFT_VECTORS + FFT_VECTORS_PER_ROW m) n_i + 48 4 nx_i ny_i)   bytes
//! ```
//!
//! An FFT patch whose sides are even and at least `2 MIN_COARSE_SIDE`, in a scene with a
//! textured or frictional patch (a cold solve's grid continuation,
//! [`crate::scene::limits::MIN_COARSE_SIDE`]), keeps its
//! twins on grids twice, four times, ... as coarse, each with its own operator: their
//! estimates add at most a third, `(1/4 + 1/16 + ...)`, so its estimate is `4/3` of the above.
//!
//! A finger's texture adds its bytes ([`texture_bytes`]): `8 N_i` for the heights at the element
//! centres, plus a height map's `8 rows cols`, or a random surface's generation grid of
//! `G x G` pixels at [`crate::geometry::random_surface::BYTES_PER_PIXEL`] each while it is made
//! (`G` from [`crate::geometry::random_surface::grid_side`]).
//!
//! A finger's sensor adds its read-outs' bytes ([`sensor_bytes`]): a gel image's arrays
//! ([`GEL_PIXEL_BYTES`] a pixel) and, when it is read on the element lattice, the lattice's
//! kernel table, compliance spectra, forces and displacements (`48 4 + 32 (k + c + 3) + 16 (1 +
//! c)` bytes a lattice point, about 600 with friction); a taxel grid read on its lattice, its
//! nine spectra (`9 16 2 (Lx + 1) Ly` bytes) twice, kept and while built.
//!
//! In the dense estimate [`DENSE_COPIES`] counts the model's block, the assembled program's
//! copy and the factorisations of the solver, and [`SPARSE_ALLOWANCE`] (the same again) for the sparse
//! solver's fill-in and workspace. Every product saturates at `u64::MAX`, so absurd grids give
//! an absurd estimate rather than a wrapped small one. On the bundled examples the estimate lies
//! above the measured peak (`grasp study` reports it); the factors may be retuned.

use crate::allocation::check_room;
use crate::error::{InputProblem, OutOfMemory};
use crate::geometry::surface_texture::HeightGrid;
use crate::option_names;
use crate::scene::limits::{MAX_COMPLIANCE_BYTES, MIN_COARSE_SIDE};
use crate::scene::loaded_scene::LoadedScene;
use crate::scene::scene_format::{FingerSpec, Scene};
use crate::scene::scene_geometry::SceneGeometry;
use crate::scene::sensor_kind::ElementGrid;

/// Copies of each dense compliance block the model, the program and the factorisations hold.
pub const DENSE_COPIES: u64 = 4;

/// Allowance of the sparse solver (fill-in, workspace), in dense blocks: the same again.
pub const SPARSE_ALLOWANCE: u64 = DENSE_COPIES;

/// Bytes of one `f64`.
const F64_BYTES: u64 = 8;

/// Vectors of a finger's unknowns the FFT path keeps besides its equality columns (the
/// conjugate-gradient iterates, the Newton step's and the program's vectors).
pub const FFT_VECTORS: u64 = 48;

/// Vectors per equality row the FFT path keeps for a finger: `Et'` and `U = M^-1 Et'` in each
/// of the two cached reduced systems.
pub const FFT_VECTORS_PER_ROW: u64 = 4;

/// Bytes of the table of rectangle integrals per padded grid point, while the operator is
/// built (six `f64`).
const TABLE_BYTES: u64 = 48;

/// Safety factor of the FFT path's estimate (allocator slack, the model's other vectors).
pub const FFT_SAFETY: u64 = 2;

/// Bytes of one element's record in a solution (at least `size_of::<ElementSolution>()`, a
/// test of the solution checks it).
pub const ELEMENT_RECORD_BYTES: u64 = 192;

/// Bytes in a GiB, for messages.
const GIB: f64 = 1073741824.0;

/// Tangential unknowns per element of a finger: 0 frictionless, 1 planar, 2 in 3-D.
pub fn tangential_components(scene: &Scene, finger: &FingerSpec) -> u64 {
    finger.tangential_unknowns(scene.planar.is_some()) as u64
}

/// Unknowns of one finger, `n_i = N_i (1 + c_i)` (saturating).
pub fn finger_unknowns(scene: &Scene, finger: &FingerSpec) -> u64 {
    let elements = (finger.patch.grid[0] as u64).saturating_mul(finger.patch.grid[1] as u64);
    elements.saturating_mul(1 + tangential_components(scene, finger))
}

/// Bytes of the dense compliance blocks of every finger, `sum_i 8 n_i^2` (saturating).
#[cfg(test)]
pub fn compliance_bytes(scene: &Scene) -> u64 {
    compliance_bytes_of(scene, |_| true)
}

/// Bytes of the dense compliance blocks of the fingers for which `dense` is true (saturating).
pub fn compliance_bytes_of(scene: &Scene, dense: impl Fn(&FingerSpec) -> bool) -> u64 {
    scene
        .fingers
        .iter()
        .filter(|f| dense(f))
        .map(|f| dense_block_bytes(finger_unknowns(scene, f)))
        .fold(0, u64::saturating_add)
}

/// Estimated peak memory of a solve of the scene with every patch dense, bytes (see the
/// module documentation; a height map counts when it was read).
pub fn estimate_memory_bytes(scene: &LoadedScene) -> u64 {
    estimate_memory_bytes_with(scene, |_| false)
}

/// Estimated peak memory of a solve of the scene, bytes, with the patches for which `fft`
/// is true taking the FFT operator and the others the dense matrix (see the module
/// documentation; a height map counts when it was read).
pub fn estimate_memory_bytes_with(scene: &LoadedScene, fft: impl Fn(&FingerSpec) -> bool) -> u64 {
    estimate_bytes_of(scene, &scene.geometry, fft)
}

/// [`estimate_memory_bytes_with`] of a scene and what reading it found (its height maps).
fn estimate_bytes_of(
    scene: &Scene,
    geometry: &SceneGeometry,
    fft: impl Fn(&FingerSpec) -> bool,
) -> u64 {
    scene
        .fingers
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let solve = match fft(f) {
                true => fft_bytes(scene, f),
                false => {
                    let n = finger_unknowns(scene, f);
                    n.saturating_mul(n)
                        .saturating_mul(F64_BYTES)
                        .saturating_mul(DENSE_COPIES + SPARSE_ALLOWANCE)
                }
            };
            solve
                .saturating_add(texture_bytes(f, geometry.height_map(i)))
                .saturating_add(sensor_bytes(scene, f))
        })
        .fold(0, u64::saturating_add)
}

/// Bytes of a finger's texture (0 without one; saturating): the heights at its element
/// centres, and a height map's heights (`map`, when its texture is one and they were read) or
/// a random surface's generation grid (see the module documentation). A random surface whose
/// grid cannot be counted counts as `u64::MAX` (validation refuses it).
pub fn texture_bytes(finger: &FingerSpec, map: Option<&HeightGrid>) -> u64 {
    let Some(t) = &finger.texture else { return 0 };
    let elements = (finger.patch.grid[0] as u64).saturating_mul(finger.patch.grid[1] as u64);
    let source = if let Some(map) = map.filter(|_| t.heights.is_some()) {
        (map.heights_m.len() as u64).saturating_mul(F64_BYTES)
    } else if let Some(r) = &t.random {
        crate::geometry::random_surface::grid_side(&r.surface(), finger.patch.size).map_or(
            u64::MAX,
            |g| {
                (g as u64)
                    .saturating_mul(g as u64)
                    .saturating_mul(crate::geometry::random_surface::BYTES_PER_PIXEL)
            },
        )
    } else {
        0
    };
    elements.saturating_mul(F64_BYTES).saturating_add(source)
}

/// The size of a solve's work: the program's unknowns, its equality rows and the elements of
/// its patches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolveSize {
    /// Unknowns of the program.
    pub unknowns: usize,
    /// Equality rows (equilibrium, and a load row per finger at most).
    pub equality_rows: usize,
    /// Elements of every patch.
    pub elements: usize,
}

impl SolveSize {
    /// Bytes a solve works in besides its model: the conjugate-gradient and Newton vectors of
    /// the unknowns and the equality columns (`8 (FFT_VECTORS + FFT_VECTORS_PER_ROW m)` per
    /// unknown, as [`estimate_memory_bytes_with`] counts them) and the solution's element
    /// records (`ELEMENT_RECORD_BYTES`, 192, each).
    pub fn bytes(&self) -> u64 {
        let vectors = F64_BYTES * (FFT_VECTORS + FFT_VECTORS_PER_ROW * self.equality_rows as u64);
        (self.unknowns as u64).saturating_mul(vectors) + self.elements as u64 * ELEMENT_RECORD_BYTES
    }

    /// Checks that a solve's working vectors and its solution can be allocated now (they
    /// are, ordinarily), or what they need.
    pub(crate) fn check_room(&self) -> Result<(), OutOfMemory> {
        check_room(self.bytes(), || {
            format!(
                "the solve's working vectors and its solution ({} unknowns)",
                self.unknowns
            )
        })
    }
}

/// Bytes of the table of rectangle integrals of a patch of `nx x ny` elements, held while its
/// compliance is built (six `f64` per point of the `(2 nx - 1) x (2 ny - 1)` grid of offsets).
pub fn kernel_table_bytes(nx: usize, ny: usize) -> u64 {
    TABLE_BYTES * (2 * nx as u64 - 1) * (2 * ny as u64 - 1)
}

/// Bytes of a dense compliance block of `unknowns` unknowns, `8 n^2` (saturating).
pub fn dense_block_bytes(unknowns: u64) -> u64 {
    unknowns.saturating_mul(unknowns).saturating_mul(F64_BYTES)
}

/// The problem of a scene whose dense compliance blocks (of the fingers `dense` picks) would
/// exceed [`MAX_COMPLIANCE_BYTES`], with the whole solve's estimate (the fingers not picked on
/// the FFT path; the height maps of `geometry`); `None` when they fit. Validation checks the
/// automatic choice, the model builder the caller's.
pub fn dense_blocks_problem(
    scene: &Scene,
    geometry: &SceneGeometry,
    dense: impl Fn(&FingerSpec) -> bool,
) -> Option<InputProblem> {
    let bytes = compliance_bytes_of(scene, &dense) as f64;
    if bytes <= MAX_COMPLIANCE_BYTES {
        return None;
    }
    let whole = estimate_bytes_of(scene, geometry, |f| !dense(f)) as f64;
    Some(InputProblem {
        path: "fingers".into(),
        message: format!(
            "a solve needs an estimated {:.1} GiB of memory, its dense patch compliance blocks \
             alone {:.1} GiB, more than the {:.0} GiB allowed them",
            whole / GIB,
            bytes / GIB,
            MAX_COMPLIANCE_BYTES / GIB
        ),
        fix: format!(
            "set `{}` to auto or fft, or use coarser grids",
            option_names::COMPLIANCE
        ),
    })
}

/// What building one finger's patch compliance holds: the compliance it keeps (its dense
/// matrix or its FFT operator's spectra) and, while it is built, the kernel table of its grid.
pub(crate) struct ComplianceBuild<'a> {
    /// The finger's index in the scene.
    pub finger: usize,
    /// Its name.
    pub name: &'a str,
    /// Its grid, elements along `t1`, `t2`.
    pub grid: [usize; 2],
    /// What the compliance keeps ("compliance matrix", "influence spectra").
    pub kept: &'a str,
    /// Bytes it keeps.
    pub kept_bytes: u64,
}

impl ComplianceBuild<'_> {
    /// Bytes the build holds at most.
    pub fn bytes(&self) -> u64 {
        let [nx, ny] = self.grid;
        kernel_table_bytes(nx, ny) + self.kept_bytes
    }

    /// An allocation of the build refused: named for the finger's grid and what it builds.
    pub fn refused(&self, e: OutOfMemory) -> crate::error::SceneError {
        let [nx, ny] = self.grid;
        crate::error::SceneError::OutOfMemory {
            path: format!("fingers[{}].patch.grid", self.finger),
            source: e.named(
                format!("the {nx} x {ny} {} of finger `{}`", self.kept, self.name),
                self.bytes(),
            ),
        }
    }

    /// Checks that the build can be allocated now.
    pub fn check_room(&self) -> Result<(), crate::error::SceneError> {
        check_room(self.bytes(), String::new).map_err(|e| self.refused(e))
    }
}

/// Bytes a finger's patch holds per element at most while its model is built: the element
/// centres (16) and gaps (8), the exact gaps' working copies and flags, and a texture's heights
/// and the gaps they change (8 each), rounded up.
pub const PATCH_BYTES_PER_ELEMENT: u64 = 128;

/// Checks that finger `finger` (`name`)'s patch of `grid` elements (along `t1`, `t2`) can hold
/// its per-element buffers now ([`PATCH_BYTES_PER_ELEMENT`] each), before they are allocated:
/// the first allocations of a finger's model, made before its compliance's own check
/// ([`ComplianceBuild::check_room`]), which under an address-space limit aborted the process.
pub(crate) fn check_patch_room(
    finger: usize,
    name: &str,
    grid: [usize; 2],
) -> Result<(), crate::error::SceneError> {
    let [nx, ny] = grid;
    let bytes = (nx as u64)
        .saturating_mul(ny as u64)
        .saturating_mul(PATCH_BYTES_PER_ELEMENT);
    check_room(bytes, || {
        format!("the {nx} x {ny} patch (element centres and gaps) of finger `{name}`")
    })
    .map_err(|source| crate::error::SceneError::OutOfMemory {
        path: format!("fingers[{finger}].patch.grid"),
        source,
    })
}

/// Bytes of a gel image's pixel: its height (`f64`), normal and colour (three `f64` each) and
/// 8-bit colour.
pub const GEL_PIXEL_BYTES: u64 = 8 + 24 + 24 + 3;

/// Bytes of a finger's sensor read-outs (0 without a sensor; saturating): see the module
/// documentation.
pub fn sensor_bytes(scene: &Scene, f: &FingerSpec) -> u64 {
    let Some(sensor) = &f.sensor else { return 0 };
    let patch = ElementGrid::of_patch(f.patch.size, f.patch.grid);
    let mut bytes = 0u64;
    if let Some(g) = &sensor.gel {
        bytes = (g.pixel_count() as u64).saturating_mul(GEL_PIXEL_BYTES);
        if let Some(l) = g.lattice(&patch) {
            let c = if tangential_components(scene, f) > 0 {
                2
            } else {
                0
            };
            let kernels = [1, 3, 6][c as usize];
            let per_point = 4 * TABLE_BYTES + 32 * (kernels + c + 3) + 16 * (1 + c);
            let points = (l.size[0] as u64).saturating_mul(l.size[1] as u64);
            bytes = bytes.saturating_add(points.saturating_mul(per_point));
        }
    }
    if let Some(l) = sensor.taxels.as_ref().and_then(|t| t.lattice(&patch)) {
        let spectra = (2 * 9 * 16 * 2u64)
            .saturating_mul(l.size[0] as u64 + 1)
            .saturating_mul(l.size[1] as u64);
        bytes = bytes.saturating_add(spectra);
    }
    bytes
}

/// The FFT path's estimate for one finger, bytes (saturating).
fn fft_bytes(scene: &Scene, f: &FingerSpec) -> u64 {
    let (nx, ny) = (f.patch.grid[0] as u64, f.patch.grid[1] as u64);
    let spectrum = (2 * 16u64)
        .saturating_mul(nx)
        .saturating_mul(ny.saturating_add(1));
    let c = tangential_components(scene, f);
    // Kernels kept: nn; then 11 and n1; then 22, 12 and n2.
    let kernels = [1, 3, 6][c as usize];
    // The operator's spectra and an apply's; the preconditioner's (quarter-size: twice its
    // kernels while built, and an apply's).
    let spectra = spectrum
        .saturating_mul(kernels + c + 3)
        .saturating_add((spectrum / 4).saturating_mul(2 * kernels + c + 3));
    // Equality rows: 6 (3 planar) equilibrium rows, at most one load row per finger, and a
    // hand's 6 and a servo's 1 (`hands`, `servos`).
    let springs = 6 * scene.hands.len() + scene.servos.len();
    let rows = 6 + scene.fingers.len() as u64 + springs as u64;
    let per_unknown = F64_BYTES * (FFT_VECTORS + FFT_VECTORS_PER_ROW * rows);
    let vectors = finger_unknowns(scene, f).saturating_mul(per_unknown);
    let table = (4 * TABLE_BYTES).saturating_mul(nx).saturating_mul(ny);
    let fine = spectra
        .saturating_add(vectors)
        .saturating_add(table)
        .saturating_mul(FFT_SAFETY);
    match continued(scene, f) {
        true => fine.saturating_add(fine / 3),
        false => fine,
    }
}

/// True when a cold solve of the FFT patch `f` may keep coarser twins of its grid (module
/// docs): its sides allow them and some patch of the scene is textured or has friction.
fn continued(scene: &Scene, f: &FingerSpec) -> bool {
    let side = |n: usize| n.is_multiple_of(2) && n >= 2 * MIN_COARSE_SIDE;
    let rough_or_frictional =
        |g: &FingerSpec| g.texture.is_some() || tangential_components(scene, g) > 0;
    side(f.patch.grid[0]) && side(f.patch.grid[1]) && scene.fingers.iter().any(rough_or_frictional)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(grid: [usize; 2], mu: f64) -> LoadedScene {
        let text = format!(
            r#"{{"object": {{"weight": 1, "center_of_mass": [0, 0, 0], "material": "rigid"}},
               "fingers": [{{"name": "f", "contact_point": [0, 0, 0], "normal": [0, 0, 1],
               "material": {{"youngs_modulus": 1e6, "poisson_ratio": 0.3}},
               "patch": {{"size": [0.01, 0.01], "grid": [{}, {}]}}, "friction": {{"mu": {mu}}}}}]}}"#,
            grid[0], grid[1]
        );
        LoadedScene::of_plain(serde_json::from_str(&text).unwrap()).unwrap()
    }

    #[test]
    fn estimate_is_eight_dense_blocks_of_the_unknowns() {
        // 5 x 5 elements, 3 unknowns each: n = 75, block 8 * 75^2 = 45000 bytes.
        assert_eq!(compliance_bytes(&scene([5, 5], 0.4)), 45_000);
        assert_eq!(estimate_memory_bytes(&scene([5, 5], 0.4)), 8 * 45_000);
        // Frictionless: one unknown per element.
        assert_eq!(compliance_bytes(&scene([5, 5], 0.0)), 8 * 25 * 25);
    }

    #[test]
    fn a_64_by_64_patch_needs_about_ten_gigabytes() {
        let e = estimate_memory_bytes(&scene([64, 64], 0.4));
        assert_eq!(e, 8 * 8 * 12288 * 12288);
        assert_eq!(e, estimate_memory_bytes(&scene([4096, 1], 0.4)));
    }

    #[test]
    fn a_1024_by_1024_fft_patch_is_estimated_below_two_gigabytes() {
        // A frictionless 1024 x 1024 patch within 2 GB; with friction (three
        // unknowns an element) still far below the dense path's 8 (3 N)^2 8 bytes.
        let e = estimate_memory_bytes_with(&scene([1024, 1024], 0.0), |_| true);
        assert!(e < 2 << 30, "{e} bytes");
        for mu in [0.0, 0.4] {
            let e = estimate_memory_bytes_with(&scene([1024, 1024], mu), |_| true);
            assert!(e < estimate_memory_bytes(&scene([1024, 1024], mu)) / 1000);
        }
    }

    #[test]
    fn a_texture_adds_its_heights_and_its_generation_grid() {
        let plain = scene([8, 8], 0.4);
        let mut textured = plain.clone();
        // Short 10 um: pixels of 1.25 um; the 10 mm patch needs 8000 -> 8192 a side.
        textured.fingers[0].texture = Some(
            serde_json::from_str(
                r#"{"random": {"rms_m": 1e-6, "hurst": 0.8, "wavelengths_m": [1e-4, 1e-5]}}"#,
            )
            .unwrap(),
        );
        let grid = 8192u64 * 8192 * 24;
        assert_eq!(
            estimate_memory_bytes(&textured) - estimate_memory_bytes(&plain),
            8 * 64 + grid
        );
        assert_eq!(
            estimate_memory_bytes_with(&textured, |_| true)
                - estimate_memory_bytes_with(&plain, |_| true),
            8 * 64 + grid
        );
    }

    #[test]
    fn a_gel_image_adds_its_pixels_and_its_lattice() {
        let mut loaded = scene([256, 256], 0.5);
        let before = estimate_memory_bytes_with(&loaded, |_| true);
        // Pixels on element centres: read on the 256 x 256 lattice of patch and image.
        let gel = r#"{"gel": {"image_px": [256, 256], "field_of_view_m": [0.01, 0.01]}}"#;
        loaded.scene.fingers[0].sensor = Some(serde_json::from_str(gel).unwrap());
        let added = estimate_memory_bytes_with(&loaded, |_| true) - before;
        let points = 256 * 256;
        // Friction: six kernels, two tangential components.
        let per_point = 4 * 48 + 32 * (6 + 2 + 3) + 16 * 3;
        assert_eq!(added, points * GEL_PIXEL_BYTES + points * per_point);
        // A 2 x 2 image far from the centre is read pixel by pixel: its arrays alone.
        let small = r#"{"gel": {"image_px": [2, 2], "field_of_view_m": [1e-3, 1e-3]}}"#;
        loaded.scene.fingers[0].sensor = Some(serde_json::from_str(small).unwrap());
        let added = estimate_memory_bytes_with(&loaded, |_| true) - before;
        assert_eq!(added, 4 * GEL_PIXEL_BYTES);
    }

    #[test]
    fn absurd_grids_saturate_instead_of_wrapping() {
        assert_eq!(
            estimate_memory_bytes(&scene([usize::MAX, usize::MAX], 0.4)),
            u64::MAX
        );
    }
}
