//! A uniform grid of cells over a set of points, which finds the points within a distance of
//! a query point among those near it rather than among all of them.
//!
//! A mesh's curvature fit and reference normal look at the vertices and triangle centres
//! around one surface point; scanning the whole smooth region instead made a
//! million-triangle mesh take a minute.
//!
//! The grid keeps only indices: the caller gives each point's position when it builds the grid
//! and again when it queries, so that a distance is computed from the caller's own numbers
//! (`(p - q).norm()`, bit for bit what a scan of every point computes).

use nalgebra::Vector3;

/// Cells per point at most (the grid spans the points' bounding box; a surface fills few of
/// its cells).
const CELLS_PER_POINT: usize = 2;

/// A uniform grid of cubic cells over points `0..n`, each listed in the cell holding it.
#[derive(Debug, Clone, PartialEq)]
pub struct PointGrid {
    /// The lower corner of the grid, m.
    origin_m: Vector3<f64>,
    /// The side of a cell, m.
    cell_m: f64,
    /// Cells along x, y and z.
    dims: [usize; 3],
    /// Where each cell's points start in `items` (one more entry than cells).
    starts: Vec<u32>,
    /// The points' indices by cell, ascending within a cell.
    items: Vec<u32>,
    /// The diagonal of the points' bounding box, m: no two points are farther apart.
    span_m: f64,
}

impl PointGrid {
    /// The grid over the `n` points whose positions `at` gives (finite, m), with about one cell
    /// per point over their bounding box.
    pub fn new(n: usize, at: impl Fn(u32) -> Vector3<f64>) -> PointGrid {
        let (mut lo, mut hi) = (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN));
        for i in 0..n as u32 {
            let p = at(i);
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
        if n == 0 {
            (lo, hi) = (Vector3::zeros(), Vector3::zeros());
        }
        let extent = hi - lo;
        let span_m = extent.norm();
        let largest = extent.max();
        // Cells of the side that gives one per point in the box, grown while there are more
        // than CELLS_PER_POINT a point (a flat or thin box).
        let volume: f64 = extent.iter().map(|e| e.max(largest * 1e-3)).product();
        let mut cell_m = (volume / n.max(1) as f64).cbrt();
        if !(cell_m > 0.0 && cell_m.is_finite()) {
            cell_m = largest.max(1.0);
        }
        let dims_of = |c: f64| extent.map(|e| (e / c).floor() as usize + 1);
        let mut dims = dims_of(cell_m);
        let most = CELLS_PER_POINT * n.max(1);
        while dims
            .iter()
            .try_fold(1usize, |m, &d| m.checked_mul(d))
            .is_none_or(|c| c > most)
        {
            cell_m *= 1.5;
            dims = dims_of(cell_m);
        }
        let dims = [dims.x, dims.y, dims.z];
        let mut grid = PointGrid {
            origin_m: lo,
            cell_m,
            dims,
            starts: Vec::new(),
            items: Vec::new(),
            span_m,
        };
        let cells: Vec<usize> = (0..n as u32).map(|i| grid.cell_of(&at(i))).collect();
        let mut starts = vec![0u32; dims[0] * dims[1] * dims[2] + 1];
        for &c in &cells {
            starts[c + 1] += 1;
        }
        for c in 1..starts.len() {
            starts[c] += starts[c - 1];
        }
        let mut next = starts.clone();
        let mut items = vec![0u32; n];
        for (i, &c) in cells.iter().enumerate() {
            items[next[c] as usize] = i as u32;
            next[c] += 1;
        }
        grid.starts = starts;
        grid.items = items;
        grid
    }

    /// The side of a cell, m.
    pub fn cell_m(&self) -> f64 {
        self.cell_m
    }

    /// The diagonal of the points' bounding box, m.
    pub fn span_m(&self) -> f64 {
        self.span_m
    }

    /// The cell index along each axis of the point `p` (clamped into the grid).
    fn cell_coords(&self, p: &Vector3<f64>) -> [usize; 3] {
        let mut c = [0; 3];
        for k in 0..3 {
            let x = ((p[k] - self.origin_m[k]) / self.cell_m).floor();
            c[k] = if x > 0.0 {
                (x as usize).min(self.dims[k] - 1)
            } else {
                0
            };
        }
        c
    }

    /// The cell holding `p`.
    fn cell_of(&self, p: &Vector3<f64>) -> usize {
        let [i, j, k] = self.cell_coords(p);
        (i * self.dims[1] + j) * self.dims[2] + k
    }

    /// Calls `visit(i, d)` for every point `i` at a distance `d = (p_i - q).norm()` of at most
    /// `radius_m` from `q` (`at` giving the positions the grid was built with), in no
    /// particular order. A NaN radius visits none.
    pub fn within(
        &self,
        q: &Vector3<f64>,
        radius_m: f64,
        at: impl Fn(u32) -> Vector3<f64>,
        mut visit: impl FnMut(u32, f64),
    ) {
        if radius_m.is_nan() || radius_m < 0.0 {
            return;
        }
        // The box of cells searched is a little wider than the ball, so that no rounding of
        // its corners leaves out a point at the distance exactly.
        let r = Vector3::repeat(radius_m * (1.0 + 1e-9) + 1e-9 * self.cell_m);
        let (lo, hi) = (self.cell_coords(&(q - r)), self.cell_coords(&(q + r)));
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                let row = (i * self.dims[1] + j) * self.dims[2];
                let (a, b) = (self.starts[row + lo[2]], self.starts[row + hi[2] + 1]);
                for &p in &self.items[a as usize..b as usize] {
                    let d = (at(p) - q).norm();
                    if d <= radius_m {
                        visit(p, d);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a sphere, a plane and a line: every ball query finds exactly the points a scan
    /// of all of them finds, with the same distances.
    #[test]
    fn a_ball_query_finds_what_a_scan_finds() {
        let sphere: Vec<Vector3<f64>> = (0..2000)
            .map(|k| {
                let (a, b) = (k as f64 * 0.7, k as f64 * 1.3);
                Vector3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * 0.05
            })
            .collect();
        let plane: Vec<Vector3<f64>> = (0..900)
            .map(|k| Vector3::new((k % 30) as f64 * 1e-3, (k / 30) as f64 * 1e-3, 0.0))
            .collect();
        let line: Vec<Vector3<f64>> = (0..50).map(|k| Vector3::new(0.0, 0.0, k as f64)).collect();
        let single = vec![Vector3::new(1.0, 2.0, 3.0)];
        for points in [sphere, plane, line, single] {
            let grid = PointGrid::new(points.len(), |i| points[i as usize]);
            for (q, r) in [
                (points[0], 0.0),
                (points[points.len() / 2], 3e-3),
                (points[points.len() - 1] * 1.01, 0.02),
                (Vector3::new(5.0, -5.0, 5.0), 1e3),
                (Vector3::new(0.01, 0.01, 0.0), f64::INFINITY),
            ] {
                let mut got = Vec::new();
                grid.within(&q, r, |i| points[i as usize], |i, d| got.push((i, d)));
                got.sort_by_key(|x| x.0);
                let want: Vec<(u32, f64)> = (0..points.len() as u32)
                    .map(|i| (i, (points[i as usize] - q).norm()))
                    .filter(|x| x.1 <= r)
                    .collect();
                assert_eq!(got, want, "{q:?} {r}");
            }
            let mut none = 0;
            grid.within(
                &points[0],
                f64::NAN,
                |i| points[i as usize],
                |_, _| none += 1,
            );
            assert_eq!(none, 0);
        }
    }
}
