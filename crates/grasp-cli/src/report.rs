//! Human-readable reports (tables with units in the headers).

use std::fmt::Write;
use std::path::Path;

use grasp_model::{GraspModel, Solution};

/// The per-finger table, the rigid displacement, and the residuals beside the run time (a
/// successful run prints no line starting with `error:`: that word is kept for errors).
pub fn solution_table(scene: &Path, model: &GraspModel, sol: &Solution, build_s: f64) -> String {
    let mut s = String::new();
    outcome_lines(scene, model, sol, &mut s);
    if sol.status.has_forces() {
        finger_rows(sol, &mut s);
        edge_peak_note(sol, &mut s);
        if let Some(d) = &sol.rigid_displacement {
            displacement_line(d, &mut s);
        }
        if let Some(r) = &sol.residuals {
            residuals_line(r, &mut s);
        }
    }
    let _ = writeln!(
        s,
        "time: model {:.1} ms, solve {:.1} ms ({})",
        build_s * 1e3,
        sol.solve_time_s * 1e3,
        solver_words(&sol.solver)
    );
    if let Some(why) = &sol.solver.fallback {
        let _ = writeln!(s, "solver fallback: {why}");
    }
    s
}

/// What was solved and how it ended: the scene's size, the model, the status, the sequential
/// solve's iterations, the reason of a failure and the warnings.
fn outcome_lines(scene: &Path, model: &GraspModel, sol: &Solution, s: &mut String) {
    let planar = if model.plane().is_some() {
        "planar"
    } else {
        "3-D"
    };
    let _ = writeln!(
        s,
        "{}: {}, {} scene, {} unknowns, {} equality + {} cone rows",
        scene.display(),
        count(model.fingers().len() as u64, "finger", "fingers"),
        planar,
        sol.solver.unknowns,
        sol.solver.equality_rows,
        sol.solver.cone_rows
    );
    let status = serde_json::to_value(sol.status).ok();
    let status = status.as_ref().and_then(|v| v.as_str()).unwrap_or("?");
    let kind = serde_json::to_value(model.kind()).ok();
    let kind = kind.as_ref().and_then(|v| v.as_str()).unwrap_or("?");
    let _ = writeln!(s, "model: {kind}");
    let _ = writeln!(s, "status: {status}");
    if let Some(q) = &sol.sequential {
        let _ = writeln!(
            s,
            "sequential solve: {}, last change of an element normal force {:.2e} N \
             (tolerance {:.2e} N), {}",
            count(q.iterations, "convex solve", "convex solves"),
            q.last_change_n,
            q.tolerance_n,
            if q.converged {
                "converged"
            } else {
                "not converged"
            }
        );
    }
    if let Some(r) = &sol.reason {
        let _ = writeln!(s, "  {r}");
    }
    for w in &sol.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
}

/// The per-finger table: its header and a row per finger (forces, moment, friction use, area,
/// peak pressure, element states).
fn finger_rows(sol: &Solution, s: &mut String) {
    let _ = writeln!(
        s,
        "\n{:<10} {:>11} {:>11} {:>30} {:>12} {:>7} {:>12} {:>12} {:>17}",
        "finger",
        "P [N]",
        "|Q| [N]",
        "Q world [N]",
        "T_n [N m]",
        "|Q|/muP",
        "area [m^2]",
        "p_max [Pa]",
        "stick/slip/sep"
    );
    for f in &sol.fingers {
        let q = f.tangential_force_n;
        let _ = writeln!(
            s,
            "{:<10} {:>11.5} {:>11.5} {:>30} {:>12.3e} {:>7.3} {:>12.3e} {:>12.4e} {:>17}",
            f.name,
            f.normal_force_n,
            f.tangential_magnitude_n,
            format!("[{:+.4}, {:+.4}, {:+.4}]", q[0], q[1], q[2]),
            f.torsional_moment_nm,
            f.friction_utilization,
            f.contact_area_m2,
            f.peak_pressure_pa,
            state_counts(f)
        );
    }
}

/// Under the table, the fingers whose peak pressure lies at a sharp edge of the contact, where
/// the pressure is singular (`FingerSolution::peak_pressure_grid_dependent`): their `p_max` is
/// a property of the grid, not a result.
fn edge_peak_note(sol: &Solution, s: &mut String) {
    let at_edge: Vec<&str> = sol
        .fingers
        .iter()
        .filter(|f| f.peak_pressure_grid_dependent)
        .map(|f| f.name.as_str())
        .collect();
    if at_edge.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "p_max of {} lies at a sharp edge of the contact (the object's edge, the tip's rim or a \
         flat pad's rim), where the pressure is singular: it grows as the grid is refined and \
         is not a converged value (grasp study shows its trend); the forces converge",
        at_edge.join(", ")
    );
}

/// The object's rigid displacement: the centre of mass's translation and the rotation.
fn displacement_line(d: &grasp_model::RigidDisplacement, s: &mut String) {
    let t = d.translation_m;
    let r = d.rotation_rad;
    let _ = writeln!(
        s,
        "\nobject rigid displacement: translation of the centre of mass \
         [{:+.3e}, {:+.3e}, {:+.3e}] m, rotation [{:+.3e}, {:+.3e}, {:+.3e}] rad",
        t[0], t[1], t[2], r[0], r[1], r[2]
    );
}

/// The residuals recomputed from the solution, each relative to its scale.
fn residuals_line(r: &grasp_model::Residuals, s: &mut String) {
    let _ = writeln!(
        s,
        "residuals: equilibrium {:.1e} of the load ({:.3e} N, {:.3e} N m), cones {:.1e}, \
         penetration {:.1e}, compatibility {:.1e}, complementarity {:.1e}, stick motion \
         {:.1e}, slip direction {:.1e}",
        r.equilibrium_relative,
        r.force_n,
        r.moment_nm,
        r.cone_violation_relative,
        r.penetration_relative,
        r.compatibility_relative,
        r.complementarity_relative,
        r.stick_motion_relative,
        r.slip_direction_error
    );
}

/// A finger's element counts, `stick/slip/separated`, then the elements off the surface. A
/// frictionless finger's elements in contact neither stick nor slip (there is no friction to
/// hold them or to be overcome; their state is `frictionless`): they are counted apart,
/// `-/-/sep +n frictionless`.
fn state_counts(f: &grasp_model::FingerSolution) -> String {
    let mut cell = match f.friction_coefficient > 0.0 {
        true => format!("{}/{}/{}", f.stick_count, f.slip_count, f.separated_count),
        false => format!(
            "-/-/{} +{} frictionless",
            f.separated_count, f.frictionless_count
        ),
    };
    if f.off_surface_count > 0 {
        cell.push_str(&format!(" +{} off", f.off_surface_count));
    }
    cell
}

/// `x` to `digits` significant digits, in plain decimals from 1e-3 to 1e6 and in exponent form
/// outside (a margin of 2.5385 N, not 2.53853e0; one of 4.3e-9 N stays readable).
pub fn significant(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if (1e-3..1e6).contains(&a) {
        let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.*e}", digits - 1)
    }
}

/// What the solves of a run are, for the lines under its warnings: a noun (`step`,
/// `grid`, `direction`) and how one is named from its index.
pub struct Solves<'a> {
    /// How many solves the run made.
    pub total: usize,
    /// The noun, singular.
    pub singular: &'a str,
    /// The noun, plural.
    pub plural: &'a str,
    /// The name of the solve with this index (`3`, `24x24`, `#2`).
    pub label: &'a dyn Fn(usize) -> String,
}

/// The warnings of a run's solves, each once: `warning: <text>`, and under it the solves it
/// applies to (`  at 16 of 41 steps: 3-17, 25 (t = 0.300 to 1.700 s)`, `  at every step
/// (41)`).
pub fn tallied_warning_lines(warnings: &[grasp_model::TalliedWarning], solves: &Solves) -> String {
    let mut s = String::new();
    for w in warnings {
        let _ = writeln!(s, "warning: {}", w.message);
        let times = match (w.first_time_s, w.last_time_s) {
            (Some(a), Some(b)) if a == b => format!(" (t = {a:.3} s)"),
            (Some(a), Some(b)) => format!(" (t = {a:.3} to {b:.3} s)"),
            _ => String::new(),
        };
        if w.at_every_one_of(solves.total) && solves.total > 1 {
            let _ = writeln!(
                s,
                "  at every {} ({}){times}",
                solves.singular, solves.total
            );
            continue;
        }
        let noun = match solves.total {
            1 => solves.singular,
            _ => solves.plural,
        };
        let _ = writeln!(
            s,
            "  at {} of {} {noun}: {}{times}",
            w.count,
            solves.total,
            w.runs_text(solves.label)
        );
    }
    s
}

/// The slip-margin rule under a smallest slip margin `counted` (of `grasp transfer` or `grasp
/// plan`: one rule, `grasp_transfer::SLIP_MARGIN_RULE`), and the lighter finger it leaves out
/// when that one came closer to sliding: an indented line.
pub fn slip_rule_line(
    counted: Option<f64>,
    not_counted: Option<&grasp_transfer::SlipMargin>,
) -> String {
    let percent = 100.0 * grasp_transfer::CARRYING_FRACTION;
    let mut line =
        format!("  counted over the fingers carrying at least {percent} % of the load scale");
    if let Some(m) = not_counted.filter(|m| counted.is_none_or(|c| m.margin < c)) {
        line.push_str(&format!(
            "; a lighter one is not: {} came to {} at t = {:.3} s (a finger letting go, or just \
             touching, may slide)",
            m.finger,
            // Within round-off of 0, as the summary's own figure: at the friction limit.
            if m.margin.abs() <= 1e-9 {
                "0".to_string()
            } else {
                significant(m.margin, 3)
            },
            m.time_s
        ));
    }
    line.push('\n');
    line
}

/// `n` and its noun, singular for one: `1 Newton step`, `7 Newton steps`.
pub fn count(n: impl Into<u64>, singular: &str, plural: &str) -> String {
    let n = n.into();
    format!("{n} {}", if n == 1 { singular } else { plural })
}

/// Which solver answered, its time and iterations, in words.
pub fn solver_words(st: &grasp_model::SolverStats) -> String {
    use grasp_model::CompliancePath;
    match (st.solver, st.compliance) {
        (grasp_model::SolverKind::Native, CompliancePath::Dense) => format!(
            "native solver {:.1} ms, {}, {}",
            st.solver_time_s * 1e3,
            count(st.iterations, "Newton step", "Newton steps"),
            count(st.factorizations, "factorization", "factorizations")
        ),
        (grasp_model::SolverKind::Native, path) => format!(
            "native solver, {path} compliance, {:.1} ms, {}, {}, {}",
            st.solver_time_s * 1e3,
            count(st.iterations, "Newton step", "Newton steps"),
            count(st.factorizations, "reduced system", "reduced systems"),
            count(
                st.inner_iterations,
                "conjugate-gradient iteration",
                "conjugate-gradient iterations"
            )
        ),
        (grasp_model::SolverKind::Clarabel, _) => format!(
            "Clarabel {:.1} ms, {}",
            st.solver_time_s * 1e3,
            count(st.iterations, "iteration", "iterations")
        ),
    }
}

/// The discretisation error estimate as one line, with its extra cost.
pub fn error_estimate_line(
    scene: &grasp_model::LoadedScene,
    sol: &Solution,
    options: grasp_model::SolveOptions,
) -> anyhow::Result<String> {
    use grasp_model::{estimate_error, NoEstimate};
    // A peak at a singular edge has no error to estimate: it grows with the grid.
    let singular = sol.fingers.iter().any(|f| f.peak_pressure_grid_dependent);
    Ok(match estimate_error(scene, sol, options)? {
        Ok(e) => format!(
            "discretisation error estimate (coarse grids {:?}, ratio {:.2}, order 1): P within {:.2e} N, \
             Q within {:.2e} N ({:.1e} of the load), peak pressure {}; extra time {:.1} ms",
            e.coarse_grids,
            e.refinement_ratio,
            e.normal_force_error_n,
            e.tangential_force_error_n,
            e.relative,
            match singular {
                true => "not estimated (at a sharp edge: grid-dependent)".to_string(),
                false => format!("{:.1e} relative", e.peak_pressure_relative),
            },
            e.extra_time_s * 1e3
        ),
        Err(NoEstimate::CannotCoarsen) => {
            "discretisation error estimate: not available, every grid is 1 x 1".into()
        }
        Err(NoEstimate::CoarseFailed(why)) => {
            format!("discretisation error estimate: not available, the coarse grid failed: {why}")
        }
    })
}

/// A sensitivity as the table shows it, to six significant digits in exponent form
/// (`1.25000e-3`); a negative zero (a derivative that vanishes, computed as `-0.0`) as `0`'s
/// `0.00000e0`, never `-0.00000e0`.
fn sensitivity_cell(x: f64) -> String {
    format!("{:.5e}", x + 0.0)
}

/// The finger-force part of the sensitivities: per finger, `dP` and the world components of
/// `dQ` for each parameter; undefined parameters show as `-`.
pub fn sensitivity_table(sens: &grasp_model::Sensitivities, time_s: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nsensitivities at the active set (N per N for forces and loads, N per N m for couples, \
         N per m for approaches, N per N/m or N m/rad for stiffnesses, N per unit factor for a \
         matrix's scale; force at the centre of mass), {:.1} ms:",
        time_s * 1e3
    );
    let _ = write!(s, "{:<16}", "");
    for p in &sens.parameters {
        let _ = write!(s, "{:>14}", p.name);
    }
    let _ = writeln!(s);
    for f in &sens.fingers {
        // Per row: its label and the value of column c.
        let value = |k: usize, c: usize| match k {
            0 => f.normal_force[c],
            _ => f.tangential_force[c][k - 1],
        };
        let rows = ["dP", "dQx", "dQy", "dQz"];
        for (k, label) in rows.iter().enumerate() {
            let name = if k == 0 { f.name.as_str() } else { "" };
            let _ = write!(s, "{name:<10}{label:<6}");
            for (c, p) in sens.parameters.iter().enumerate() {
                if p.defined {
                    let _ = write!(s, "{:>14}", sensitivity_cell(value(k, c)));
                } else {
                    let _ = write!(s, "{:>14}", "-");
                }
            }
            let _ = writeln!(s);
        }
    }
    for p in sens.parameters.iter().filter(|p| !p.defined) {
        let _ = writeln!(
            s,
            "{}: no derivative ({})",
            p.name,
            p.reason.as_deref().unwrap_or("")
        );
    }
    if !sens.near_changes.is_empty() {
        let _ = writeln!(
            s,
            "{} element(s) at a state boundary (derivatives one-sided there), first: {} {:?} \
             ({})",
            sens.near_changes.len(),
            sens.near_changes[0].finger,
            sens.near_changes[0].index,
            sens.near_changes[0].transition
        );
    }
    for n in &sens.notes {
        let _ = writeln!(s, "note: {n}");
    }
    s
}

/// The tactile sensors' readings (`grasp solve` on a scene with `fingers[i].sensor`): per
/// finger with taxels, its taxels, depth, the totals over the taxels and the largest taxel
/// force; then per finger with markers, the largest tangential and normal displacements;
/// then per finger with a gel image, its size, the deepest pixel and how it was read.
pub fn sensor_table(readings: &[grasp_model::SensorReadings]) -> String {
    let mut s = String::new();
    let taxels: Vec<_> = readings.iter().filter_map(|r| r.taxels.as_ref()).collect();
    if !taxels.is_empty() {
        let _ = writeln!(
            s,
            "\ntaxels (force crossing each taxel at its depth, contact frame):\n{:<16}{:>8}{:>12}{:>14}{:>14}{:>14}{:>10}",
            "finger", "taxels", "depth_mm", "sum_Fn_N", "sum_Ft_N", "largest_N", "at"
        );
    }
    for r in taxels {
        let [t1, t2] = r.total_shear_n();
        let (k, largest) = r.largest();
        let _ = writeln!(
            s,
            "{:<16}{:>8}{:>12}{:>14}{:>14}{:>14}{:>10}",
            r.finger,
            format!("{}x{}", r.count[0], r.count[1]),
            significant(r.depth_m * 1e3, 4),
            significant(r.total_normal_n(), 6),
            significant(t1.hypot(t2), 6),
            significant(largest, 6),
            grid_index(k, r.count)
        );
    }
    s.push_str(&marker_table(readings));
    s.push_str(&gel_table(readings));
    s
}

/// The gel images' part of [`sensor_table`]: per finger with a gel image, its pixels, the
/// deepest pixel's height (um, into the pad) and where, and the read-out's path.
fn gel_table(readings: &[grasp_model::SensorReadings]) -> String {
    let mut s = String::new();
    let gels: Vec<_> = readings
        .iter()
        .filter_map(|r| r.gel.as_ref().map(|g| (&r.finger, g)))
        .collect();
    if gels.is_empty() {
        return s;
    }
    let _ = writeln!(
        s,
        "\ngel images (height of the pad's surface, + into the pad; --json or --npz for the \
         pixels):\n{:<16}{:>10}{:>16}{:>12}{:>8}",
        "finger", "pixels", "deepest_um", "at", "read"
    );
    for (finger, g) in gels {
        let (k, deepest) = g.deepest();
        let path = match g.path {
            grasp_model::HeightPath::Lattice => "fft",
            grasp_model::HeightPath::Dense => "dense",
            grasp_model::HeightPath::Flat => "flat",
        };
        let _ = writeln!(
            s,
            "{:<16}{:>10}{:>16}{:>12}{:>8}",
            finger,
            format!("{}x{}", g.count[0], g.count[1]),
            significant(deepest * 1e6, 6),
            grid_index(k, g.count),
            path
        );
    }
    s
}

/// `[i, j]` of the row-major index `k` of a grid of `count` points.
fn grid_index(k: usize, count: [usize; 2]) -> String {
    format!("[{}, {}]", k / count[1].max(1), k % count[1].max(1))
}

/// The markers' part of [`sensor_table`]: per finger with markers, the largest tangential
/// displacement and the normal displacement of largest size (positive into the pad), um.
fn marker_table(readings: &[grasp_model::SensorReadings]) -> String {
    let mut s = String::new();
    let markers: Vec<_> = readings
        .iter()
        .filter_map(|r| r.markers.as_ref().map(|m| (&r.finger, m)))
        .collect();
    if markers.is_empty() {
        return s;
    }
    let _ = writeln!(
        s,
        "\nmarkers (pad surface displacement relative to the finger's core; normal + into the pad):\n{:<16}{:>8}{:>16}{:>10}{:>16}{:>10}",
        "finger", "markers", "largest_ut_um", "at", "largest_un_um", "at"
    );
    for (finger, m) in markers {
        let (kt, ut) = m.largest_tangential();
        let (kn, un) = m.largest_normal();
        let _ = writeln!(
            s,
            "{:<16}{:>8}{:>16}{:>10}{:>16}{:>10}",
            finger,
            format!("{}x{}", m.count[0], m.count[1]),
            significant(ut * 1e6, 6),
            grid_index(kt, m.count),
            significant(un * 1e6, 6),
            grid_index(kn, m.count)
        );
    }
    s
}

/// The mounted fingers' cores (`grasp solve` on a scene with `fingers[i].mount`): per finger
/// its approach (the commanded jaw position; found, for a force-controlled finger), the
/// core's displacement from its commanded pose (along the normal: negative pushed back; the
/// translation's length) and the core's rotation; empty when no finger has a mount.
pub fn mount_table(solution: &grasp_model::Solution) -> String {
    let mounted: Vec<_> = solution
        .fingers
        .iter()
        .filter_map(|f| f.mount_displacement.map(|d| (f, d)))
        .collect();
    if mounted.is_empty() {
        return String::new();
    }
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nmounts (each core's displacement from its commanded pose):\n{:<16}{:>14}{:>18}{:>16}{:>18}",
        "finger", "approach_mm", "core_along_n_mm", "core_moved_mm", "core_turned_mrad"
    );
    for (f, d) in mounted {
        let _ = writeln!(
            s,
            "{:<16}{:>14}{:>18}{:>16}{:>18}",
            f.name,
            significant(f.approach_m * 1e3, 6),
            significant(d.normal_m * 1e3 + 0.0, 6),
            significant(d.moved_m() * 1e3, 6),
            significant(d.turned_rad() * 1e3, 6)
        );
    }
    s
}

/// The hands' and servos' loads and motions (`grasp solve` on a scene with `hands` or
/// `servos`): per hand the force its fingers put on the object and how far its base moved and
/// turned; per servo the sum of its jaws' forces and their travel short of the command (mm,
/// negative: pushed back); empty when the scene has neither.
pub fn shared_spring_table(solution: &grasp_model::Solution) -> String {
    let mut s = String::new();
    let v = |a: [f64; 3], scale: f64| {
        let c = |x: f64| x * scale + 0.0;
        format!("[{:+.4e}, {:+.4e}, {:+.4e}]", c(a[0]), c(a[1]), c(a[2]))
    };
    if !solution.hands.is_empty() {
        let _ = writeln!(
            s,
            "\nhands (each base's displacement from its commanded pose):\n{:<16}{:<38}{:<38}rotation [mrad]",
            "hand", "force on object [N]", "translation [mm]"
        );
        for h in &solution.hands {
            let _ = writeln!(
                s,
                "{:<16}{:<38}{:<38}{}",
                h.name,
                v(h.force_n, 1.0),
                v(h.translation_m, 1e3),
                v(h.rotation_rad, 1e3)
            );
        }
    }
    if !solution.servos.is_empty() {
        let _ = writeln!(
            s,
            "\nservos (the jaws' travel from their commanded position):\n{:<16}{:>14}{:>14}",
            "servo", "force_n", "travel_mm"
        );
        for sv in &solution.servos {
            let _ = writeln!(
                s,
                "{:<16}{:>14}{:>14}",
                sv.name,
                significant(sv.force_n, 6),
                significant(sv.travel_m * 1e3 + 0.0, 6)
            );
        }
    }
    s
}

/// What the object's shape gave each finger (`grasp solve --explain-frames`).
pub fn frames_table(r: &grasp_model::ShapeReport) -> String {
    let mut o = String::new();
    let mass = r.mass_kg.map_or(String::new(), |m| {
        format!(
            ", mass {m:.6} kg (weight {:.6} N)",
            m * grasp_model::STANDARD_GRAVITY
        )
    });
    let c = r.centroid_m;
    let _ = writeln!(
        o,
        "shape: volume {:.6e} m^3, centroid [{:.6}, {:.6}, {:.6}] m{mass}",
        r.volume_m3, c[0], c[1], c[2]
    );
    let v = |a: [f64; 3]| format!("[{:+.6}, {:+.6}, {:+.6}]", a[0], a[1], a[2]);
    let radius = |x: Option<f64>| x.map_or("flat".to_string(), |r| format!("{r:.6} m"));
    for f in &r.fingers {
        let _ = writeln!(o, "finger {} ({}):", f.finger, f.source);
        let _ = writeln!(
            o,
            "  contact point {} m, {:.3e} m from the surface",
            v(f.contact_point_m),
            f.distance_m
        );
        let _ = writeln!(o, "  inward normal {}", v(f.normal));
        if let Some(t) = f.tangent {
            let _ = writeln!(o, "  tangent t1    {}", v(t));
            let _ = writeln!(
                o,
                "  curvature along t1, t2: {:.6}, {:.6} 1/m; object_radius: {}, {}",
                f.curvature_per_m[0],
                f.curvature_per_m[1],
                radius(f.object_radius_m[0]),
                radius(f.object_radius_m[1])
            );
        }
        for n in &f.notes {
            let _ = writeln!(o, "  note: {n}");
        }
    }
    o
}

/// A finger's initial gaps: how they are computed, their range and largest slope over the
/// elements facing a surface, and how many face none.
fn gap_line(name: &str, m: &grasp_model::FingerModel) -> String {
    let kind = match m.has_exact_gaps() {
        true => "exact (from the shapes)",
        false => "quadratic (the thesis's form from the radii)",
    };
    let patch = m.patch();
    let off = patch.off_surface_count();
    let range = match patch.gap_range() {
        Some(([lo, hi], slope)) => format!(
            "from {:.4} to {:.4} mm, largest slope {slope:.3} ({:.1} degrees)",
            1e3 * lo,
            1e3 * hi,
            slope.atan().to_degrees()
        ),
        None => "none: no element faces a surface".into(),
    };
    format!(
        "finger {name}: gaps {kind}: {range}; {off} of {} elements face no surface",
        patch.len()
    )
}

/// Per finger, its initial gaps, and per curved contact the Hertz estimate and the patch it
/// suggests (`--explain-frames`), at the finger's commanded load, or the object's weight for a
/// held finger.
pub fn hertz_table(scene: &grasp_model::LoadedScene) -> anyhow::Result<String> {
    let model = grasp_model::GraspModel::from_loaded(scene)?;
    let mut o = String::new();
    let mm = |x: f64| format!("{:.3}", 1e3 * x);
    for (f, m) in scene.fingers.iter().zip(model.fingers()) {
        let _ = writeln!(o, "{}", gap_line(&f.name, m));
        let (load, which) = match f.control.normal_load_n() {
            Some(p) => (p, "its commanded load"),
            None => (scene.object.weight, "the object's weight"),
        };
        let Some(h) = grasp_model::hertz_suggestion(f, m, load) else {
            continue;
        };
        let axis = |a: Option<f64>| a.map_or("line".to_string(), |a| format!("{} mm", mm(a)));
        let kind = match h.layered {
            true => "contact on a layer (estimate)",
            false => "Hertz contact",
        };
        let _ = writeln!(
            o,
            "finger {}: {kind} at {:.4} N ({which}): semi-axes {} x {}; suggested patch [{}, {}] mm (now [{}, {}] mm)",
            f.name,
            h.load_n,
            axis(h.semi_axes_m[0]),
            axis(h.semi_axes_m[1]),
            mm(h.suggested_size_m[0]),
            mm(h.suggested_size_m[1]),
            mm(f.patch.size[0]),
            mm(f.patch.size[1])
        );
    }
    Ok(o)
}

#[cfg(test)]
mod tests {
    #[test]
    fn significant_digits_are_plain_in_the_usual_range() {
        use super::significant;
        assert_eq!(significant(2.538531, 5), "2.5385");
        assert_eq!(significant(0.0170589, 5), "0.017059");
        assert_eq!(significant(4448.0, 5), "4448.0");
        assert_eq!(significant(25.7943, 5), "25.794");
        assert_eq!(significant(5.1381e-4, 5), "5.1381e-4");
        assert_eq!(significant(0.0, 5), "0");
    }

    /// A derivative computed as `-0.0` is shown as zero, not `-0.00000e0`.
    #[test]
    fn a_negative_zero_sensitivity_is_shown_without_its_sign() {
        use super::sensitivity_cell;
        assert_eq!(sensitivity_cell(-0.0), "0.00000e0");
        assert_eq!(sensitivity_cell(0.0), "0.00000e0");
        assert_eq!(sensitivity_cell(-1.25e-3), "-1.25000e-3");
    }

    use super::count;

    #[test]
    fn one_of_a_kind_is_singular() {
        assert_eq!(count(1u32, "Newton step", "Newton steps"), "1 Newton step");
        assert_eq!(count(0u32, "Newton step", "Newton steps"), "0 Newton steps");
        assert_eq!(count(7u32, "program", "programs"), "7 programs");
    }
}
