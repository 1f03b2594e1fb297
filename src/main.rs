//! The `pathlab` command line.

mod cli;

fn main() {
    // Before any thread starts: Mesa's device-select layer off (its headless noise), as every
    // front-end of the library has it.
    pathlab::gpu::quiet_device_select();
    // Rust ignores SIGPIPE, so printing to a closed pipe (`pathlab check s.toml | head -1`)
    // would panic; the default action ends the process quietly, as for any Unix tool.
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    std::process::exit(cli::run());
}
