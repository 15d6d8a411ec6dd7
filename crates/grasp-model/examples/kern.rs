use std::time::Instant;
/// Row-major lower Cholesky in place (lower triangle), returns false on a non-positive pivot.
fn chol(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let (head, rest) = a.split_at_mut(j * n);
        let rowj = &mut rest[..n];
        let _ = head;
        let mut d = rowj[j];
        for k in 0..j {
            d -= rowj[k] * rowj[k];
        }
        if !(d > 0.0) {
            return false;
        }
        let ljj = d.sqrt();
        rowj[j] = ljj;
        let rowj: Vec<f64> = rowj[..j].to_vec();
        for i in j + 1..n {
            let rowi = &mut a[i * n..i * n + n];
            let s: f64 = rowi[..j].iter().zip(&rowj).map(|(x, y)| x * y).sum();
            rowi[j] = (rowi[j] - s) / ljj;
        }
    }
    true
}
fn main() {
    for n in [54usize, 75, 128, 192, 256, 400] {
        let a: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                1.0 / (1.0 + (i as f64 - j as f64).abs()) + if i == j { 1.0 } else { 0.0 }
            })
            .collect();
        let reps = 20000 / n;
        let t = Instant::now();
        for _ in 0..reps {
            let mut b = a.clone();
            assert!(chol(&mut b, n));
        }
        let tn = t.elapsed().as_secs_f64() / reps as f64;
        let fm = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
        let t = Instant::now();
        for _ in 0..reps {
            let mut b = fm.clone();
            let mut mem = faer::dyn_stack::MemBuffer::new(
                faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
                    n,
                    faer::Par::Seq,
                    Default::default(),
                ),
            );
            faer::linalg::cholesky::llt::factor::cholesky_in_place(
                b.as_mut(),
                Default::default(),
                faer::Par::Seq,
                faer::dyn_stack::MemStack::new(&mut mem),
                Default::default(),
            )
            .unwrap();
        }
        let tf = t.elapsed().as_secs_f64() / reps as f64;
        let mut best = String::new();
        for rt in [32usize, 64, 96, 128, 192, 256] {
            let params = faer::linalg::cholesky::llt::factor::LltParams {
                recursion_threshold: rt,
                blocksize: 128,
                ..faer::Auto::<f64>::auto()
            };
            let t = Instant::now();
            for _ in 0..reps {
                let mut b = fm.clone();
                let mut mem = faer::dyn_stack::MemBuffer::new(
                    faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
                        n,
                        faer::Par::Seq,
                        params.into(),
                    ),
                );
                faer::linalg::cholesky::llt::factor::cholesky_in_place(
                    b.as_mut(),
                    Default::default(),
                    faer::Par::Seq,
                    faer::dyn_stack::MemStack::new(&mut mem),
                    params.into(),
                )
                .unwrap();
            }
            best.push_str(&format!(
                " rt{rt}: {:.1}",
                t.elapsed().as_secs_f64() / reps as f64 * 1e6
            ));
        }
        println!(
            "n {n}: naive {:.1} us, faer {:.1} us;{best}",
            tn * 1e6,
            tf * 1e6
        );
    }
}
