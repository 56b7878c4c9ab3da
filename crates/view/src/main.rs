//! The `view` binary: see the `view` crate's docs (`view --help` lists the flags).

use clap::Parser as _;

fn main() -> std::process::ExitCode {
    let args = view::Args::parse();
    match view::run(args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
