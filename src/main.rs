//! The `meshfree` binary: see `meshfree --help` and `src/cli.rs`.
use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = meshfree::cli::Cli::parse();
    match meshfree::cli::main(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
