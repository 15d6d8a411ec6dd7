//! Tactile sensors read from a solved grasp: what a sensor in a finger's pad would measure
//! under the solved element tractions, a read-out (no solve): the layout of a taxel grid
//! ([`taxel_grid`]), its readings from one finger's solved elements ([`taxel_readings`]), a
//! marker grid's readings of the pad's surface displacement ([`marker_readings`]), an optical
//! gel's image of the pad ([`gel_image`]: its height map [`gel_height`], its shading
//! [`gel_shading`]) and every
//! sensor of a scene read from a [`Solution`](crate::Solution) ([`sensor_readings`]). The
//! kinds share the grid's layout and the checks of their work through
//! `crate::scene::sensor_kind::SensorKind`.

pub mod gel_height;
pub mod gel_image;
pub mod gel_shading;
pub mod marker_readings;
pub mod readout_cache;
pub mod sensor_readings;
pub mod sensor_response;
pub mod taxel_grid;
pub mod taxel_lattice;
pub mod taxel_matrix;
pub mod taxel_readings;
