//! One module per subcommand: its flags (`Args`, as clap parses them) and `execute`, which
//! turns them into a validated configuration and runs the command.

pub mod batch;
pub mod bench;
pub mod margin;
pub mod plan;
pub mod plot;
pub mod schema;
pub mod solve;
pub mod study;
pub mod sweep;
pub mod transfer;
