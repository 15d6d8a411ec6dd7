//! Geometry of surfaces, independent of the scene format: contact frames, points on a surface
//! with their normal and principal curvatures, the exact primitives, triangle meshes, the posed
//! shape that answers closest-point and ray queries, its tessellation for drawing, and the
//! texture heights under a patch (a height map, ridges, a seeded random surface).

pub mod contact_frame;
pub mod mesh_surface;
pub mod mesh_topology;
pub mod point_grid;
pub mod portable_fft;
pub mod primitive_surface;
pub mod random_surface;
pub mod shape;
pub mod surface_point;
pub mod surface_texture;
pub mod tessellation;
