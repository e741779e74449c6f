use std::process::ExitCode;

/// mimalloc keeps freed frame-sized blocks (visibility buffer, image) for the next frame;
/// glibc's allocator returned them to the system and page-faulted them back every frame,
/// which doubled the default 640x480 frame (13.9 ms against 6.2 ms; docs/benchmarks.md,
/// "The kernel").
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    // A closed standard output (`brdfkit compare a.exr b.exr | head`) ends the program
    // quietly, as it does every Unix filter: Rust ignores SIGPIPE by default, so a write to
    // the closed pipe would fail and `println!` panic (exit 101) instead.
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition, before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Ctrl-C or a kill during a write leaves no `.NAME.*.tmp` beside the output.
    if let Err(e) = brdfkit::image_io::remove_temporary_files_on_signals() {
        eprintln!("brdfkit: warning: no SIGINT/SIGTERM handler ({e}): an interrupted write may leave a temporary file");
    }
    let cli = brdfkit::cli::parse::parse_args();
    match brdfkit::cli::run(cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("brdfkit: error: {e}");
            ExitCode::from(2)
        }
    }
}
