//! The scene format and everything that turns written JSON into a validated [`Scene`](scene_format::Scene): strict
//! JSON reading, every structural problem at once (against the JSON Schema), validation with
//! a path and a fix per problem, the object's shape checks, fingers placed on the shape, the
//! report of what the shape gave each finger, and the memory estimate of a solve before
//! anything is allocated.
//!
//! The scene is plain data; what reading it finds beyond (the posed shapes, the object's
//! triangles, the height maps: [`scene_geometry`]) travels beside it in a
//! [`LoadedScene`](loaded_scene::LoadedScene), from which the model is built.
//!
//! Reading a scene ([`scene_reading`]) ends with its validation pass ([`scene_validation`]),
//! which applies the checks of one field each ([`field_checks`], a finger's texture in
//! [`texture_checks`], its sensor in [`sensor_checks`]) over the vector arithmetic
//! of [`vector_math`]; each imports only those after it.

pub mod field_checks;
pub mod finger_placement;
pub mod gel_spec;
pub mod limits;
pub mod loaded_scene;
pub mod memory_budget;
pub mod mesh_budget;
pub mod mount_checks;
pub mod mount_spec;
pub mod patch_on_shape;
pub mod response_spec;
pub mod scene_format;
pub mod scene_geometry;
pub mod scene_reading;
pub mod scene_validation;
pub mod schema_check;
pub mod sensor_checks;
pub mod sensor_kind;
pub mod sensor_spec;
pub mod shape_checks;
pub mod shape_report;
pub mod shape_spec;
pub mod shared_spring_checks;
pub mod shared_spring_spec;
pub mod strict_json;
pub mod texture_checks;
pub mod texture_spec;
pub mod tip_shapes;
pub mod vector_math;
