//! `grasp schema`: the JSON Schema of the scene format or of the schedule format.

use std::process::ExitCode;

use anyhow::Result;

/// Print the JSON Schema of the scene format (or of the schedule format).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print the schedule format's schema instead.
    #[arg(long)]
    pub schedule: bool,
}

/// `grasp schema`.
pub fn execute(args: Args) -> Result<ExitCode> {
    let schema = if args.schedule {
        serde_json::to_value(schemars::schema_for!(grasp_transfer::ScheduleSpec))?
    } else {
        serde_json::to_value(grasp_model::scene_json_schema())?
    };
    println!("{}", serde_json::to_string_pretty(&schema)?);
    Ok(ExitCode::SUCCESS)
}
