//! The memory a mesh's surface queries take: bytes per triangle, checked before a mesh is
//! prepared (a scene's other buffers are `super::memory_budget`'s).

use crate::allocation::check_room;
use crate::error::OutOfMemory;

/// Bytes preparing a mesh for its surface queries takes per triangle, rounded up from the 650
/// measured on a sphere of a million triangles: parry's bounding-volume tree (about half, and
/// as much again while it is built) and pseudo-normals, the mesh as read, its topology and the
/// grids of its vertices and triangle centres.
pub const MESH_BYTES_PER_TRIANGLE: u64 = 700;

/// Checks that a mesh of `triangles` can be prepared now ([`MESH_BYTES_PER_TRIANGLE`] each),
/// before it is: its buffers are allocated ordinarily, by parry among others.
pub fn check_mesh_room(triangles: usize) -> Result<(), OutOfMemory> {
    let bytes = (triangles as u64).saturating_mul(MESH_BYTES_PER_TRIANGLE);
    check_room(bytes, || {
        format!("preparing the mesh's {triangles} triangles")
    })
}
