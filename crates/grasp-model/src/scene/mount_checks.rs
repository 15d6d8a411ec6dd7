//! The checks of `fingers[i].mount`: one form of stiffness (per direction, a full matrix, or a
//! compliance), its numbers in range, a matrix symmetric and positive definite, a compliance
//! symmetric and positive semidefinite, and a preload the finger's control can take. Each
//! problem names its JSON path and the fix.

use nalgebra::Matrix6;

use crate::scene::field_checks::{number, FieldChecks};
use crate::scene::limits::{
    MOUNT_ROTATIONAL_STIFFNESS_RANGE_NM_PER_RAD, MOUNT_STIFFNESS_RANGE_N_PER_M,
};
use crate::scene::mount_spec::MountSpec;
use crate::scene::scene_format::{ControlSpec, FingerSpec};

/// Relative asymmetry `|K_ij - K_ji| / max |K|` above which a mount's matrix is refused.
pub const MOUNT_SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Checks `fingers[i].mount` (`p` is `fingers[i]`).
pub fn check_mount(p: &str, f: &FingerSpec, v: &mut FieldChecks) {
    let Some(m) = &f.mount else { return };
    let mp = format!("{p}.mount");
    let by_direction = [
        m.normal_n_per_m,
        m.tangential_n_per_m,
        m.rotational_nm_per_rad,
    ];
    let forms = [m.matrix.is_some(), m.compliance.is_some()];
    if forms.iter().filter(|x| **x).count() + usize::from(by_direction.iter().any(Option::is_some))
        > 1
    {
        v.push(
            &mp,
            "gives more than one form of its stiffness".into(),
            "give one of `matrix`, `compliance`, or `normal_n_per_m` / `tangential_n_per_m` / \
             `rotational_nm_per_rad`",
        );
    } else if let Some(s) = &m.compliance {
        check_compliance(&mp, s, v);
    }
    match (&m.matrix, by_direction.iter().any(Option::is_some)) {
        _ if m.compliance.is_some() => {}
        (Some(_), true) => {}
        (None, false) => v.push(
            &mp,
            "gives no stiffness".into(),
            "give `normal_n_per_m`, `tangential_n_per_m`, `rotational_nm_per_rad` (N/m, N m/rad), \
             a 6x6 `matrix` or a 6x6 `compliance`; omit `mount` for a rigid core",
        ),
        (Some(k), false) => check_matrix(&mp, k, MOUNT_AXES, v),
        (None, true) => check_directions(&mp, m, v),
    }
    check_preload(p, &mp, f, m, v);
}

/// The stiffnesses by direction, each in its range.
fn check_directions(mp: &str, m: &MountSpec, v: &mut FieldChecks) {
    let fix = "give the stiffness in N/m, or leave it out for a rigid direction";
    if let Some(k) = m.normal_n_per_m {
        v.range(
            &format!("{mp}.normal_n_per_m"),
            k,
            MOUNT_STIFFNESS_RANGE_N_PER_M,
            "N/m",
            fix,
        );
    }
    if let Some(k) = m.tangential_n_per_m {
        v.range(
            &format!("{mp}.tangential_n_per_m"),
            k,
            MOUNT_STIFFNESS_RANGE_N_PER_M,
            "N/m",
            fix,
        );
    }
    if let Some(k) = m.rotational_nm_per_rad {
        v.range(
            &format!("{mp}.rotational_nm_per_rad"),
            k,
            MOUNT_ROTATIONAL_STIFFNESS_RANGE_NM_PER_RAD,
            "N m/rad",
            "give the stiffness in N m/rad, or leave it out for a rigid core in rotation",
        );
    }
}

/// The rows of a mount's matrix, as its problems name them.
const MOUNT_AXES: &str = "t1, t2, n, rot t1, rot t2, rot n";

/// A full stiffness matrix at `mp.matrix`, rows `axes` (three translations, then three
/// rotations): finite, symmetric, positive definite, its diagonal in range.
pub(crate) fn check_matrix(mp: &str, k: &[[f64; 6]; 6], axes: &str, v: &mut FieldChecks) {
    let path = format!("{mp}.matrix");
    if let Some((r, c)) = (0..36)
        .map(|i| (i / 6, i % 6))
        .find(|&(r, c)| !k[r][c].is_finite())
    {
        v.push(
            &format!("{path}[{r}][{c}]"),
            format!("is {}", number(k[r][c])),
            "give finite stiffnesses",
        );
        return;
    }
    for (c, row) in k.iter().enumerate() {
        let range = match c < 3 {
            true => MOUNT_STIFFNESS_RANGE_N_PER_M,
            false => MOUNT_ROTATIONAL_STIFFNESS_RANGE_NM_PER_RAD,
        };
        let unit = if c < 3 { "N/m" } else { "N m/rad" };
        if !v.range(
            &format!("{path}[{c}][{c}]"),
            row[c],
            range,
            unit,
            &format!("give the diagonal's stiffnesses in range (rows {axes})"),
        ) {
            return;
        }
    }
    let largest = k.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
    let asymmetric = (0..36)
        .map(|i| (i / 6, i % 6))
        .find(|&(r, c)| (k[r][c] - k[c][r]).abs() > MOUNT_SYMMETRY_TOLERANCE * largest);
    if let Some((r, c)) = asymmetric {
        v.push(
            &format!("{path}[{r}][{c}]"),
            format!(
                "is {} but [{c}][{r}] is {}: a stiffness is symmetric",
                number(k[r][c]),
                number(k[c][r])
            ),
            "make the matrix symmetric",
        );
        return;
    }
    if Matrix6::from_fn(|r, c| k[r][c]).cholesky().is_none() {
        v.push(
            &path,
            "is not positive definite: some motion would need no force".into(),
            "give a positive definite stiffness (every eigenvalue above 0)",
        );
    }
}

/// Largest compliance entry a mount takes, m/N (1/N, rad/(N m)): the inverse of the smallest
/// stiffness, 1e-6 N/m.
pub const MOUNT_LARGEST_COMPLIANCE: f64 = 1e6;

/// A compliance at `mp.compliance`: finite, within [`MOUNT_LARGEST_COMPLIANCE`], symmetric,
/// positive semidefinite (its eigenvalues above `-1e-12` of the largest), not all zero.
fn check_compliance(mp: &str, s: &[[f64; 6]; 6], v: &mut FieldChecks) {
    let path = format!("{mp}.compliance");
    let mut entries = (0..36).map(|i| (i / 6, i % 6));
    if let Some((r, c)) = entries
        .clone()
        .find(|&(r, c)| !s[r][c].is_finite() || s[r][c].abs() > MOUNT_LARGEST_COMPLIANCE)
    {
        v.push(
            &format!("{path}[{r}][{c}]"),
            format!("is {}", number(s[r][c])),
            "give finite compliances of at most 1e6 (m/N, 1/N, rad/(N m))",
        );
        return;
    }
    let largest = s.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
    let asymmetric =
        entries.find(|&(r, c)| (s[r][c] - s[c][r]).abs() > MOUNT_SYMMETRY_TOLERANCE * largest);
    if let Some((r, c)) = asymmetric {
        let what = format!(
            "is {} but [{c}][{r}] is {}: a compliance is symmetric",
            number(s[r][c]),
            number(s[c][r])
        );
        v.push(
            &format!("{path}[{r}][{c}]"),
            what,
            "make the compliance symmetric",
        );
        return;
    }
    let eigen = Matrix6::from_fn(|r, c| 0.5 * (s[r][c] + s[c][r])).symmetric_eigenvalues();
    if largest == 0.0 || eigen.min() < -1e-12 * eigen.max() {
        v.push(
            &path,
            "is not positive semidefinite (or is all zero): some load would do negative work"
                .into(),
            "give a positive semidefinite compliance with some direction above 0 (a rank-one \
             `J J' / K_q` written with full precision: rounding may leave an eigenvalue below \
             -1e-12 of the largest), or omit `mount` for a rigid core",
        );
    }
}

/// A preload needs a compliant normal and a finger whose normal load is not prescribed.
fn check_preload(p: &str, mp: &str, f: &FingerSpec, m: &MountSpec, v: &mut FieldChecks) {
    let path = format!("{mp}.preload_n");
    if !v.force(&path, m.preload_n, "give the preload in newtons, or 0") || m.preload_n == 0.0 {
        return;
    }
    if matches!(f.control, ControlSpec::Load(_)) {
        v.push(
            &path,
            format!("is set but {p}.control prescribes the normal load"),
            "drop preload_n (the load is the control's), or drive the finger by `approach_m`",
        );
    } else if m.compliance.is_some_and(|s| s[2][2] <= 0.0) {
        v.push(
            &path,
            "is set but the compliance does not move the core along the normal".into(),
            "give a compliance with `[2][2]` above 0, or drop preload_n",
        );
    } else if m.matrix.is_none() && m.compliance.is_none() && m.normal_n_per_m.is_none() {
        v.push(
            &path,
            "is set but the mount is rigid along the normal".into(),
            "give normal_n_per_m, or drop preload_n",
        );
    }
}
