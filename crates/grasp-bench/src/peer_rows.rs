//! The peer's rows in the table: on a Hertz FFT case just measured, the peer library solves the
//! same grid with as many timing runs ([`crate::peer`]); its row (time, peak-pressure error), one
//! row per solver with the ratio of the peer's time to ours, and a note with the peer's checks
//! against the closed form. The bench never fails for the peer: a missing peer is not tried
//! again, any other failure is a note.

use grasp_model::SolverChoice;

use crate::measurement::Measured;
use crate::peer::{Peer, PeerError, PeerProblem, PeerRecord};
use crate::table::{time, Row};

/// Runs the peer on the case of `ours` (its measurements, one per solver) and returns its rows,
/// with its note added to `notes`; when the peer turns out missing, `peer` becomes
/// [`Peer::Absent`] with the reason. `progress` is told when the peer starts.
pub(crate) fn peer_case(
    ours: &[Measured],
    peer: &mut Peer,
    notes: &mut Vec<String>,
    progress: &dyn Fn(&str),
) -> Vec<Row> {
    let (Some(first), Peer::Python(python)) = (ours.first(), &*peer) else {
        return Vec::new();
    };
    let case = first.case;
    progress(&format!("bench: {} (peer)", case.name));
    let record = case
        .prepare(SolverChoice::Native)
        .map_err(|e| PeerError::Problem {
            case: case.name.to_string(),
            message: e.to_string(),
        })
        .and_then(|p| PeerProblem::of(&p))
        .and_then(|problem| Ok((problem.measure(python, first.runs)?, problem.ours)));
    match record {
        Ok((r, solved)) => {
            notes.push(peer_note(&r, case.name, solved));
            peer_rows(&r, ours)
        }
        Err(e @ PeerError::Missing { .. }) => {
            *peer = Peer::Absent(e.to_string());
            Vec::new()
        }
        Err(e) => {
            notes.push(format!("peer not measured on {}: {e}", case.name));
            Vec::new()
        }
    }
}

/// The note under the table on the peer's run of `case`: its tolerance, runs, and errors
/// against Hertz's closed form, or (a gap map) its peak pressure and contact against ours.
fn peer_note(r: &PeerRecord, case: &str, ours: Option<(f64, usize)>) -> String {
    let head = format!(
        "peer {} {} on {case}: tolerance {:e} (its own relative measure), {} timed runs after an \
         untimed one; ",
        r.peer, r.version, r.tolerance, r.runs
    );
    match (r.p0_error, r.contact_radius_error, r.load_error, ours) {
        (Some(p0), Some(radius), Some(load), _) => format!(
            "{head}against Hertz: peak pressure {p0:+.1e}, contact radius {radius:+.1e}, load \
             {load:+.1e}"
        ),
        (_, _, _, Some((p_max, contact))) => format!(
            "{head}on our gap map (tilted as our solution tilts the object): peak pressure \
             {:.6e} Pa (ours {p_max:.6e}, {:+.1e}), {} elements in contact (ours {contact})",
            r.p_max_pa,
            p_max / r.p_max_pa - 1.0,
            r.contact_elements
        ),
        _ => format!("{head}peak pressure {:.6e} Pa", r.p_max_pa),
    }
}

/// The peer's row on the case (its time, its peak-pressure error) and one row per solver
/// measured on the case with the ratio of the peer's time to ours.
fn peer_rows(record: &PeerRecord, ours: &[Measured]) -> Vec<Row> {
    let Some(case) = ours.first().map(|m| m.case) else {
        return Vec::new();
    };
    let dash = || "-".to_string();
    let mut rows = vec![Row {
        case: case.name.to_string(),
        timed: case.kind.timed().to_string(),
        solver: format!("{} {} (peer)", record.peer, record.version),
        median: time(record.median_s),
        range: format!("{}-{}", time(record.min_s), time(record.max_s)),
        runs: record.runs.to_string(),
        unknowns: (record.grid * record.grid).to_string(),
        iterations: dash(),
        factorizations: dash(),
        peak_mib: dash(),
        error: record
            .p0_error
            .map_or("-".into(), |e| format!("{:.1e}", e.abs())),
        target: dash(),
    }];
    for m in ours {
        rows.push(Row {
            case: format!("{} peer/ours", case.name),
            timed: "time ratio".into(),
            solver: m.solver.to_string(),
            median: format!("{:.2}x", record.median_s / m.median_s),
            range: format!("{} / {}", time(record.median_s), time(m.median_s)),
            ..Row::default()
        });
    }
    rows
}
