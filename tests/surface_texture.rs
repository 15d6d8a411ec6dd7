//! Texture heights under a patch (`fingers[i].texture`): a seeded random self-affine surface
//! has exactly its rms and the spectrum's slope, and the same heights for the same seed on any
//! thread count; a height map is interpolated bilinearly with its centre on the contact point,
//! read alike from `.npy` and `.csv`; ridges follow their cosine.

mod support;
use support::*;

use std::path::{Path, PathBuf};

use grasp_model::{
    random_surface, texture_heights_m, HeightGrid, HeightMapSpec, RandomSurfaceSpec, RidgesSpec,
    TextureSpec,
};
use npyz::WriterBuilder;
use rustfft::num_complex::Complex64;
use serde_json::json;

fn spec(hurst: f64, seed: u64) -> RandomSurfaceSpec {
    RandomSurfaceSpec {
        rms_m: 2e-6,
        hurst,
        wavelengths_m: [5e-5, 1e-6],
        seed,
    }
}

fn random(r: RandomSurfaceSpec) -> TextureSpec {
    TextureSpec {
        random: Some(r),
        ..TextureSpec::default()
    }
}

/// Element centres of a patch of `size` m and `grid` elements (row-major, as the model's).
fn centres(size: [f64; 2], grid: [usize; 2]) -> (Vec<[f64; 2]>, [f64; 2]) {
    let h = [size[0] / grid[0] as f64, size[1] / grid[1] as f64];
    let c = (0..grid[0] * grid[1])
        .map(|k| {
            let (i, j) = (k / grid[1], k % grid[1]);
            [
                (i as f64 + 0.5) * h[0] - 0.5 * size[0],
                (j as f64 + 0.5) * h[1] - 0.5 * size[1],
            ]
        })
        .collect();
    (c, h)
}

/// Sum of squares by Neumaier's compensated summation: independent of the generator's
/// row-by-row sums.
fn sum_of_squares(x: &[f64]) -> f64 {
    let (mut s, mut c) = (0.0_f64, 0.0_f64);
    for v in x {
        let y = v * v;
        let t = s + y;
        c += if s.abs() >= y {
            (s - t) + y
        } else {
            (y - t) + s
        };
        s = t;
    }
    s + c
}

#[test]
fn the_random_surface_has_exactly_its_rms() {
    // Scaled to rms_m, so equal to round-off: the relative error of a sum of 2^20 squares and
    // one scaling is far below 1e-12.
    for (hurst, seed) in [(0.3, 1), (0.8, 2), (1.0, 3)] {
        let s = random_surface(&spec(hurst, seed).surface(), [1e-4, 1e-4]).unwrap();
        let n = s.side * s.side;
        assert_eq!(s.heights_m.len(), n);
        let rms = (sum_of_squares(&s.heights_m) / n as f64).sqrt();
        assert!((rms / 2e-6 - 1.0).abs() < 1e-12, "H {hurst}: rms {rms}");
        // Zero mean (the q = 0 coefficient is zero): to round-off of the rms.
        let mean = s.heights_m.iter().sum::<f64>() / n as f64;
        assert!(mean.abs() < 1e-12 * 2e-6, "mean {mean}");
    }
}

/// The power `|H(k)|^2` of a square periodic grid at each wavevector (rustfft, forward),
/// with `|k|` in units of the grid's fundamental.
fn power_spectrum(heights: &[f64], n: usize) -> Vec<(f64, f64)> {
    let mut planner = rustfft::FftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let mut z: Vec<Complex64> = heights.iter().map(|h| Complex64::new(*h, 0.0)).collect();
    for row in z.chunks_exact_mut(n) {
        fft.process(row);
    }
    let mut col = vec![Complex64::new(0.0, 0.0); n];
    for j in 0..n {
        (0..n).for_each(|i| col[i] = z[i * n + j]);
        fft.process(&mut col);
        (0..n).for_each(|i| z[i * n + j] = col[i]);
    }
    let fold = |k: usize| {
        if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        }
    };
    (0..n * n)
        .map(|k| {
            let (a, b) = (fold(k / n), fold(k % n));
            ((a * a + b * b).sqrt(), z[k].norm_sqr())
        })
        .collect()
}

#[test]
fn the_spectrum_falls_like_q_to_the_minus_two_one_plus_h() {
    // long 50 um, short 1 um, pixels of 0.125 um, a 100 um patch: N = 1024; the fundamental is
    // 2 pi / 128 um, so q_L is at |k| = 2.56 and q_s at |k| = 128.
    for hurst in [0.3, 0.7, 1.0] {
        let s = random_surface(&spec(hurst, 11).surface(), [1e-4, 1e-4]).unwrap();
        let n = s.side;
        assert_eq!(n, 1024);
        let period = n as f64 * s.pixel_m;
        let (k_long, k_short) = (period / 5e-5, period / 1e-6);
        let power = power_spectrum(&s.heights_m, n);
        // Nothing above q_s: round-off only (1e-20 of the total).
        let total: f64 = power.iter().map(|p| p.1).sum();
        let above: f64 = power
            .iter()
            .filter(|p| p.0 > k_short * 1.001)
            .map(|p| p.1)
            .sum();
        assert!(
            above < 1e-20 * total,
            "H {hurst}: {above} of {total} above q_s"
        );
        // Radial averages in 16 bins of equal log width between 1.5 q_L and 0.9 q_s, then the
        // least-squares slope of log(power) against log(|k|).
        let (lo, hi) = ((1.5 * k_long).ln(), (0.9 * k_short).ln());
        let bins = 16;
        let mut acc = vec![(0.0, 0.0, 0usize); bins];
        for (k, p) in &power {
            let b = ((k.ln() - lo) / (hi - lo) * bins as f64).floor();
            if *k > 0.0 && b >= 0.0 && b < bins as f64 {
                let a = &mut acc[b as usize];
                *a = (a.0 + k.ln(), a.1 + p, a.2 + 1);
            }
        }
        let pts: Vec<(f64, f64)> = acc
            .iter()
            .map(|(lk, p, m)| (lk / *m as f64, (p / *m as f64).ln()))
            .collect();
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / bins as f64;
        let my = pts.iter().map(|p| p.1).sum::<f64>() / bins as f64;
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        let slope = sxy / sxx;
        let want = -2.0 * (1.0 + hurst);
        // Random-phase amplitudes are exact (sqrt(C) at each wavevector), so the slope differs
        // from the power law's only through the bins: each averages C over an annulus of a
        // finite width at the few discrete wavevectors it holds (six at the lowest bin), which
        // biases log(mean C) against mean log|k| by a curvature term of the order of the
        // squared bin width times the slope's square. 0.02 (0.5 %) bounds it.
        assert!(
            (slope - want).abs() < 0.02,
            "H {hurst}: slope {slope}, want {want}"
        );
    }
}

#[test]
fn the_same_seed_gives_the_same_bits_on_any_thread_count() {
    let make = |threads: usize, seed: u64| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (c, h) = centres([3e-5, 2e-5], [30, 20]);
        pool.install(|| texture_heights_m(&random(spec(0.8, seed)), None, &c, h).unwrap())
    };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let one = make(1, 42);
    assert_eq!(bits(&one), bits(&make(1, 42)), "twice on one thread");
    assert_eq!(bits(&one), bits(&make(2, 42)), "on one thread and on two");
    assert_eq!(bits(&one), bits(&make(3, 42)), "on one thread and on three");
    // Another seed, another surface: heights of the order of the rms apart.
    let other = make(2, 43);
    let diff = one
        .iter()
        .zip(&other)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff > 0.5 * 2e-6, "largest difference {diff} m");
}

#[test]
fn refining_the_elements_samples_the_same_surface() {
    // A 40 x 40 um patch of 10 x 10 and of 40 x 40 elements: one generation grid, so each
    // element's height is the surface's at its centre.
    let r = spec(0.8, 5);
    let surface = random_surface(&r.surface(), [4e-5, 4e-5]).unwrap();
    for grid in [[10, 10], [40, 40], [40, 10]] {
        let (c, h) = centres([4e-5, 4e-5], grid);
        let got = texture_heights_m(&random(r), None, &c, h).unwrap();
        for (x, g) in c.iter().zip(&got) {
            assert_eq!(*g, surface.height_at_m(x[0], x[1]), "{grid:?} at {x:?}");
        }
    }
}

fn map_texture(pixel_m: [f64; 2]) -> TextureSpec {
    TextureSpec {
        heights: Some(HeightMapSpec {
            file: "in memory".into(),
            pixel_m,
        }),
        ..TextureSpec::default()
    }
}

#[test]
fn a_height_map_reproduces_a_linear_field_and_is_centred_on_the_contact_point() {
    // 7 rows (t1) of 0.5 um and 10 columns (t2) of 0.3 um: pixel centres span +-1.5 um by
    // +-1.35 um. Heights h = a + b x + c y at the pixel centres.
    let (rows, cols, dx, dy) = (7, 10, 5e-7, 3e-7);
    let (a, b, c) = (1e-7, 0.02, -0.05);
    let at = |i: usize, j: usize| {
        let x = (i as f64 - 3.0) * dx;
        let y = (j as f64 - 4.5) * dy;
        a + b * x + c * y
    };
    let grid = HeightGrid {
        rows,
        cols,
        heights_m: (0..rows * cols).map(|k| at(k / cols, k % cols)).collect(),
    };
    let t = map_texture([dx, dy]);
    let (centres, h) = centres([3e-6, 2.7e-6], [13, 17]);
    let got = texture_heights_m(&t, Some(&grid), &centres, h).unwrap();
    for (x, g) in centres.iter().zip(&got) {
        let want = a + b * x[0] + c * x[1];
        // Bilinear interpolation is exact on a linear field: round-off of a few operations on
        // heights of about 1e-7 m.
        assert!((g - want).abs() < 1e-21, "at {x:?}: {g} vs {want}");
    }
    // The contact point is the map's centre: the middle row, between columns 4 and 5.
    let origin = texture_heights_m(&t, Some(&grid), &[[0.0, 0.0]], h).unwrap()[0];
    assert!((origin - 0.5 * (at(3, 4) + at(3, 5))).abs() < 1e-21);
    // Beyond the outermost pixel centres: refused.
    let e = texture_heights_m(&t, Some(&grid), &[[1.6e-6, 0.0]], h).unwrap_err();
    assert!(e.contains("outside the height map"), "{e}");
}

#[test]
fn ridges_follow_their_cosine() {
    for angle_deg in [0.0, 30.0, 90.0, -135.0] {
        let ridges = RidgesSpec {
            amplitude_m: 3e-7,
            period_m: 7e-5,
            angle_deg,
        };
        let t = TextureSpec {
            ridges: Some(ridges),
            ..TextureSpec::default()
        };
        let (c, h) = centres([1e-3, 6e-4], [40, 24]);
        let got = texture_heights_m(&t, None, &c, h).unwrap();
        let th = angle_deg * std::f64::consts::PI / 180.0;
        for (x, g) in c.iter().zip(&got) {
            let s = x[0] * th.cos() + x[1] * th.sin();
            let want = 3e-7 * (2.0 * std::f64::consts::PI * s / 7e-5).cos();
            // libm's and the platform's cosines differ in the last bits, and the phase
            // 2 pi s / L (up to about 45 rad) carries round-off of about 1e-14 rad.
            assert!((g - want).abs() < 1e-13 * 3e-7, "{angle_deg} deg at {x:?}");
        }
    }
}

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-texture-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A `.npy` file of `rows x cols` f64 heights (`k = i cols + j`), C or Fortran order.
fn write_npy(path: &Path, rows: usize, cols: usize, h: &[f64], fortran: bool) {
    let mut bytes = Vec::new();
    let order = if fortran {
        npyz::Order::Fortran
    } else {
        npyz::Order::C
    };
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[rows as u64, cols as u64])
        .order(order)
        .writer(&mut bytes)
        .begin_nd()
        .unwrap();
    let stored: Vec<f64> = match fortran {
        false => h.to_vec(),
        true => (0..rows * cols)
            .map(|k| h[(k % rows) * cols + k / rows])
            .collect(),
    };
    w.extend(stored).unwrap();
    w.finish().unwrap();
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn npy_and_csv_of_the_same_map_give_the_same_heights() {
    let dir = folder("formats");
    // 9 x 11 pixels of 1 x 0.8 mm: +-4 mm both ways, the 10 mm patches' outermost centres.
    let (rows, cols) = (9, 11);
    let h: Vec<f64> = (0..rows * cols)
        .map(|k| 1e-6 * ((k / cols) as f64 * 0.7).sin() * ((k % cols) as f64 * 0.4).cos())
        .collect();
    write_npy(&dir.join("c.npy"), rows, cols, &h, false);
    write_npy(&dir.join("f.npy"), rows, cols, &h, true);
    let csv: String = h
        .chunks(cols)
        .map(|r| {
            r.iter()
                .map(|x| format!("{x:e}"))
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        })
        .collect();
    std::fs::write(dir.join("h.csv"), csv).unwrap();
    let heights = |file: &str| {
        let mut v = example_json("cube_a.json");
        v["fingers"][0]["texture"] = json!({"heights": {"file": file, "pixel_m": [1e-3, 8e-4]}});
        let path = dir.join(format!("scene-{file}.json"));
        std::fs::write(&path, v.to_string()).unwrap();
        let read = grasp_io::read_scene_file(&path).unwrap_or_else(|e| panic!("{file}: {e:?}"));
        let map = dir.join(file).canonicalize().unwrap();
        let noted = read
            .inputs
            .paths()
            .any(|p| p.canonicalize().unwrap() == map);
        assert!(noted, "{file} is among the files read");
        let f = &read.scene.fingers[0];
        let (c, e) = centres(f.patch.size, f.patch.grid);
        let texture = f.texture.as_ref().unwrap();
        texture_heights_m(texture, read.scene.height_map(0), &c, e).unwrap()
    };
    let from_csv = heights("h.csv");
    assert_eq!(heights("c.npy"), from_csv);
    assert_eq!(heights("f.npy"), from_csv);
    // The corner element's centre (-4, -4) mm is pixel (0, 0).
    assert!((from_csv[0] - h[0]).abs() < 1e-20);
    // Element (2, 2) is the contact point: the middle pixel (4, 5).
    assert!((from_csv[12] - h[4 * cols + 5]).abs() < 1e-20);
}

/// The rough pad of `examples/rough_sphere_on_flat.json` (64 x 64, 4,096 frictionless
/// unknowns), and the same pad ridged (`ridged_sphere_on_flat.json`): the FFT path's answer,
/// which a cold solve starts from the answer on a 32 x 32 twin of the patch (grid
/// continuation, `solver/grid_continuation.rs`) with full Newton steps, equals Clarabel's on the
/// dense matrix, an independent solver of the same discrete problem: every element force within
/// `SOLVER_AGREEMENT` (1e-8) of the 0.5 N load (Clarabel's interior point leaves about 1e-10 N on
/// separated elements, so the force, not its sign, is compared), the same tilt of the object.
/// The continuation only chooses where the Newton iteration starts, so the answer is the
/// program's to the solvers' tolerances; an answer from a coarse grid left unpolished (its
/// 2 x 2 blocks' forces spread evenly) differs by about a tenth of an element's force.
#[test]
fn rough_and_ridged_patches_solved_from_a_coarser_grid_match_clarabel_on_the_dense_matrix() {
    use grasp_model::{ComplianceChoice, SolveOptions, SolverChoice};
    for name in ["rough_sphere_on_flat.json", "ridged_sphere_on_flat.json"] {
        let v = example_json(name);
        let native = solve_with_options(
            &v,
            SolveOptions {
                solver: SolverChoice::Native,
                compliance: ComplianceChoice::Fft,
                ..SolveOptions::default()
            },
        );
        let reference = solve_with_options(
            &v,
            SolveOptions {
                solver: SolverChoice::Clarabel,
                compliance: ComplianceChoice::Dense,
                tolerance: REFERENCE_TOLERANCE,
                ..SolveOptions::default()
            },
        );
        assert!(native.status.has_forces(), "{name}: {:?}", native.reason);
        assert!(
            reference.status.has_forces(),
            "{name}: {:?}",
            reference.reason
        );
        let d = element_force_difference_n(&native, &reference);
        assert!(
            d <= SOLVER_AGREEMENT * 0.5,
            "{name}: element forces differ by {d:e} N"
        );
        let (a, b) = (
            native.rigid_displacement.expect("native tilt").rotation_rad,
            reference
                .rigid_displacement
                .expect("reference tilt")
                .rotation_rad,
        );
        for c in 0..3 {
            // The tilt to 1e-6 of the largest (Clarabel's 1e-12 on the dense program), and to
            // 1e-12 rad where there is none (the ridges are symmetric: round-off, 1e-17 rad,
            // which moves the patch's edge by 1e-20 m).
            let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let allowed = 1e-6 * scale + 1e-12;
            assert!(
                (a[c] - b[c]).abs() <= allowed,
                "{name}: rotation {a:?} against {b:?}"
            );
        }
    }
}
