//! The `pathlab` command line.

mod cli;

fn main() {
    // Mesa's implicit Vulkan layer VK_LAYER_MESA_device_select connects to Wayland and X11 to
    // find the display's GPU when adapters are enumerated; on a headless machine libwayland then
    // prints "error: XDG_RUNTIME_DIR is invalid or not set in the environment." (twice), which
    // reads like a failure. pathlab picks its adapter itself (`--adapter`, PATHLAB_ADAPTER), so
    // the layer is switched off by the variable its manifest names, unless the user configures
    // it (MESA_VK_DEVICE_SELECT) or has decided (NODEVICE_SELECT). Set before any thread starts.
    if std::env::var_os("NODEVICE_SELECT").is_none() && std::env::var_os("MESA_VK_DEVICE_SELECT").is_none() {
        // SAFETY: the process is single-threaded here.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
    // Rust ignores SIGPIPE, so printing to a closed pipe (`pathlab check s.toml | head -1`)
    // would panic; the default action ends the process quietly, as for any Unix tool.
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    std::process::exit(cli::run());
}
