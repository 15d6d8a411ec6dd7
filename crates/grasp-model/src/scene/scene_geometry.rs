//! What reading a scene found beyond its plain data: the shape's report, the posed object
//! shape and its triangles for drawing, each finger's posed tip shape and its height map (read
//! from its file or given as an array). Runtime data, not part of the file: it travels beside
//! the plain [`Scene`](crate::scene::scene_format::Scene) in a
//! [`LoadedScene`](crate::scene::loaded_scene::LoadedScene), and the model keeps what it needs
//! of it.

use std::sync::Arc;

use crate::geometry::mesh_surface::TriangleMesh;
use crate::geometry::shape::Shape;
use crate::geometry::surface_texture::HeightGrid;
use crate::scene::shape_report::ShapeReport;

/// What reading a scene found beyond its plain data (everything empty for a scene without
/// `object.shape` and without height maps).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneGeometry {
    /// What the object's shape gave: derived finger frames, volume, mass, warnings (`None`
    /// without `object.shape`).
    pub report: Option<ShapeReport>,
    /// The posed object shape (`object.shape`), for the exact gaps.
    pub shape: Option<SharedShape>,
    /// The object shape's surface as triangles, world frame, m, for drawing.
    pub surface: Option<Arc<TriangleMesh>>,
    /// Per finger, scene order, its posed tip shape (`fingers[i].tip.shape`; `None` for the
    /// other tips), for the exact gaps; empty without `object.shape`.
    pub tips: Vec<Option<SharedShape>>,
    /// Per finger, scene order, its height map (`fingers[i].texture.heights`, read from its
    /// file or given as an array; `None` for the other fingers); empty without height maps.
    pub height_maps: Vec<Option<Arc<HeightGrid>>>,
}

impl SceneGeometry {
    /// Finger `i`'s posed tip shape, if it has one.
    pub fn tip(&self, i: usize) -> Option<&SharedShape> {
        self.tips.get(i).and_then(Option::as_ref)
    }

    /// Finger `i`'s height map, if one was read or given.
    pub fn height_map(&self, i: usize) -> Option<&HeightGrid> {
        self.height_maps.get(i).and_then(Option::as_deref)
    }

    /// The shape checks' warnings (a patch over an edge, overlapping patches, an open mesh):
    /// every solution of the scene carries them.
    pub fn warnings(&self) -> &[String] {
        self.report.as_ref().map_or(&[], |r| &r.warnings)
    }
}

/// A posed shape shared by the scene's geometry and its models; two are equal when they are
/// the same one.
#[derive(Debug, Clone)]
pub struct SharedShape(pub(crate) Arc<Shape>);

impl SharedShape {
    /// `shape`, to be shared.
    pub(crate) fn new(shape: Shape) -> SharedShape {
        SharedShape(Arc::new(shape))
    }
}

impl PartialEq for SharedShape {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}
