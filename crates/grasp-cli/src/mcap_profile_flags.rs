//! The flags choosing what an MCAP log holds, one group flattened into every command that
//! writes one (`grasp transfer`, `grasp plan`): `--mcap-profile` and `--ros2-start-time`.

use anyhow::{anyhow, bail, Result};
use grasp_transfer::McapProfile;

/// The MCAP log's profile by name.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
pub enum ProfileName {
    /// JSON messages with JSON Schemas (Foxglove).
    Json,
    /// CDR-encoded ROS 2 messages with ros2msg schemas (rosbag2).
    Ros2,
}

/// `--mcap-profile` and `--ros2-start-time`.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct McapProfileFlags {
    /// What the MCAP log holds: `json` (JSON messages with JSON Schemas, for Foxglove) or
    /// `ros2` (CDR-encoded ROS 2 messages with ros2msg schemas, as `ros2 bag record` writes
    /// them: forces as geometry_msgs/WrenchStamped, /tf, markers, pressure images; see
    /// docs/guide/outputs.md, "ROS 2").
    #[arg(
        long,
        value_enum,
        default_value = "json",
        value_name = "json|ros2",
        requires = "mcap"
    )]
    pub mcap_profile: ProfileName,
    /// With `--mcap-profile ros2`: the stamp of the schedule's time 0, in seconds after the Unix
    /// epoch (default 0), to lay a simulated hand-off beside a real recording.
    #[arg(long, value_name = "SECONDS", requires = "mcap")]
    pub ros2_start_time: Option<f64>,
}

impl McapProfileFlags {
    /// The profile asked for, its start time checked.
    pub fn profile(&self) -> Result<McapProfile> {
        match (self.mcap_profile, self.ros2_start_time) {
            (ProfileName::Json, None) => Ok(McapProfile::Json),
            (ProfileName::Json, Some(_)) => {
                bail!("--ros2-start-time applies to the ros2 MCAP profile: add --mcap-profile ros2")
            }
            (ProfileName::Ros2, t) => {
                let t = t.unwrap_or(0.0);
                McapProfile::ros2_from(t).map_err(|why| anyhow!("--ros2-start-time {t}: {why}"))
            }
        }
    }
}
