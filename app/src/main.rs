//! The `meshfree` binary: see `meshfree --help` and `src/cli/` (one file per command).
use std::process::ExitCode;

use clap::Parser;

#[cfg(feature = "viewer")]
mod view;
#[cfg(feature = "viewer")]
mod view_run;

fn main() -> ExitCode {
    let cli = meshfree::cli::Cli::parse();
    let result = match cli.command {
        #[cfg(feature = "viewer")]
        meshfree::cli::Command::View(a) => view::view(a),
        #[cfg(feature = "viewer")]
        meshfree::cli::Command::Render(a) => view::render(a),
        _ => meshfree::cli::main(cli),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let code = meshfree::cli::exit_code(&e);
            if code != 0 {
                meshfree::errln!("error: {e:#}");
            }
            ExitCode::from(code)
        }
    }
}
