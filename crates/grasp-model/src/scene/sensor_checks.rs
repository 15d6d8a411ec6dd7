//! The checks of `fingers[i].sensor`: at least one kind, each grid's numbers in range (a gel
//! image's shading too), a pad the read-out describes (a half-space: no bonded layer; not
//! viscoelastic, unless the kind reads stresses) when a kind needs one (taxels at depth,
//! markers, a gel image), and read-outs
//! of bounded work. Each problem names its JSON path and the fix.

use crate::scene::field_checks::{number, FieldChecks};
use crate::scene::gel_spec::{GelSpec, LightSpec, LookupSpec, MAX_LIGHTS, MAX_PIXELS_PER_SIDE};
use crate::scene::limits::{LENGTH_RANGE_M, MAX_COORDINATE_M};
use crate::scene::response_spec::ResponseSpec;
use crate::scene::scene_format::FingerSpec;
use crate::scene::sensor_kind::{ElementGrid, GridLayout, HalfSpaceNeed, SensorKind};
use crate::scene::sensor_spec::{MarkerGridSpec, TaxelGridSpec, MAX_TAXEL_CELLS_PER_SIDE};

/// Most taxels along a grid's side.
pub const MAX_TAXELS_PER_SIDE: usize = 256;

/// Most markers along a grid's side.
pub const MAX_MARKERS_PER_SIDE: usize = 256;

/// Checks `fingers[i].sensor` (`p` is `fingers[i]`).
pub fn check_sensor(p: &str, f: &FingerSpec, v: &mut FieldChecks) {
    let Some(s) = &f.sensor else { return };
    let sp = format!("{p}.sensor");
    if s.kinds().is_empty() {
        v.push(
            &sp,
            "has no kind of sensor".to_string(),
            "give `taxels`, `markers`, `gel` or more than one, or omit the sensor",
        );
        return;
    }
    let mut ok = true;
    if let Some(t) = &s.taxels {
        ok &= check_numbers(&format!("{sp}.taxels"), t, v);
        ok &= check_response(&format!("{sp}.taxels.response"), &t.response, v);
    }
    if let Some(m) = &s.markers {
        ok &= check_markers(&format!("{sp}.markers"), m, v);
        ok &= check_response(&format!("{sp}.markers.response"), &m.response, v);
    }
    if let Some(g) = &s.gel {
        ok &= check_gel(&format!("{sp}.gel"), g, v);
        ok &= check_response(&format!("{sp}.gel.response"), &g.response, v);
    }
    if !ok {
        return;
    }
    let patch = ElementGrid::of_patch(f.patch.size, f.patch.grid);
    for kind in s.kinds() {
        if let Some(need) = kind.half_space_need() {
            check_pad(p, &sp, f, need, v);
        }
        let work = kind.kernel_evaluations(&patch);
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
    let layout = m.layout();
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
        g.pitch_m[0],
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
    let layout = t.layout();
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

/// A pad read by a kind that `need`s a half-space: no bonded layer, and no relaxation law
/// unless the kind reads stresses ([`HalfSpaceNeed::reads_stress`]).
fn check_pad(p: &str, sp: &str, f: &FingerSpec, need: HalfSpaceNeed, v: &mut FieldChecks) {
    let HalfSpaceNeed {
        what,
        instead,
        reads_stress,
    } = need;
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
    if f.material.relaxation().is_some() && !reads_stress {
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

/// A gel image's numbers and shading; false when one is unusable.
fn check_gel(gp: &str, g: &GelSpec, v: &mut FieldChecks) -> bool {
    let mut ok = true;
    for k in 0..2 {
        if !(1..=MAX_PIXELS_PER_SIDE).contains(&g.image_px[k]) {
            v.push(
                &format!("{gp}.image_px[{k}]"),
                format!("is {}, outside [1, {MAX_PIXELS_PER_SIDE}]", g.image_px[k]),
                "give the image's size in pixels along each side",
            );
            ok = false;
        }
        ok &= v.range(
            &format!("{gp}.field_of_view_m[{k}]"),
            g.field_of_view_m[k],
            1e-9..=10.0,
            "m",
            "give the gel's field of view along each side in metres",
        );
    }
    ok &= check_placement(gp, &g.layout(), v);
    if g.lookup.is_some() && (g.lights.is_some() || g.ambient_rgb.is_some()) {
        v.push(
            gp,
            "has both `lookup` and `lights` or `ambient_rgb`".to_string(),
            "give the lookup table alone (it gives the colour whole), or the lights",
        );
        ok = false;
    }
    if let Some(lights) = &g.lights {
        ok &= check_lights(&format!("{gp}.lights"), lights, v);
    }
    if let Some(a) = &g.ambient_rgb {
        for (c, x) in a.iter().enumerate() {
            ok &= v.range(
                &format!("{gp}.ambient_rgb[{c}]"),
                *x,
                0.0..=1.0,
                "",
                "give the ambient light per channel in [0, 1], or omit it",
            );
        }
    }
    if let Some(t) = &g.lookup {
        ok &= check_lookup(&format!("{gp}.lookup"), t, v);
    }
    ok
}

/// The lights: 1 to [`MAX_LIGHTS`], each toward the camera's side, colours in range.
fn check_lights(lp: &str, lights: &[LightSpec], v: &mut FieldChecks) -> bool {
    if !(1..=MAX_LIGHTS).contains(&lights.len()) {
        v.push(
            lp,
            format!("has {} lights, outside [1, {MAX_LIGHTS}]", lights.len()),
            "give at least one light, or omit `lights` for the default three",
        );
        return false;
    }
    let mut ok = true;
    for (k, l) in lights.iter().enumerate() {
        let d = l.direction;
        let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(length.is_finite() && length > 0.0 && d[2] > 0.0) {
            v.push(
                &format!("{lp}[{k}].direction"),
                format!("is [{}, {}, {}]", number(d[0]), number(d[1]), number(d[2])),
                "give a finite direction toward the light with w > 0 (on the camera's side \
                 of the gel)",
            );
            ok = false;
        }
        for (c, x) in l.rgb.iter().enumerate() {
            ok &= v.range(
                &format!("{lp}[{k}].rgb[{c}]"),
                *x,
                0.0..=10.0,
                "",
                "give the light's colour per channel in [0, 10]",
            );
        }
    }
    ok
}

/// A lookup table: a slope range, `na x nb` colours in `[2, 256]` each way, in `[0, 1]`.
fn check_lookup(tp: &str, t: &LookupSpec, v: &mut FieldChecks) -> bool {
    let mut ok = v.range(
        &format!("{tp}.slope_range"),
        t.slope_range,
        1e-9..=100.0,
        "",
        "give the largest slope (m/m) the table covers",
    );
    let na = t.rgb.len();
    let nb = t.rgb.first().map_or(0, Vec::len);
    if !(2..=256).contains(&na) || !(2..=256).contains(&nb) {
        v.push(
            &format!("{tp}.rgb"),
            format!("is {na} x {nb}, outside [2, 256] each way"),
            "give a table of at least 2 x 2 colours",
        );
        return false;
    }
    for (a, row) in t.rgb.iter().enumerate() {
        if row.len() != nb {
            v.push(
                &format!("{tp}.rgb[{a}]"),
                format!("has {} colours, the first row {nb}", row.len()),
                "give every row of the table as many colours",
            );
            ok = false;
            continue;
        }
        let bad = row
            .iter()
            .flatten()
            .any(|x| !(x.is_finite() && (0.0..=1.0).contains(x)));
        if bad {
            v.push(
                &format!("{tp}.rgb[{a}]"),
                "has a channel outside [0, 1]".to_string(),
                "give each colour's channels in [0, 1]",
            );
            ok = false;
        }
    }
    ok
}

/// A kind's response, when given: its spreads, saturation range, quantum and seed in range.
fn check_response(rp: &str, r: &Option<ResponseSpec>, v: &mut FieldChecks) -> bool {
    let Some(r) = r else { return true };
    let mut ok = v.range(
        &format!("{rp}.gain_std"),
        r.gain_std,
        0.0..=1.0,
        "",
        "give the gains' standard deviation about 1, or omit it",
    );
    ok &= v.range(
        &format!("{rp}.noise_std"),
        r.noise_std,
        0.0..=1e6,
        "",
        "give the noise's standard deviation in the reading's unit (N, m, or colour in [0, 1]), or omit it",
    );
    if let Some([low, high]) = r.saturation {
        if !(low.is_finite() && high.is_finite() && low < high) {
            v.push(
                &format!("{rp}.saturation"),
                format!("is [{}, {}]", number(low), number(high)),
                "give the range [low, high] the reading saturates at, low below high, or omit it",
            );
            ok = false;
        }
    }
    if let Some(q) = r.quantum {
        ok &= v.range(
            &format!("{rp}.quantum"),
            q,
            1e-300..=1e6,
            "",
            "give the reading's resolution (a positive step in its unit), or omit it",
        );
    }
    if r.seed > 1u64 << 53 {
        v.push(
            &format!("{rp}.seed"),
            format!("is {}, above 2^53", r.seed),
            "give a seed in [0, 2^53] (JSON numbers above it lose digits)",
        );
        ok = false;
    }
    ok
}
