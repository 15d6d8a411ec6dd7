//! The checks of `fingers[i].sensor`: at least one kind, each grid's numbers in range, a pad
//! the read-out describes (a half-space: no bonded layer, not viscoelastic) when a kind needs
//! one (taxels at depth, markers), and read-outs of bounded work. Each problem names its JSON
//! path and the fix.

use crate::scene::field_checks::{number, FieldChecks};
use crate::scene::limits::{LENGTH_RANGE_M, MAX_COORDINATE_M};
use crate::scene::scene_format::FingerSpec;
use crate::scene::sensor_kind::{GridLayout, HalfSpaceNeed};
use crate::scene::sensor_spec::{MarkerGridSpec, TaxelGridSpec, MAX_TAXEL_CELLS_PER_SIDE};

/// Most taxels along a grid's side.
pub const MAX_TAXELS_PER_SIDE: usize = 256;

/// Most markers along a grid's side.
pub const MAX_MARKERS_PER_SIDE: usize = 256;

/// Checks `fingers[i].sensor` (`p` is `fingers[i]`).
pub fn check_sensor(p: &str, f: &FingerSpec, v: &mut FieldChecks) {
    let Some(s) = &f.sensor else { return };
    let sp = format!("{p}.sensor");
    if s.taxels.is_none() && s.markers.is_none() {
        v.push(
            &sp,
            "has no kind of sensor".to_string(),
            "give `taxels`, `markers` or both, or omit the sensor",
        );
        return;
    }
    let mut ok = true;
    if let Some(t) = &s.taxels {
        ok &= check_numbers(&format!("{sp}.taxels"), t, v);
    }
    if let Some(m) = &s.markers {
        ok &= check_markers(&format!("{sp}.markers"), m, v);
    }
    if !ok {
        return;
    }
    let elements = f.patch.grid[0] * f.patch.grid[1];
    for kind in s.kinds() {
        if let Some(need) = kind.half_space_need() {
            check_pad(p, &sp, f, need, v);
        }
        let work = kind.kernel_evaluations(elements);
        let most = kind.most_kernel_evaluations();
        if work > most {
            v.push(
                &sp,
                format!(
                    "needs {work:.2e} kernel evaluations ({}), above {most:.0e}",
                    kind.work_terms()
                ),
                kind.work_fix(),
            );
        }
    }
}

/// A marker grid's numbers; false when one is unusable.
fn check_markers(mp: &str, m: &MarkerGridSpec, v: &mut FieldChecks) -> bool {
    let layout = crate::scene::sensor_kind::SensorKind::layout(m);
    let ok = check_spacing(mp, &layout, Noun::MARKER, v);
    ok & check_placement(mp, &layout, v)
}

/// How a kind's points are named in its fixes.
#[derive(Clone, Copy)]
struct Noun {
    /// One point (`"taxel"`).
    one: &'static str,
    /// Their most along a side.
    most: usize,
}

impl Noun {
    const TAXEL: Noun = Noun {
        one: "taxel",
        most: MAX_TAXELS_PER_SIDE,
    };
    const MARKER: Noun = Noun {
        one: "marker",
        most: MAX_MARKERS_PER_SIDE,
    };
}

/// A grid's counts and pitch; false when one is unusable.
fn check_spacing(gp: &str, g: &GridLayout, noun: Noun, v: &mut FieldChecks) -> bool {
    let mut ok = true;
    let most = noun.most;
    for k in 0..2 {
        if !(1..=most).contains(&g.count[k]) {
            v.push(
                &format!("{gp}.count[{k}]"),
                format!("is {}, outside [1, {most}]", g.count[k]),
                &format!("give at least one {} along each side", noun.one),
            );
            ok = false;
        }
    }
    ok &= v.range(
        &format!("{gp}.pitch_m"),
        g.pitch_m,
        LENGTH_RANGE_M,
        "m",
        &format!(
            "give the {}s' centre-to-centre distance in metres",
            noun.one
        ),
    );
    ok
}

/// A grid's rotation and offset; false when one is unusable.
fn check_placement(gp: &str, g: &GridLayout, v: &mut FieldChecks) -> bool {
    let mut ok = v.range(
        &format!("{gp}.rotation_rad"),
        g.rotation_rad,
        -std::f64::consts::TAU..=std::f64::consts::TAU,
        "rad",
        "give the grid's angle to t1 in radians, or omit it",
    );
    for k in 0..2 {
        ok &= v.range(
            &format!("{gp}.offset_m[{k}]"),
            g.offset_m[k],
            -MAX_COORDINATE_M..=MAX_COORDINATE_M,
            "m",
            "give the grid's centre from the contact point in metres, or omit it",
        );
    }
    ok
}

/// The grid's numbers; false when one is unusable (the later checks need them all).
fn check_numbers(tp: &str, t: &TaxelGridSpec, v: &mut FieldChecks) -> bool {
    let layout = crate::scene::sensor_kind::SensorKind::layout(t);
    let mut ok = check_spacing(tp, &layout, Noun::TAXEL, v);
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
    ok & check_placement(tp, &layout, v)
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

/// A pad read by a kind that `need`s a half-space: no bonded layer, no relaxation law.
fn check_pad(p: &str, sp: &str, f: &FingerSpec, need: HalfSpaceNeed, v: &mut FieldChecks) {
    let HalfSpaceNeed { what, instead } = need;
    if f.material.layer_thickness_m().is_some() {
        v.push(
            sp,
            format!(
                "{what} need a half-space pad; {p}.material has a bonded layer \
                 (layer_thickness_m)"
            ),
            &format!("{instead}, or drop the layer"),
        );
    }
    if f.material.relaxation().is_some() {
        v.push(
            sp,
            format!(
                "{what} need an elastic half-space pad; {p}.material is viscoelastic \
                 (relaxation)"
            ),
            &format!("{instead}, or drop the relaxation law"),
        );
    }
}
