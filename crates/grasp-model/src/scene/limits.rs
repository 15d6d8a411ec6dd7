//! The ranges a scene's numbers may take: physical ranges outside which an input is almost
//! surely in the wrong unit, the size limits of a patch, and the tolerance of the planarity
//! checks. Validation ([`super::scene_validation`], [`super::field_checks`]) and the shape checks ([`super::shape_checks`])
//! read them from here.

use std::ops::RangeInclusive;

/// Largest number of elements allowed in one patch (2048 x 2048). Patches above
/// [`AUTO_FFT_ABOVE_UNKNOWNS`] are solved with the FFT compliance operator unless the dense
/// matrix is asked for; the memory estimate of the path that runs
/// ([`super::memory_budget::estimate_memory_bytes_with`]), checked by the caller against the
/// machine, refuses what does not fit before this limit does.
pub const MAX_ELEMENTS_PER_PATCH: usize = 2048 * 2048;

/// Most elements along one side of a patch: the largest patch is 2048 x 2048, and a strip of
/// millions of elements one wide is no contact patch (its FFT grid alone runs for minutes).
pub const MAX_GRID_SIDE: usize = 2048;

/// A grid continuation's coarsest grid keeps at least this many elements a side: a cold solve
/// of a textured or frictional FFT patch whose sides are even and at least twice this starts
/// from its twin on a grid twice as coarse (`model/grid_coarsening.rs`,
/// `solver/grid_continuation.rs`), and that one from a coarser, down to this.
pub const MIN_COARSE_SIDE: usize = 32;

/// Patches with more unknowns than this (elements times `1 + n_tangential`: 32 x 32
/// frictionless, about 18 x 18 with friction in 3-D) take the FFT compliance operator when
/// the form is chosen automatically. Measured on the bundled scenes (`grasp solve`, 2 cores):
/// the FFT path is already faster at 1,024 frictionless unknowns (Hertz 32 x 32: 2 ms
/// against 16 ms dense) and level at 768 with friction (cube A 16 x 16: 50 ms against 61 ms),
/// then pulls away (cube A 28 x 28: 0.2 s against 1.1 s); up to here the dense path is a few
/// milliseconds and gives every analysis its matrix directly.
pub const AUTO_FFT_ABOVE_UNKNOWNS: usize = 1024;

/// A contact point farther from the centre of mass than this multiple of the median distance of
/// all contact points is taken as a unit mistake (millimetres written as metres, say).
pub const PLAUSIBLE_REACH_FACTOR: f64 = 100.0;

/// Physical range of Young's modulus, Pa (soft gels to beyond diamond); outside it the input is
/// almost surely in the wrong unit.
pub const MODULUS_RANGE_PA: RangeInclusive<f64> = 1.0..=1e15;

/// Physical range of the thickness of an elastic layer on a rigid core, m (a micrometre coating
/// to a metre-thick pad).
pub const LAYER_THICKNESS_RANGE_M: RangeInclusive<f64> = 1e-6..=1.0;

/// Range of a relaxation time, s (a microsecond to about 31 years, the schedules' longest
/// time).
pub const RELAXATION_TIME_RANGE_S: RangeInclusive<f64> = 1e-6..=1e9;

/// Most terms of a Prony series: measured laws use a handful (about one a decade of time),
/// and the stepping's cost grows with the square of their number.
pub const MAX_PRONY_TERMS: usize = 32;

/// Largest Poisson's ratio of a bonded layer, `0.5 - 1e-9`: nearer 0.5 the layer's
/// compliance is ill-conditioned past what the iterative solves resolve (a 0.1 mm coating at
/// `0.5 - 1e-14` took 18,413 conjugate-gradient iterations, 24 s, against 288 and 0.7 s at
/// this bound), while at the bound the layer is already incompressible for any patch under
/// ten thousand thicknesses (its compressibility length is about 12,900 thicknesses).
pub const MAX_LAYER_POISSON_RATIO: f64 = 0.5 - 1e-9;

/// Range of a prescribed approach, m: negative withdraws the finger (opens a jaw) from first
/// touch.
pub const APPROACH_RANGE_M: RangeInclusive<f64> = -1.0..=1.0;

/// Range of a mount's translational stiffness, N/m (`fingers[i].mount`): from a spring a
/// micronewton per micrometre would not load to a stiffness beyond any steel contact's.
pub const MOUNT_STIFFNESS_RANGE_N_PER_M: RangeInclusive<f64> = 1e-6..=1e15;

/// Range of a mount's rotational stiffness, N m/rad.
pub const MOUNT_ROTATIONAL_STIFFNESS_RANGE_NM_PER_RAD: RangeInclusive<f64> = 1e-9..=1e12;

/// Physical range of a patch side, m.
pub const PATCH_SIDE_RANGE_M: RangeInclusive<f64> = 1e-9..=10.0;

/// Largest force anywhere in a scene or schedule, N (weight, prescribed loads, each component
/// of an external force, friction-table loads): about the weight of a 1000 t object.
pub const MAX_FORCE_N: f64 = 1e7;

/// Smallest nonzero force, N: below it a load is no physical grasp (and its scale would
/// underflow the program's). Forces are 0 or in `[MIN_NONZERO_FORCE_N, MAX_FORCE_N]`.
pub const MIN_NONZERO_FORCE_N: f64 = 1e-15;

/// Smallest nonzero friction coefficient (0 is a frictionless finger).
pub const MIN_NONZERO_FRICTION_COEFFICIENT: f64 = 1e-6;

/// True for a force magnitude a grasp can have: 0, or in `[MIN_NONZERO_FORCE_N, MAX_FORCE_N]`.
pub fn force_in_range(x: f64) -> bool {
    x == 0.0 || (MIN_NONZERO_FORCE_N..=MAX_FORCE_N).contains(&x)
}

/// Largest absolute coordinate of a point (centre of mass, contact points, points of external
/// forces), m.
pub const MAX_COORDINATE_M: f64 = 1e3;

/// Most triangles of a mesh (an object's or a fingertip's). Preparing a mesh for its surface
/// queries takes about `mesh_budget::MESH_BYTES_PER_TRIANGLE` bytes and 2 µs a
/// triangle (parry's bounding-volume tree most of the memory): 2,000,000 triangles take
/// about 1.3 GB and a few seconds, where the largest mesh file (256 MiB of binary STL, 5.4
/// million triangles) took 3.5 GB. A finer mesh tells patches of millimetre elements nothing
/// more about the surface.
pub const MAX_MESH_TRIANGLES: usize = 2_000_000;

/// Range of a radius of curvature or an eq. (40) length, m (a radius above it is flat for any
/// patch: write `null`).
pub const LENGTH_RANGE_M: RangeInclusive<f64> = 1e-9..=1e3;

/// Largest friction coefficient (measured ones stay below about 5).
pub const MAX_FRICTION_COEFFICIENT: f64 = 1e3;

/// Largest memory the dense patch compliance blocks may take, bytes (the cone solver needs a
/// few times more: see [`super::memory_budget::estimate_memory_bytes`], which callers check against the
/// machine's memory).
pub const MAX_COMPLIANCE_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// Relative tolerance of the planarity checks (normalised directions, distances over the
/// scene's length scale).
pub const PLANAR_TOLERANCE: f64 = 1e-6;

/// Largest side of a random texture's generation grid, pixels (of `short / 8`): see
/// `geometry/random_surface.rs`. Its memory is counted in the solve's estimate
/// ([`crate::estimate_memory_bytes`]).
pub use crate::geometry::random_surface::MAX_GRID_SIDE as MAX_RANDOM_TEXTURE_GRID_SIDE;

/// Fewest elements per shortest texture wavelength (a ridge period along its direction, a
/// random surface's short wavelength): below two the elements cannot resolve it, and the
/// sampled texture aliases into a longer, false one.
pub const MIN_ELEMENTS_PER_TEXTURE_WAVELENGTH: f64 = 2.0;
