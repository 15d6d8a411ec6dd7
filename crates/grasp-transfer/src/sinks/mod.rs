//! Log sinks of a hand-off, each optional and independent: MCAP (its JSON profile, or its ROS 2
//! profile), Rerun, CSV, NumPy `.npz`; the
//! files a run writes opened for them; and what they share (the trait, the drawing's scale and
//! colours, fingertip drawings, element maps, the Foxglove scene, the Rerun layout).

pub mod colour_key;
pub mod csv_history;
pub mod drawing_scale;
pub mod element_maps;
pub mod fingertip_drawing;
pub mod foxglove_scene;
pub mod gel_drawing;
pub mod gel_image_message;
pub mod identical_curves;
pub mod mcap_log;
pub mod npz_steps;
pub mod output_files;
pub mod patch_maps_message;
pub mod patch_views;
pub mod rerun_grid_maps;
pub mod rerun_layout;
pub mod rerun_log;
pub mod ros2_definitions;
pub mod ros2_log;
pub mod ros2_messages;
pub mod ros2_patch_images;
pub mod ros2_scene_markers;
pub mod sensor_columns;
pub mod shared_spring_drawing;
pub mod sink;
pub mod tactile_drawing;
pub mod tactile_message;
pub mod viewer_address;
