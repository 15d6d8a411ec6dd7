//! Triangle meshes: the data a mesh file gives ([`TriangleMesh`], read by the I/O layer),
//! its volume integrals, and the surface queries of a mesh object ([`MeshSurface`]): closest
//! point and ray hits through parry's bounding-volume tree; on a flat region (a face bounded
//! by sharp edges, [`crate::geometry::mesh_topology`]) the region's exact normal; elsewhere the
//! normal, principal directions and curvatures estimated by a least-squares quadric fit to the
//! vertices of the point's smooth region around it (the osculating paraboloid; do Carmo 3-3,
//! the shape operator of a graph `z = f(x, y)` from its first and second fundamental forms),
//! so that no fit reaches across a sharp edge; and points on sharp edges and corners marked as
//! such, as on the primitives.

use nalgebra::{DMatrix, DVector, Matrix2, Vector3};
use parry3d_f64::math::Vector as PVec;
use parry3d_f64::query::{PointQueryWithLocation, Ray, RayCast};
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

use crate::geometry::mesh_topology::{MeshDefects, MeshTopology};
use crate::geometry::point_grid::PointGrid;
use crate::geometry::surface_point::{perpendicular, SurfaceFeature, SurfacePoint};

/// A triangle mesh in metres (local frame of the shape), triangles counter-clockwise seen
/// from outside (a mesh wound the other way is turned over on load).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions, m.
    pub vertices_m: Vec<[f64; 3]>,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Volume, m^3, and centroid, m, of the closed surface (divergence theorem: a signed
    /// tetrahedron from the origin per triangle; Zhang and Chen 2001). The volume is negative
    /// when the triangles are wound clockwise seen from outside.
    pub fn volume_and_centroid(&self) -> (f64, Vector3<f64>) {
        let mut volume = 0.0;
        let mut moment = Vector3::zeros();
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| Vector3::from(self.vertices_m[i as usize]));
            let v = a.dot(&b.cross(&c)) / 6.0;
            volume += v;
            moment += (a + b + c) * (v / 4.0);
        }
        let centroid = if volume != 0.0 {
            moment / volume
        } else {
            Vector3::zeros()
        };
        (volume, centroid)
    }
}

/// Fewest vertices of the curvature fit around a point.
pub const FIT_VERTICES: usize = 12;

/// A point within this fraction of the mesh's size (its largest half extent) of a sharp
/// edge is on the edge, as on a primitive box (`1e-9` of its largest half side).
pub const EDGE_TOLERANCE: f64 = 1e-9;

/// A mesh object ready for queries.
#[derive(Debug, Clone)]
pub struct MeshSurface {
    mesh: TriangleMesh,
    trimesh: TriMesh,
    topology: MeshTopology,
    vertices: Vec<Vector3<f64>>,
    /// The vertices by place (the curvature fit's neighbourhood).
    vertex_grid: PointGrid,
    /// The used triangles' centres by place (the fit's reference normal).
    centre_grid: PointGrid,
    /// Distance within which a point is on a sharp edge, m ([`EDGE_TOLERANCE`]).
    edge_tolerance_m: f64,
}

fn pv(v: &Vector3<f64>) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

fn nv(v: PVec) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

impl MeshSurface {
    /// Prepares `mesh`: vertices at the same place merged, each connected part wound alike
    /// and outward (triangles turned over where needed, [`MeshTopology`]), the sharp edges
    /// and smooth regions found.
    pub fn new(mut mesh: TriangleMesh) -> Result<MeshSurface, String> {
        check_indices_and_numbers(&mesh)?;
        let vertices: Vec<Vector3<f64>> =
            mesh.vertices_m.iter().map(|v| Vector3::from(*v)).collect();
        let topology = MeshTopology::new(&vertices, &mesh.triangles);
        if topology.triangles.is_empty() {
            return Err("has no triangle with three distinct vertices".into());
        }
        for (&k, &turned) in topology.source.iter().zip(&topology.turned) {
            if turned {
                mesh.triangles[k].swap(1, 2);
            }
        }
        let trimesh = TriMesh::with_flags(
            vertices.iter().map(pv).collect(),
            topology.triangles.clone(),
            TriMeshFlags::ORIENTED,
        )
        .map_err(|e| format!("is not a usable triangle mesh: {e}"))?;
        let size_m = (0..3)
            .map(|c| {
                let (lo, hi) = vertices.iter().fold((f64::MAX, f64::MIN), |(lo, hi), v| {
                    (lo.min(v[c]), hi.max(v[c]))
                });
                (hi - lo) / 2.0
            })
            .fold(0.0, f64::max);
        let vertex_grid = PointGrid::new(vertices.len(), |i| vertices[i as usize]);
        let centre_grid = PointGrid::new(topology.triangles.len(), |t| {
            triangle_centre(&vertices, &topology.triangles[t as usize])
        });
        Ok(MeshSurface {
            mesh,
            trimesh,
            topology,
            vertices,
            vertex_grid,
            centre_grid,
            edge_tolerance_m: EDGE_TOLERANCE * size_m,
        })
    }

    /// The mesh as read, each triangle wound outward.
    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    /// Why the mesh does not bound a solid, if it does not.
    pub fn defects(&self) -> MeshDefects {
        self.topology.defects
    }

    /// The surface point closest to `p` (local frame): on a flat region (a face bounded by
    /// sharp edges) its exact normal and no curvature; elsewhere the geometry fitted to the
    /// vertices of its smooth region (a quadric fit). Within [`EDGE_TOLERANCE`] of
    /// a sharp edge the point is on an edge (three sharp edges at a vertex: a corner).
    pub fn closest(&self, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
        if !p.iter().all(|x| x.is_finite()) {
            return Err("is not a finite point".into());
        }
        let (proj, (triangle, _)) = self
            .trimesh
            .project_local_point_and_get_location(pv(p), false);
        let q = nv(proj.point);
        let region = self.topology.region_of[triangle as usize] as usize;
        let mut s = match self.topology.regions[region].flat_normal {
            Some(n) => flat_point(&q, &n),
            None => self.fit_at(&q, triangle as usize)?,
        };
        s.feature = self.feature_at(&q, region);
        let sign = if proj.is_inside { -1.0 } else { 1.0 };
        s.distance_m = sign * (p - q).norm();
        Ok(s)
    }

    /// Distance within which a point is on a sharp edge, m ([`EDGE_TOLERANCE`] of the mesh's
    /// size).
    pub fn edge_tolerance_m(&self) -> f64 {
        self.edge_tolerance_m
    }

    /// Ray parameter of the first hit of `o + t d` (`d` unit), if any.
    pub fn ray_hit(&self, o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
        self.trimesh
            .cast_local_ray(&Ray::new(pv(o), pv(d)), f64::MAX, true)
    }

    /// The sharp edges bounding the smooth region of the surface point closest to `p`
    /// (local) that pass within `radius_m` of it, as segments (local, m).
    pub fn region_edges_near(&self, p: &Vector3<f64>, radius_m: f64) -> Vec<[Vector3<f64>; 2]> {
        let (proj, (triangle, _)) = self
            .trimesh
            .project_local_point_and_get_location(pv(p), false);
        let q = nv(proj.point);
        let region = self.topology.region_of[triangle as usize] as usize;
        self.topology.regions[region]
            .boundary
            .iter()
            .map(|e| e.map(|v| self.vertices[v as usize]))
            .filter(|[a, b]| segment_distance(&q, a, b) <= radius_m)
            .collect()
    }

    /// Face, edge or corner: the point `q` of `region` is on an edge within the edge
    /// tolerance of a sharp edge bounding the region, on a corner within it of a vertex of
    /// that edge where three or more sharp edges meet.
    fn feature_at(&self, q: &Vector3<f64>, region: usize) -> SurfaceFeature {
        let tol = self.edge_tolerance_m;
        let mut feature = SurfaceFeature::Face;
        for e in &self.topology.regions[region].boundary {
            let [a, b] = e.map(|v| self.vertices[v as usize]);
            if segment_distance(q, &a, &b) > tol {
                continue;
            }
            feature = SurfaceFeature::Edge;
            let corner = e.iter().any(|&v| {
                self.topology.sharp_at_vertex[v as usize] >= 3
                    && (self.vertices[v as usize] - q).norm() <= tol
            });
            if corner {
                return SurfaceFeature::Vertex;
            }
        }
        feature
    }

    /// The vertices of the smooth `region` used for the fit at `q`: those on the same side
    /// of the surface as the triangle `q` lies on (`facing` its normal; not the far side of
    /// a tube or a thin shell, which may be as near), within 1.5 local edge lengths (the mean
    /// length of the region's edges at its vertex nearest `q`), and at least the
    /// [`FIT_VERTICES`] nearest (nearer first, ties by index). A wider neighbourhood feels the
    /// surface's higher-order terms: on a sphere the quadric's error grows like
    /// (radius / R)^2.
    ///
    /// Only the vertices near `q` are looked at (the vertex grid, searched in a ball grown
    /// until it holds enough): every vertex of the region nearer than the farthest one taken
    /// is in the ball, so the vertices are those a scan of the whole region would take.
    fn neighbourhood(
        &self,
        q: &Vector3<f64>,
        region: usize,
        facing: &Vector3<f64>,
    ) -> Vec<Vector3<f64>> {
        // The region's vertices facing alike within `reach` of `q`, nearer first.
        let within = |reach: f64| -> Vec<(f64, u32)> {
            let mut found = Vec::new();
            let at = |i: u32| self.vertices[i as usize];
            self.vertex_grid.within(q, reach, at, |i, d| {
                if self.region_vertex_normal(i, region).dot(facing) > 0.0 {
                    found.push((d, i));
                }
            });
            found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            found
        };
        let mut reach = self.vertex_grid.cell_m();
        let mut by_distance = within(reach);
        while by_distance.len() < FIT_VERTICES && reach < self.vertex_grid.span_m() {
            reach *= 2.0;
            by_distance = within(reach);
        }
        let radius = 1.5
            * by_distance
                .first()
                .map_or(0.0, |&(_, i)| self.region_edge_m(i, region));
        if radius > reach {
            by_distance = within(radius);
        }
        let n = by_distance
            .iter()
            .take_while(|(d, _)| *d <= radius)
            .count()
            .max(FIT_VERTICES);
        by_distance
            .into_iter()
            .take(n)
            .map(|(_, i)| self.vertices[i as usize])
            .collect()
    }

    /// Sum of the unit normals of `region`'s triangles at vertex `v`.
    fn region_vertex_normal(&self, v: u32, region: usize) -> Vector3<f64> {
        self.topology.vertex_triangles[v as usize]
            .iter()
            .filter(|&&t| self.topology.region_of[t as usize] as usize == region)
            .map(|&t| self.topology.normals[t as usize])
            .sum()
    }

    /// Mean length of the edges of `region`'s triangles at vertex `v`, m.
    fn region_edge_m(&self, v: u32, region: usize) -> f64 {
        let (mut total, mut count) = (0.0, 0usize);
        for &t in &self.topology.vertex_triangles[v as usize] {
            if self.topology.region_of[t as usize] as usize != region {
                continue;
            }
            for &w in &self.topology.triangles[t as usize] {
                if w != v {
                    total += (self.vertices[w as usize] - self.vertices[v as usize]).norm();
                    count += 1;
                }
            }
        }
        total / count.max(1) as f64
    }

    /// Area-weighted normal of the triangles of `region` around `q` (outward): weights
    /// falling off beyond `radius`, none beyond twice it. The triangles are those whose
    /// centres the centre grid finds within twice the radius, summed in the region's order
    /// (a triangle farther away adds an exact zero to a scan of the whole region).
    fn reference_normal(&self, q: &Vector3<f64>, radius: f64, region: usize) -> Vector3<f64> {
        let mut near = Vec::new();
        let centre = |t: u32| triangle_centre(&self.vertices, &self.topology.triangles[t as usize]);
        self.centre_grid.within(q, 2.0 * radius, centre, |t, _| {
            if self.topology.region_of[t as usize] as usize == region {
                near.push(t);
            }
        });
        near.sort_unstable();
        let mut n = Vector3::zeros();
        for t in near {
            let [a, b, c] = self.topology.triangles[t as usize].map(|i| self.vertices[i as usize]);
            let centre = (a + b + c) / 3.0;
            let w = 1.0 / (1.0 + ((centre - q).norm() / radius).powi(2));
            n += (b - a).cross(&(c - a)) * w * f64::from((centre - q).norm() <= 2.0 * radius);
        }
        n.normalize()
    }

    /// Normal, principal directions and curvatures at the surface point `q` of `triangle`
    /// (in a smooth region) from a height function `w = f(u, v)` fitted to the region's vertices nearby,
    /// in a frame `(u, v, w)` with `w` along the reference normal ([`height_fit`]): vertices
    /// beyond a sharp edge are not on this surface and are not used. When the neighbourhood
    /// is wide against the curvature it finds (long thin CAD facets force that: the nearest
    /// vertices may be far along a facet), the fit is repeated on the vertices within about
    /// 30 degrees of arc of `q` by that first estimate (`|h| k_max <= 1/8`, `h` its quadratic
    /// height), if at least [`FIT_VERTICES`] remain: further round, the surface turns away
    /// and a polynomial over the tangent plane no longer follows it.
    fn fit_at(&self, q: &Vector3<f64>, triangle: usize) -> Result<SurfacePoint, String> {
        let region = self.topology.region_of[triangle] as usize;
        let near = self.neighbourhood(q, region, &self.topology.normals[triangle]);
        let radius = near.iter().map(|p| (p - q).norm()).fold(0.0, f64::max);
        let w = self.reference_normal(q, radius, region);
        if !w.iter().all(|x| x.is_finite()) {
            return Err("lies where the mesh has no usable normal".into());
        }
        let offsets: Vec<Vector3<f64>> = near.iter().map(|p| p - q).collect();
        let first = height_fit(&offsets, &w)?;
        let k_max = first.hessian_norm();
        // Within the window (widened while it holds too few vertices: the first estimate
        // errs high on a wide neighbourhood), and on the surface the first fit describes (not,
        // say, the centre of a cylinder's end cap, level with the side's vertices but far
        // below them).
        let window = |scale: f64| -> Vec<Vector3<f64>> {
            offsets
                .iter()
                .filter(|d| {
                    let inside = (first.quadratic_part(d) * k_max).abs() <= scale * ARC_WINDOW;
                    inside && (d.dot(&w) - first.value(d)).abs() * k_max <= scale * ARC_WINDOW
                })
                .copied()
                .collect()
        };
        let local = [1.0, 2.0, 4.0]
            .into_iter()
            .map(window)
            .find(|l| l.len() >= FIT_VERTICES);
        let fit = match local {
            Some(l) if k_max > 0.0 && l.len() < offsets.len() => height_fit(&l, &w)?,
            _ => first,
        };
        Ok(graph_geometry(
            q,
            [fit.u, fit.v, w],
            [fit.c[1], fit.c[2]],
            [2.0 * fit.c[3], fit.c[4], 2.0 * fit.c[5]],
        ))
    }
}

/// Largest `|h| k_max` of a vertex in the second pass of the curvature fit (`h` the first
/// fit's quadratic height there; on a circle of curvature `k`, `h k = 1/8` at 30 degrees of
/// arc), and largest `|h - f| k_max` (`f` the first fit's height: a vertex off the surface it
/// describes is left out).
const ARC_WINDOW: f64 = 0.125;

/// Singular values below this fraction of the largest count as zero in [`fit_terms`]
/// (columns scaled to unit length). The vertices lie on the true surface, which departs
/// from the fitted quadric by a few per cent of its quadratic height within the fit's
/// window (the quartic term: `(arc)^2 / 12`, 2 % at 30 degrees); a term the vertices set
/// apart from the others by less than 1e-3 would carry that departure magnified a
/// thousandfold. At 1e-8 (round-off only), two rows of vertices seen slightly askew (the
/// rims of long facets, 1 mm below one rim) kept `u^2` and tilted the normal by 90 degrees.
const RANK_TOLERANCE: f64 = 1e-3;

/// A quadric height function over the tangent plane: axes and the coefficients of
/// `1, u, v, u^2, uv, v^2` (zero where the term was not fitted).
struct HeightFit {
    u: Vector3<f64>,
    v: Vector3<f64>,
    c: [f64; 6],
}

impl HeightFit {
    /// The fitted height at offset `d`.
    fn value(&self, d: &Vector3<f64>) -> f64 {
        let (x, y) = (d.dot(&self.u), d.dot(&self.v));
        self.c[0] + self.c[1] * x + self.c[2] * y + self.quadratic_part(d)
    }

    /// The quadratic part `c3 u^2 + c4 uv + c5 v^2` at offset `d`.
    fn quadratic_part(&self, d: &Vector3<f64>) -> f64 {
        let (x, y) = (d.dot(&self.u), d.dot(&self.v));
        self.c[3] * x * x + self.c[4] * x * y + self.c[5] * y * y
    }

    /// The largest absolute eigenvalue of the Hessian at the origin, 1/m (about the largest
    /// principal curvature).
    fn hessian_norm(&self) -> f64 {
        let h = Matrix2::new(2.0 * self.c[3], self.c[4], self.c[4], 2.0 * self.c[5]);
        let e = h.symmetric_eigen().eigenvalues;
        e[0].abs().max(e[1].abs())
    }
}

/// Least-squares quadric height function through `offsets` (vertex minus surface point; `w`
/// the normal) in the axes of their spread ([`spread_axes`]), each term kept only if the
/// vertices can tell it from the terms before it ([`fit_terms`]).
fn height_fit(offsets: &[Vector3<f64>], w: &Vector3<f64>) -> Result<HeightFit, String> {
    let (u, v) = spread_axes(offsets, w);
    let mut a = DMatrix::zeros(offsets.len(), 6);
    let mut b = DVector::zeros(offsets.len());
    for (r, d) in offsets.iter().enumerate() {
        let (x, y) = (d.dot(&u), d.dot(&v));
        for (c, val) in [1.0, x, y, x * x, x * y, y * y].iter().enumerate() {
            a[(r, c)] = *val;
        }
        b[r] = d.dot(w);
    }
    // Columns scaled to unit size so the rank test and the SVD's cut-off treat every order
    // alike.
    let scales: Vec<f64> = (0..6)
        .map(|c| a.column(c).norm().max(f64::MIN_POSITIVE))
        .collect();
    for (c, s) in scales.iter().enumerate() {
        a.column_mut(c).scale_mut(1.0 / s);
    }
    let terms = fit_terms(&a);
    let design = DMatrix::from_fn(offsets.len(), terms.len(), |r, j| a[(r, terms[j])]);
    let solved = design
        .svd(true, true)
        .solve(&b, 1e-12)
        .map_err(|e| format!("curvature fit failed: {e}"))?;
    let mut c = [0.0; 6];
    for (j, &t) in terms.iter().enumerate() {
        c[t] = solved[j] / scales[t];
    }
    Ok(HeightFit { u, v, c })
}

/// The columns of the (scaled) design `a` the fit uses, in order: each term is kept only if
/// it adds rank to the terms before it. A term that adds no rank is an alias the vertices
/// cannot tell apart: on two rows of vertices (the rims of long facets) at `u = +-a`, `u^2`
/// is a multiple of the constant, and fitting both would put an arbitrary curvature across
/// the rows (it stays zero: nothing there says otherwise).
fn fit_terms(a: &DMatrix<f64>) -> Vec<usize> {
    let rank = |cols: &[usize]| -> usize {
        let m = DMatrix::from_fn(a.nrows(), cols.len(), |r, j| a[(r, cols[j])]);
        let sv = m.singular_values();
        let top = sv.max();
        sv.iter().filter(|s| **s > RANK_TOLERANCE * top).count()
    };
    let mut terms = Vec::with_capacity(a.ncols());
    let mut have = 0;
    for t in 0..a.ncols() {
        terms.push(t);
        let r = rank(&terms);
        if r > have {
            have = r;
        } else {
            terms.pop();
        }
    }
    terms
}

/// Tangent axes `(u, v)` (with `w` right-handed) along the principal directions of the
/// offsets' spread in the tangent plane (their covariance about their mean), `u` the wider:
/// the fit's frame follows the sampling, so that on two rows of vertices the aliased terms
/// are whole terms ([`fit_terms`]). About the mean, not the surface point: two rows holding
/// the same positions along them (the rims of long facets) have no covariance across, so
/// the axes lie along the rows wherever the point is between them.
fn spread_axes(offsets: &[Vector3<f64>], w: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let u0 = perpendicular(w);
    let v0 = w.cross(&u0);
    let plane: Vec<(f64, f64)> = offsets.iter().map(|d| (d.dot(&u0), d.dot(&v0))).collect();
    let count = plane.len().max(1) as f64;
    let mean_x = plane.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = plane.iter().map(|p| p.1).sum::<f64>() / count;
    let mut cov = Matrix2::zeros();
    for (x, y) in plane {
        let (x, y) = (x - mean_x, y - mean_y);
        cov += Matrix2::new(x * x, x * y, x * y, y * y);
    }
    let eig = cov.symmetric_eigen();
    let i = if eig.eigenvalues[0] >= eig.eigenvalues[1] {
        0
    } else {
        1
    };
    let e = eig.eigenvectors.column(i);
    let u = (u0 * e[0] + v0 * e[1]).normalize();
    if !u.iter().all(|c| c.is_finite()) {
        return (u0, v0);
    }
    (u, w.cross(&u))
}

/// Geometry of the graph `w = f(u, v)` at the origin from its gradient `[fu, fv]` and
/// Hessian `[fuu, fuv, fvv]` (shape operator `S = I^-1 II`; do Carmo 3-3). `w` points out.
fn graph_geometry(
    q: &Vector3<f64>,
    [u, v, w]: [Vector3<f64>; 3],
    [fu, fv]: [f64; 2],
    [fuu, fuv, fvv]: [f64; 3],
) -> SurfacePoint {
    let len = (1.0 + fu * fu + fv * fv).sqrt();
    let normal = ((w - u * fu - v * fv) / len).normalize();
    let first = Matrix2::new(1.0 + fu * fu, fu * fv, fu * fv, 1.0 + fv * fv);
    let second = Matrix2::new(fuu, fuv, fuv, fvv) / len;
    let shape = first.try_inverse().unwrap_or_else(Matrix2::identity) * second;
    // S is self-adjoint in the first form: eigen-decompose the symmetric I^-1/2 II I^-1/2.
    let eig = shape.complex_eigenvalues();
    let mut ks = [eig[0].re, eig[1].re];
    // Outward normal: a convex surface curves down (f'' < 0), so convex curvature is -k.
    ks = [-ks[0], -ks[1]];
    let order = if ks[0] >= ks[1] { [0, 1] } else { [1, 0] };
    let k1 = ks[order[0]];
    let dir_param = principal_direction(&shape, -k1);
    let tangent = (u + w * fu) * dir_param.0 + (v + w * fv) * dir_param.1;
    let d1 = (tangent - normal * normal.dot(&tangent)).normalize();
    let d1 = if d1.iter().all(|x| x.is_finite()) {
        d1
    } else {
        perpendicular(&normal)
    };
    SurfacePoint {
        point_m: *q,
        outward_normal: normal,
        directions: [d1, normal.cross(&d1)],
        curvatures_per_m: [k1, ks[order[1]]],
        feature: SurfaceFeature::Face,
        distance_m: 0.0,
    }
}

/// A parameter-space eigenvector `(du, dv)` of `shape` for eigenvalue `lambda`.
fn principal_direction(shape: &Matrix2<f64>, lambda: f64) -> (f64, f64) {
    let m = shape - Matrix2::identity() * lambda;
    // Null vector of the 2x2 `m`: perpendicular to its larger row.
    let (r0, r1) = (m.row(0), m.row(1));
    let row = if r0.norm() >= r1.norm() { r0 } else { r1 };
    if row.norm() < 1e-12 * (1.0 + shape.norm()) {
        return (1.0, 0.0); // umbilic: every direction is principal
    }
    (-row[1], row[0])
}

/// Refuses a mesh without triangles, with a vertex that is not a finite number, or with a
/// triangle naming a vertex it does not have.
fn check_indices_and_numbers(mesh: &TriangleMesh) -> Result<(), String> {
    if mesh.triangles.is_empty() {
        return Err("has no triangles".into());
    }
    if let Some(i) = mesh
        .vertices_m
        .iter()
        .position(|v| !v.iter().all(|x| x.is_finite()))
    {
        return Err(format!(
            "has a vertex that is not a finite number (vertex {})",
            i + 1
        ));
    }
    let count = mesh.vertices_m.len();
    match mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i as usize >= count))
    {
        Some(t) => Err(format!(
            "triangle {} names a vertex the mesh does not have",
            t + 1
        )),
        None => Ok(()),
    }
}

/// A point of a flat region: the region's normal, no curvature.
fn flat_point(q: &Vector3<f64>, n: &Vector3<f64>) -> SurfacePoint {
    let d1 = perpendicular(n);
    SurfacePoint {
        point_m: *q,
        outward_normal: *n,
        directions: [d1, n.cross(&d1)],
        curvatures_per_m: [0.0, 0.0],
        feature: SurfaceFeature::Face,
        distance_m: 0.0,
    }
}

/// The centre of triangle `t`, `(a + b + c) / 3`, m.
fn triangle_centre(vertices: &[Vector3<f64>], t: &[u32; 3]) -> Vector3<f64> {
    let [a, b, c] = t.map(|i| vertices[i as usize]);
    (a + b + c) / 3.0
}

/// Distance of `q` from the segment `a b`, m.
fn segment_distance(q: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((q - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q - (a + ab * t)).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed sphere of radius `r`, m: `nu` meridians by `nv` bands, `2 nu (nv - 1)`
    /// triangles wound outward.
    fn uv_sphere(r: f64, nu: usize, nv: usize) -> TriangleMesh {
        use std::f64::consts::PI;
        let mut vertices_m = vec![[0.0, 0.0, r]];
        for j in 1..nv {
            let th = PI * j as f64 / nv as f64;
            for i in 0..nu {
                let ph = 2.0 * PI * i as f64 / nu as f64;
                vertices_m.push([
                    r * th.sin() * ph.cos(),
                    r * th.sin() * ph.sin(),
                    r * th.cos(),
                ]);
            }
        }
        vertices_m.push([0.0, 0.0, -r]);
        let at = |j: usize, i: usize| (1 + (j - 1) * nu + i % nu) as u32;
        let south = (vertices_m.len() - 1) as u32;
        let mut triangles = Vec::new();
        for i in 0..nu {
            triangles.push([0, at(1, i), at(1, i + 1)]);
            triangles.push([at(nv - 1, i), south, at(nv - 1, i + 1)]);
            for j in 1..nv - 1 {
                triangles.push([at(j, i), at(j + 1, i), at(j + 1, i + 1)]);
                triangles.push([at(j, i), at(j + 1, i + 1), at(j, i + 1)]);
            }
        }
        TriangleMesh {
            vertices_m,
            triangles,
        }
    }

    /// A surface query on a fine mesh looks only at the vertices near the point: on a sphere of
    /// 319,200 triangles 400 queries take a fraction of a second (scanning the whole smooth
    /// region for each made a million-triangle mesh take 76 s for a 16 x 16 pinch), each
    /// finding the surface 1 % of the radius away.
    #[test]
    fn a_query_on_a_fine_mesh_does_not_scan_the_whole_surface() {
        let r = 0.04;
        let mesh = MeshSurface::new(uv_sphere(r, 400, 400)).unwrap();
        let started = std::time::Instant::now();
        for k in 0..400 {
            let (a, b) = (k as f64 * 0.37, k as f64 * 0.91);
            let p = Vector3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * (1.01 * r);
            let s = mesh.closest(&p).unwrap();
            assert!((s.distance_m - 0.01 * r).abs() < 1e-3 * r, "{k}: {s:?}");
        }
        let took = started.elapsed().as_secs_f64();
        assert!(took < 1.5, "400 queries took {took} s");
    }
}
