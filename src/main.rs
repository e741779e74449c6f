use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = brdfkit::cli::Cli::parse();
    match brdfkit::cli::run(cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("brdfkit: error: {e}");
            ExitCode::from(2)
        }
    }
}
