//! Triangle meshes built here, independently of the code under test, for the mesh-geometry
//! tests of `tests/shapes.rs`: boxes tessellated in several ways (grids, fans, slivers),
//! tessellated cylinders (fan caps or CAD-style caps of slivers from one rim vertex), a
//! latitude-longitude sphere, and open meshes. Every closed mesh is wound counter-clockwise
//! seen from outside; the vertices where faces meet are computed from the same numbers, so
//! they coincide exactly.
#![allow(dead_code)]

use std::f64::consts::PI;

use grasp_model::TriangleMesh;

/// A mesh being built: vertices are merged by exact coordinates as they are added.
#[derive(Default)]
pub struct Builder {
    vertices: Vec<[f64; 3]>,
    index: std::collections::HashMap<[u64; 3], u32>,
    triangles: Vec<[u32; 3]>,
}

impl Builder {
    pub fn vertex(&mut self, p: [f64; 3]) -> u32 {
        let key = p.map(|x| (x + 0.0).to_bits());
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        self.vertices.push(p);
        let i = (self.vertices.len() - 1) as u32;
        self.index.insert(key, i);
        i
    }

    pub fn triangle(&mut self, a: [f64; 3], b: [f64; 3], c: [f64; 3]) {
        let t = [self.vertex(a), self.vertex(b), self.vertex(c)];
        self.triangles.push(t);
    }

    pub fn done(self) -> TriangleMesh {
        TriangleMesh {
            vertices_m: self.vertices,
            triangles: self.triangles,
        }
    }
}

/// Breakpoints `-a = x_0 < ... < x_n = a` along one box axis: uniform, or geometric with
/// ratio `r` between neighbouring intervals (slivers where the intervals are small). The
/// ends are exactly `-a` and `a`.
pub fn breakpoints(a: f64, n: usize, ratio: f64) -> Vec<f64> {
    let weights: Vec<f64> = (0..n).map(|i| ratio.powi(i as i32)).collect();
    let total: f64 = weights.iter().sum();
    let mut x = vec![-a];
    let mut acc = 0.0;
    for w in &weights[..n - 1] {
        acc += w;
        x.push(-a + 2.0 * a * acc / total);
    }
    x.push(a);
    x
}

/// How each face of a box is cut into triangles.
#[derive(Clone, Copy, Debug)]
pub enum BoxCut {
    /// Each grid cell into two triangles along one diagonal.
    Grid,
    /// Each face a fan of triangles from its centre to the grid points on its border.
    Fan,
}

/// The box `[-a, a]` whose faces follow the breakpoints `x[k]` along axis `k` (the same on
/// every face, so the faces meet vertex to vertex), cut as `cut`.
pub fn box_mesh(x: [Vec<f64>; 3], cut: BoxCut) -> TriangleMesh {
    let mut b = Builder::default();
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        for s in [-1.0, 1.0] {
            let a_k = if s > 0.0 {
                x[k][x[k].len() - 1]
            } else {
                x[k][0]
            };
            let at = |u: f64, v: f64| {
                let mut p = [0.0; 3];
                p[k] = a_k;
                p[i] = u;
                p[j] = v;
                p
            };
            // Counter-clockwise seen from outside: (e_i, e_j) is right-handed with e_k.
            let mut tri = |p: [f64; 3], q: [f64; 3], r: [f64; 3]| {
                if s > 0.0 {
                    b.triangle(p, q, r)
                } else {
                    b.triangle(p, r, q)
                }
            };
            match cut {
                BoxCut::Grid => {
                    for u in x[i].windows(2) {
                        for v in x[j].windows(2) {
                            tri(at(u[0], v[0]), at(u[1], v[0]), at(u[1], v[1]));
                            tri(at(u[0], v[0]), at(u[1], v[1]), at(u[0], v[1]));
                        }
                    }
                }
                BoxCut::Fan => {
                    let centre = at(0.0, 0.0);
                    let (xi, xj) = (&x[i], &x[j]);
                    let (ni, nj) = (xi.len() - 1, xj.len() - 1);
                    // The border counter-clockwise in (u, v).
                    let mut border = Vec::new();
                    border.extend((0..ni).map(|m| at(xi[m], xj[0])));
                    border.extend((0..nj).map(|m| at(xi[ni], xj[m])));
                    border.extend((0..ni).map(|m| at(xi[ni - m], xj[nj])));
                    border.extend((0..nj).map(|m| at(xi[0], xj[nj - m])));
                    for m in 0..border.len() {
                        tri(centre, border[m], border[(m + 1) % border.len()]);
                    }
                }
            }
        }
    }
    b.done()
}

/// The box of half sizes `a` with `n` uniform intervals along every axis, cut as `cut`
/// (`n = 1`, grid: the 12-triangle box; `n = 10`: 1,200 triangles).
pub fn uniform_box(a: [f64; 3], n: usize, cut: BoxCut) -> TriangleMesh {
    box_mesh(a.map(|h| breakpoints(h, n, 1.0)), cut)
}

/// A box whose faces are strips of slivers: 40 intervals along x growing geometrically
/// (each 1.25 times the last: the first about 1/6,000 of the side, so triangles up to about
/// 6,000:1 long), one along y and z.
pub fn sliver_box(a: [f64; 3]) -> TriangleMesh {
    box_mesh(
        [
            breakpoints(a[0], 40, 1.25),
            breakpoints(a[1], 1, 1.0),
            breakpoints(a[2], 1, 1.0),
        ],
        BoxCut::Grid,
    )
}

/// How the end caps of a tessellated cylinder are cut.
#[derive(Clone, Copy, Debug)]
pub enum CapCut {
    /// A fan from a centre vertex.
    Centre,
    /// A fan from the first rim vertex (long thin triangles, as CAD programs write them).
    Rim,
}

/// A cylinder of radius `r` along z from `-h` to `h`: `n` segments around, `rings`
/// intervals along the side, caps cut as `cap`. The rim vertices lie on the circle.
pub fn cylinder_mesh(r: f64, h: f64, n: usize, rings: usize, cap: CapCut) -> TriangleMesh {
    let mut b = Builder::default();
    let rim = |i: usize, z: f64| {
        let a = 2.0 * PI * (i % n) as f64 / n as f64;
        [r * a.cos(), r * a.sin(), z]
    };
    let zs = breakpoints(h, rings, 1.0);
    for w in zs.windows(2) {
        for i in 0..n {
            b.triangle(rim(i, w[0]), rim(i + 1, w[0]), rim(i + 1, w[1]));
            b.triangle(rim(i, w[0]), rim(i + 1, w[1]), rim(i, w[1]));
        }
    }
    match cap {
        CapCut::Centre => {
            for i in 0..n {
                b.triangle([0.0, 0.0, h], rim(i, h), rim(i + 1, h));
                b.triangle([0.0, 0.0, -h], rim(i + 1, -h), rim(i, -h));
            }
        }
        CapCut::Rim => {
            for i in 1..n - 1 {
                b.triangle(rim(0, h), rim(i, h), rim(i + 1, h));
                b.triangle(rim(0, -h), rim(i + 1, -h), rim(i, -h));
            }
        }
    }
    b.done()
}

/// A latitude-longitude sphere of radius `r`: `n` segments around, `m` bands from pole to
/// pole.
pub fn uv_sphere(r: f64, n: usize, m: usize) -> TriangleMesh {
    let mut b = Builder::default();
    let p = |i: usize, j: usize| {
        if j == 0 {
            return [0.0, 0.0, -r];
        }
        if j == m {
            return [0.0, 0.0, r];
        }
        let (phi, theta) = (
            2.0 * PI * (i % n) as f64 / n as f64,
            -PI / 2.0 + PI * j as f64 / m as f64,
        );
        [
            r * theta.cos() * phi.cos(),
            r * theta.cos() * phi.sin(),
            r * theta.sin(),
        ]
    };
    for j in 0..m {
        for i in 0..n {
            if j > 0 {
                b.triangle(p(i, j), p(i + 1, j), p(i + 1, j + 1));
            }
            if j + 1 < m {
                b.triangle(p(i, j), p(i + 1, j + 1), p(i, j + 1));
            }
        }
    }
    b.done()
}

/// `mesh` without the triangles `drop` keeps (a face taken away).
pub fn without(mesh: &TriangleMesh, drop: impl Fn(&[[f64; 3]; 3]) -> bool) -> TriangleMesh {
    let corners = |t: &[u32; 3]| t.map(|i| mesh.vertices_m[i as usize]);
    TriangleMesh {
        vertices_m: mesh.vertices_m.clone(),
        triangles: mesh
            .triangles
            .iter()
            .filter(|t| !drop(&corners(t)))
            .copied()
            .collect(),
    }
}

/// One triangle: an open sheet.
pub fn single_triangle() -> TriangleMesh {
    TriangleMesh {
        vertices_m: vec![[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.0, 0.05, 0.0]],
        triangles: vec![[0, 1, 2]],
    }
}

/// A box mesh whose vertices are written once per face (as STL does), with one face moved
/// out by `gap` metres: a crack, so the faces around it are open.
pub fn cracked_box(a: [f64; 3], gap: f64) -> TriangleMesh {
    let closed = uniform_box(a, 1, BoxCut::Grid);
    let mut vertices_m = Vec::new();
    let mut triangles = Vec::new();
    for t in &closed.triangles {
        let mut c = t.map(|i| closed.vertices_m[i as usize]);
        if c.iter().all(|p| p[2] == a[2]) {
            for p in &mut c {
                p[2] += gap;
            }
        }
        let base = vertices_m.len() as u32;
        vertices_m.extend(c);
        triangles.push([base, base + 1, base + 2]);
    }
    TriangleMesh {
        vertices_m,
        triangles,
    }
}

/// `mesh` with every triangle wound the other way (clockwise seen from outside).
pub fn turned_over(mesh: &TriangleMesh) -> TriangleMesh {
    TriangleMesh {
        vertices_m: mesh.vertices_m.clone(),
        triangles: mesh.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
    }
}

/// `mesh` with every other triangle wound the other way (an inconsistent file).
pub fn scrambled(mesh: &TriangleMesh) -> TriangleMesh {
    TriangleMesh {
        vertices_m: mesh.vertices_m.clone(),
        triangles: mesh
            .triangles
            .iter()
            .enumerate()
            .map(|(k, t)| if k % 2 == 1 { [t[0], t[2], t[1]] } else { *t })
            .collect(),
    }
}
