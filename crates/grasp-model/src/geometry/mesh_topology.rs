//! The topology of a triangle mesh that its surface queries need: vertices merged where the
//! file repeats them, one consistent outward winding per connected part, the edges where
//! the surface folds sharply (and the edges of an open or tangled mesh), the smooth regions
//! those edges bound (a box's faces, a cylinder's side and caps), and which regions are flat.
//!
//! A flat region's normal is its vector area `sum (b - a) x (c - a)` normalised: for a plane
//! polygon that is the plane's normal exactly (to round-off), whatever the triangles.

use std::collections::BTreeMap;

use nalgebra::Vector3;

/// Largest angle between the normals of two triangles that share an edge for the edge to
/// count as smooth, degrees; above it the edge is sharp (a box's 90 degrees). 40 degrees is
/// above the 30-36 degrees between the facets of the coarsest tessellations of a curved
/// surface that still say something about its curvature (10-12 segments a turn), and below a
/// 45-degree chamfer or an octagonal prism, which are polyhedra: their facets are faces.
pub const SHARP_EDGE_ANGLE_DEG: f64 = 40.0;

/// Largest distance of a region's vertex from its plane, as a fraction of the region's
/// size, for the region to count as flat. Above the round-off of single-precision
/// coordinates (STL stores `f32`: 6e-8), and small enough that anything flatter has a radius
/// above 1e5 times its size (sag `s` over size `L`: `R = L^2 / (8 s)`): flat to any patch on it.
pub const FLAT_REGION_TOLERANCE: f64 = 1e-6;

/// A triangle whose area is below this fraction of the product of two of its sides' lengths
/// (the sine of its angle) has no usable normal; its edges bound it as sharp edges.
const DEGENERATE_SINE: f64 = 1e-12;

/// What keeps a mesh from bounding a solid: its volume and mass are then not the object's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MeshDefects {
    /// Edges of one triangle only (holes, cracks, sheets).
    pub open_edges: usize,
    /// Edges shared by more than two triangles.
    pub nonmanifold_edges: usize,
    /// Edges whose two triangles cannot be wound alike (a Moebius band).
    pub misoriented_edges: usize,
}

impl MeshDefects {
    /// True when every edge joins exactly two triangles wound alike: the mesh bounds a solid.
    pub fn is_closed(&self) -> bool {
        self.open_edges + self.nonmanifold_edges + self.misoriented_edges == 0
    }

    /// The defects in words, e.g. "4 edges belong to one triangle only".
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        let mut say = |n: usize, what: &str| {
            if n > 0 {
                parts.push(format!("{n} edge{} {what}", if n == 1 { "" } else { "s" }));
            }
        };
        say(self.open_edges, "with one triangle only");
        say(self.nonmanifold_edges, "shared by more than two triangles");
        say(
            self.misoriented_edges,
            "whose triangles cannot be wound alike",
        );
        parts.join(", ")
    }
}

/// A connected part of the surface bounded by sharp edges.
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothRegion {
    /// Its triangles (indices into [`MeshTopology::triangles`]).
    pub triangles: Vec<u32>,
    /// Its vertices, each once.
    pub vertices: Vec<u32>,
    /// The unit outward normal when the region is flat ([`FLAT_REGION_TOLERANCE`]).
    pub flat_normal: Option<Vector3<f64>>,
    /// The sharp edges it is bounded by (vertex pairs).
    pub boundary: Vec<[u32; 2]>,
}

/// The topology of a mesh: triangles wound outward, their normals, regions and defects.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshTopology {
    /// The triangles used (vertices merged, triangles with a repeated vertex left out),
    /// wound outward.
    pub triangles: Vec<[u32; 3]>,
    /// Index of each used triangle in the mesh as given.
    pub source: Vec<usize>,
    /// Whether each used triangle was turned over to wind it like its neighbours and outward.
    pub turned: Vec<bool>,
    /// Unit normal of each used triangle (zero for a degenerate one).
    pub normals: Vec<Vector3<f64>>,
    /// Region of each used triangle.
    pub region_of: Vec<u32>,
    /// The smooth regions.
    pub regions: Vec<SmoothRegion>,
    /// Used triangles at each vertex.
    pub vertex_triangles: Vec<Vec<u32>>,
    /// Number of sharp edges at each vertex (3 or more: a corner).
    pub sharp_at_vertex: Vec<u32>,
    /// Why the mesh does not bound a solid, if it does not.
    pub defects: MeshDefects,
}

/// One side of an edge: the triangle and whether it runs from the lower vertex index to
/// the higher.
type EdgeSide = (u32, bool);

impl MeshTopology {
    /// The topology of the mesh `vertices` (finite), `triangles`.
    pub fn new(vertices: &[Vector3<f64>], triangles: &[[u32; 3]]) -> MeshTopology {
        let canonical = merged_vertices(vertices);
        let mut source = Vec::new();
        let mut used = Vec::new();
        for (k, t) in triangles.iter().enumerate() {
            let c = t.map(|i| canonical[i as usize]);
            if c[0] != c[1] && c[1] != c[2] && c[0] != c[2] {
                source.push(k);
                used.push(c);
            }
        }
        let turned = orient(vertices, &mut used);
        let normals: Vec<Vector3<f64>> = used.iter().map(|t| unit_normal(vertices, t)).collect();
        let edges = edge_sides(&used);
        let (region_of, sharp, defects) = classify_edges(&used, &normals, &edges);
        let mut vertex_triangles = vec![Vec::new(); vertices.len()];
        for (k, t) in used.iter().enumerate() {
            for &v in t {
                vertex_triangles[v as usize].push(k as u32);
            }
        }
        let mut sharp_at_vertex = vec![0; vertices.len()];
        for e in &sharp {
            sharp_at_vertex[e[0] as usize] += 1;
            sharp_at_vertex[e[1] as usize] += 1;
        }
        let regions = regions_of(vertices, &used, &region_of, &sharp, &edges);
        MeshTopology {
            triangles: used,
            source,
            turned,
            normals,
            region_of,
            regions,
            vertex_triangles,
            sharp_at_vertex,
            defects,
        }
    }
}

/// For each vertex, the first vertex with exactly its coordinates (`-0` equal to `0`).
fn merged_vertices(vertices: &[Vector3<f64>]) -> Vec<u32> {
    let mut first: BTreeMap<[u64; 3], u32> = BTreeMap::new();
    vertices
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let key = [v.x, v.y, v.z].map(|x| (x + 0.0).to_bits());
            *first.entry(key).or_insert(i as u32)
        })
        .collect()
}

/// Unit normal of triangle `t`, zero when it is degenerate ([`DEGENERATE_SINE`]).
fn unit_normal(vertices: &[Vector3<f64>], t: &[u32; 3]) -> Vector3<f64> {
    let [a, b, c] = t.map(|i| vertices[i as usize]);
    let (u, v) = (b - a, c - a);
    let n = u.cross(&v);
    let norm = n.norm();
    if norm > DEGENERATE_SINE * u.norm() * v.norm() && norm.is_finite() {
        n / norm
    } else {
        Vector3::zeros()
    }
}

/// The sides of every edge, keyed by its vertex pair (lower index first), in a fixed order.
fn edge_sides(triangles: &[[u32; 3]]) -> BTreeMap<[u32; 2], Vec<EdgeSide>> {
    let mut edges: BTreeMap<[u32; 2], Vec<EdgeSide>> = BTreeMap::new();
    for (k, t) in triangles.iter().enumerate() {
        for m in 0..3 {
            let (a, b) = (t[m], t[(m + 1) % 3]);
            edges
                .entry([a.min(b), a.max(b)])
                .or_default()
                .push((k as u32, a < b));
        }
    }
    edges
}

/// Winds the triangles of each connected part alike (across edges of exactly two
/// triangles: neighbours run their shared edge in opposite directions), then turns a part
/// over when its signed volume about its own centre is negative (wound inward). A part that
/// encloses no volume (a sheet) keeps the winding of its first triangle. Returns which
/// triangles were turned over.
fn orient(vertices: &[Vector3<f64>], triangles: &mut [[u32; 3]]) -> Vec<bool> {
    let edges = edge_sides(triangles);
    let mut neighbours: Vec<Vec<(u32, bool)>> = vec![Vec::new(); triangles.len()];
    for sides in edges.values() {
        if let [(p, dp), (q, dq)] = sides[..] {
            // `same`: both run the edge the same way, so one of them must be turned.
            neighbours[p as usize].push((q, dp == dq));
            neighbours[q as usize].push((p, dp == dq));
        }
    }
    let mut turn: Vec<Option<bool>> = vec![None; triangles.len()];
    let mut part = vec![0usize; triangles.len()];
    let mut parts = 0;
    for start in 0..triangles.len() {
        if turn[start].is_some() {
            continue;
        }
        turn[start] = Some(false);
        let mut stack = vec![start];
        while let Some(k) = stack.pop() {
            part[k] = parts;
            let tk = turn[k].unwrap_or(false);
            for &(q, same) in &neighbours[k] {
                if turn[q as usize].is_none() {
                    turn[q as usize] = Some(tk ^ same);
                    stack.push(q as usize);
                }
            }
        }
        parts += 1;
    }
    let mut turned: Vec<bool> = turn.iter().map(|t| t.unwrap_or(false)).collect();
    for (t, &flip) in triangles.iter_mut().zip(&turned) {
        if flip {
            t.swap(1, 2);
        }
    }
    let mut members = vec![Vec::new(); parts];
    for (k, &p) in part.iter().enumerate() {
        members[p].push(k);
    }
    for members in &members {
        if signed_volume_about_centre(vertices, triangles, members) < 0.0 {
            for &k in members {
                triangles[k].swap(1, 2);
                turned[k] = !turned[k];
            }
        }
    }
    turned
}

/// Signed volume enclosed by the triangles `members` about the mean of their vertices
/// (divergence theorem; Zhang and Chen 2001), m^3; 0 when it is below round-off of their
/// size (a flat sheet).
fn signed_volume_about_centre(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
    members: &[usize],
) -> f64 {
    let corners = || {
        members
            .iter()
            .flat_map(|&k| triangles[k].map(|i| vertices[i as usize]))
    };
    let count = 3.0 * members.len() as f64;
    let centre = corners().sum::<Vector3<f64>>() / count.max(1.0);
    let size = corners().map(|p| (p - centre).norm()).fold(0.0, f64::max);
    let volume: f64 = members
        .iter()
        .map(|&k| {
            let [a, b, c] = triangles[k].map(|i| vertices[i as usize] - centre);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum();
    if volume.abs() <= 1e-12 * size.powi(3) {
        0.0
    } else {
        volume
    }
}

/// The region of each triangle (joined across smooth edges, numbered in triangle order),
/// the sharp edges, and the defects.
fn classify_edges(
    triangles: &[[u32; 3]],
    normals: &[Vector3<f64>],
    edges: &BTreeMap<[u32; 2], Vec<EdgeSide>>,
) -> (Vec<u32>, Vec<[u32; 2]>, MeshDefects) {
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    fn root(parent: &mut [u32], mut k: u32) -> u32 {
        while parent[k as usize] != k {
            parent[k as usize] = parent[parent[k as usize] as usize];
            k = parent[k as usize];
        }
        k
    }
    let cos_sharp = SHARP_EDGE_ANGLE_DEG.to_radians().cos();
    let mut sharp = Vec::new();
    let mut defects = MeshDefects::default();
    for (&e, sides) in edges {
        match sides[..] {
            [(p, dp), (q, dq)] => {
                let (np, nq) = (normals[p as usize], normals[q as usize]);
                let usable = np != Vector3::zeros() && nq != Vector3::zeros();
                if dp == dq {
                    defects.misoriented_edges += 1;
                    sharp.push(e);
                } else if usable && np.dot(&nq) >= cos_sharp {
                    let (a, b) = (root(&mut parent, p), root(&mut parent, q));
                    parent[a.max(b) as usize] = a.min(b);
                } else {
                    sharp.push(e);
                }
            }
            [_] => {
                defects.open_edges += 1;
                sharp.push(e);
            }
            _ => {
                defects.nonmanifold_edges += 1;
                sharp.push(e);
            }
        }
    }
    let mut number = BTreeMap::new();
    let region_of = (0..triangles.len() as u32)
        .map(|k| {
            let r = root(&mut parent, k);
            let next = number.len() as u32;
            *number.entry(r).or_insert(next)
        })
        .collect();
    (region_of, sharp, defects)
}

/// The regions: triangles, vertices, boundary and flatness.
fn regions_of(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
    region_of: &[u32],
    sharp: &[[u32; 2]],
    edges: &BTreeMap<[u32; 2], Vec<EdgeSide>>,
) -> Vec<SmoothRegion> {
    let count = region_of.iter().map(|&r| r as usize + 1).max().unwrap_or(0);
    let mut regions = vec![
        SmoothRegion {
            triangles: Vec::new(),
            vertices: Vec::new(),
            flat_normal: None,
            boundary: Vec::new(),
        };
        count
    ];
    for (k, &r) in region_of.iter().enumerate() {
        let region = &mut regions[r as usize];
        region.triangles.push(k as u32);
        region.vertices.extend(triangles[k]);
    }
    for e in sharp {
        let mut seen: Vec<u32> = Vec::new();
        for &(t, _) in edges.get(e).into_iter().flatten() {
            let r = region_of[t as usize];
            if !seen.contains(&r) {
                seen.push(r);
                regions[r as usize].boundary.push(*e);
            }
        }
    }
    for region in &mut regions {
        region.vertices.sort_unstable();
        region.vertices.dedup();
        region.flat_normal = flat_normal(vertices, triangles, region);
    }
    regions
}

/// The unit normal of `region` when it is flat: its vector area normalised, if every
/// vertex lies within [`FLAT_REGION_TOLERANCE`] of its size of the plane through the first.
fn flat_normal(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
    region: &SmoothRegion,
) -> Option<Vector3<f64>> {
    let area: Vector3<f64> = region
        .triangles
        .iter()
        .map(|&k| {
            let [a, b, c] = triangles[k as usize].map(|i| vertices[i as usize]);
            (b - a).cross(&(c - a))
        })
        .sum();
    let norm = area.norm();
    let first = vertices[*region.vertices.first()? as usize];
    let size = region
        .vertices
        .iter()
        .map(|&v| (vertices[v as usize] - first).norm())
        .fold(0.0, f64::max);
    if !(norm > 0.0 && norm.is_finite() && size > 0.0) {
        return None;
    }
    let n = area / norm;
    let flat = region
        .vertices
        .iter()
        .all(|&v| (vertices[v as usize] - first).dot(&n).abs() <= FLAT_REGION_TOLERANCE * size);
    flat.then_some(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube `[0, 1]^3`: the box mesh of the tessellation, moved.
    fn cube() -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
        let mesh = crate::geometry::tessellation::box_mesh([0.5; 3]);
        let v = mesh
            .vertices_m
            .iter()
            .map(|c| Vector3::from(c.map(|x| x + 0.5)))
            .collect();
        (v, mesh.triangles)
    }

    /// A unit cube: six flat regions of two triangles, each bounded by four of the twelve
    /// sharp edges (each edge bounds two faces), three sharp edges at every corner, closed.
    #[test]
    fn a_cube_has_six_flat_faces_and_twelve_sharp_edges() {
        let (v, t) = cube();
        let m = MeshTopology::new(&v, &t);
        assert_eq!(m.regions.len(), 6);
        assert!(m.defects.is_closed());
        for r in &m.regions {
            assert_eq!(r.triangles.len(), 2);
            assert_eq!(r.boundary.len(), 4);
            let n = r.flat_normal.expect("flat");
            assert_eq!(n.abs().max(), 1.0);
        }
        assert!(m.sharp_at_vertex.iter().all(|&s| s == 3));
        assert!(m.turned.iter().all(|t| !t));
    }

    /// Every other triangle turned over: wound alike again (the same triangles as the
    /// cube's, outward); all of them turned over: turned back.
    #[test]
    fn a_tangled_or_inward_winding_is_made_outward() {
        let (v, t) = cube();
        let want = MeshTopology::new(&v, &t).triangles;
        for flip in [|k: usize| k % 2 == 1, |_| true] {
            let bad: Vec<[u32; 3]> = t
                .iter()
                .enumerate()
                .map(|(k, x)| if flip(k) { [x[0], x[2], x[1]] } else { *x })
                .collect();
            let m = MeshTopology::new(&v, &bad);
            let canon = |x: &[u32; 3]| {
                let k = (0..3).min_by_key(|&i| x[i]).unwrap_or(0);
                [x[k], x[(k + 1) % 3], x[(k + 2) % 3]]
            };
            let got: Vec<_> = m.triangles.iter().map(canon).collect();
            let exp: Vec<_> = want.iter().map(canon).collect();
            assert_eq!(got, exp);
            assert!(m.defects.is_closed());
        }
    }

    /// Without its top face the cube has four open edges; a lone triangle three.
    #[test]
    fn open_meshes_count_their_open_edges() {
        let (v, t) = cube();
        // t[2], t[3] are the face z = 1.
        let open = MeshTopology::new(
            &v,
            &[t[0], t[1], t[4], t[5], t[6], t[7], t[8], t[9], t[10], t[11]],
        );
        assert_eq!(open.defects.open_edges, 4);
        assert!(!open.defects.is_closed());
        let lone = MeshTopology::new(&v, &t[..1]);
        assert_eq!(lone.defects.open_edges, 3);
        assert_eq!(lone.regions.len(), 1);
        assert!(lone.regions[0].flat_normal.is_some());
    }
}
