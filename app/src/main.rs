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
        // A run's output directory is drawn from its frames; anything else is a scene.
        #[cfg(feature = "viewer")]
        meshfree::cli::Command::View(a) if std::path::Path::new(&a.scene).is_dir() => {
            view_run::view_run(a)
        }
        #[cfg(feature = "viewer")]
        meshfree::cli::Command::View(a) => view::view(a),
        #[cfg(feature = "viewer")]
        meshfree::cli::Command::Render(a) if std::path::Path::new(&a.scene).is_dir() => {
            view_run::render_run(a)
        }
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
