//! The scene format and everything that turns written JSON into a validated [`Scene`](scene_format::Scene): strict
//! JSON reading, every structural problem at once (against the JSON Schema), validation with
//! a path and a fix per problem, the object's shape checks, fingers placed on the shape, the
//! report of what the shape gave each finger, and the memory estimate of a solve before
//! anything is allocated.

pub mod finger_placement;
pub mod limits;
pub mod patch_on_shape;
pub mod scene_format;
pub mod schema_check;
pub mod shape_checks;
pub mod shape_report;
pub mod strict_json;
pub mod validation;
pub mod work_bounds;
