//! The in-place lower Cholesky factorisation of a small dense matrix (faer, sequential), shared
//! by the Newton method's reduced factor and the interior-point method's normal matrix.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::{MatMut, Par};

/// In-place lower Cholesky; false on a non-positive pivot.
pub(crate) fn cholesky(a: MatMut<'_, f64>) -> bool {
    let n = a.nrows();
    let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        n,
        Par::Seq,
        Default::default(),
    ));
    cholesky_in_place(
        a,
        Default::default(),
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .is_ok()
}
