//! The checks of `fingers[i].sensor`: a taxel grid's numbers in range, a pad the read-out
//! describes (a half-space: no bonded layer, not viscoelastic) when the taxels lie at depth,
//! and a read-out of bounded work. Each problem names its JSON path and the fix.

use crate::scene::field_checks::{number, FieldChecks};
use crate::scene::limits::{LENGTH_RANGE_M, MAX_COORDINATE_M};
use crate::scene::scene_format::FingerSpec;
use crate::scene::sensor_spec::{
    TaxelGridSpec, MAX_TAXEL_CELLS_PER_SIDE, MAX_TAXEL_KERNEL_EVALUATIONS,
};

/// Most taxels along a grid's side.
pub const MAX_TAXELS_PER_SIDE: usize = 256;

/// Checks `fingers[i].sensor` (`p` is `fingers[i]`).
pub fn check_sensor(p: &str, f: &FingerSpec, v: &mut FieldChecks) {
    let Some(s) = &f.sensor else { return };
    let sp = format!("{p}.sensor");
    let t = &s.taxels;
    let tp = format!("{sp}.taxels");
    if !check_numbers(&tp, t, v) {
        return;
    }
    if t.depth_m > 0.0 {
        check_pad(p, &sp, f, v);
        let elements = f.patch.grid[0] * f.patch.grid[1];
        let work = t.kernel_evaluations(elements);
        if work > MAX_TAXEL_KERNEL_EVALUATIONS {
            v.push(
                &sp,
                format!(
                    "needs {work:.2e} kernel evaluations (taxels x quadrature points x \
                     elements), above {MAX_TAXEL_KERNEL_EVALUATIONS:.0e}"
                ),
                "use fewer taxels, a larger depth_m (fewer quadrature points) or a coarser patch",
            );
        }
    }
}

/// The grid's numbers; false when one is unusable (the later checks need them all).
fn check_numbers(tp: &str, t: &TaxelGridSpec, v: &mut FieldChecks) -> bool {
    let mut ok = true;
    for k in 0..2 {
        if !(1..=MAX_TAXELS_PER_SIDE).contains(&t.count[k]) {
            v.push(
                &format!("{tp}.count[{k}]"),
                format!("is {}, outside [1, {MAX_TAXELS_PER_SIDE}]", t.count[k]),
                "give at least one taxel along each side",
            );
            ok = false;
        }
    }
    ok &= v.range(
        &format!("{tp}.pitch_m"),
        t.pitch_m,
        LENGTH_RANGE_M,
        "m",
        "give the taxels' centre-to-centre distance in metres",
    );
    ok &= v.range(
        &format!("{tp}.size_m"),
        t.size_m,
        LENGTH_RANGE_M,
        "m",
        "give each taxel's side in metres",
    );
    if ok && t.size_m > t.pitch_m {
        v.push(
            &format!("{tp}.size_m"),
            format!(
                "is {} m, above pitch_m {} m: the taxels overlap",
                number(t.size_m),
                number(t.pitch_m)
            ),
            "give a size no larger than the pitch",
        );
        ok = false;
    }
    ok &= check_depth(tp, t, v);
    ok &= v.range(
        &format!("{tp}.rotation_rad"),
        t.rotation_rad,
        -std::f64::consts::TAU..=std::f64::consts::TAU,
        "rad",
        "give the grid's angle to t1 in radians, or omit it",
    );
    for k in 0..2 {
        ok &= v.range(
            &format!("{tp}.offset_m[{k}]"),
            t.offset_m[k],
            -MAX_COORDINATE_M..=MAX_COORDINATE_M,
            "m",
            "give the grid's centre from the contact point in metres, or omit it",
        );
    }
    ok
}

/// The depth: 0, or at least `size_m / 32` (the quadrature's cells are no wider than it).
fn check_depth(tp: &str, t: &TaxelGridSpec, v: &mut FieldChecks) -> bool {
    let p = format!("{tp}.depth_m");
    if t.depth_m == 0.0 {
        return true;
    }
    if !v.range(
        &p,
        t.depth_m,
        0.0..=*LENGTH_RANGE_M.end(),
        "m",
        "give the taxels' depth below the pad's surface in metres (0: on the surface)",
    ) {
        return false;
    }
    let least = t.size_m / MAX_TAXEL_CELLS_PER_SIDE as f64;
    if t.size_m.is_finite() && t.depth_m < least {
        v.push(
            &p,
            format!(
                "is {} m, below size_m / {MAX_TAXEL_CELLS_PER_SIDE} = {} m",
                number(t.depth_m),
                number(least)
            ),
            "give 0 (the surface tractions binned onto the taxels) or a depth of at least \
             size_m / 32",
        );
        return false;
    }
    true
}

/// A pad read at depth must be a half-space: no bonded layer, no relaxation law.
fn check_pad(p: &str, sp: &str, f: &FingerSpec, v: &mut FieldChecks) {
    if f.material.layer_thickness_m().is_some() {
        v.push(
            sp,
            format!(
                "taxels at depth need a half-space pad; {p}.material has a bonded layer \
                 (layer_thickness_m)"
            ),
            "read the taxels at depth_m 0 (the surface tractions), or drop the layer",
        );
    }
    if f.material.relaxation().is_some() {
        v.push(
            sp,
            format!(
                "taxels at depth need an elastic half-space pad; {p}.material is \
                 viscoelastic (relaxation)"
            ),
            "read the taxels at depth_m 0 (the surface tractions), or drop the relaxation law",
        );
    }
}
