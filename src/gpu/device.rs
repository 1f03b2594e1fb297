//! Adapter choice and device creation.

use std::time::Duration;

/// Environment variable that selects an adapter by name substring (like `--adapter`).
pub const ADAPTER_ENV: &str = "PATHLAB_ADAPTER";

/// How long a single blocking wait on the device may take before it is reported as a hang.
const WAIT_TIMEOUT: Duration = Duration::from_secs(120);

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no Vulkan, Metal or DX12 adapter found.\n\
         On Debian/Ubuntu without a GPU, install Mesa's software Vulkan driver (lavapipe):\n    \
         sudo apt-get install -y mesa-vulkan-drivers\n\
         then check with `vulkaninfo --summary` (package vulkan-tools)."
    )]
    NoAdapter,
    #[error("no adapter name contains \"{filter}\"; available: {available}")]
    NoMatchingAdapter { filter: String, available: String },
    #[error("cannot open a device on {adapter}: {source}")]
    RequestDevice {
        adapter: String,
        #[source]
        source: wgpu::RequestDeviceError,
    },
    #[error("the GPU did not finish within {0:?}: {1}")]
    Timeout(Duration, String),
    #[error("GPU error: {0}")]
    Device(String),
}

/// An open device with what we know about it. Cloning is cheap (wgpu's device and queue are
/// shared handles): every `Renderer` owns its clone, so nothing borrows the device.
#[derive(Clone)]
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    pub features: wgpu::Features,
}

/// Switches Mesa's device-select layer off, once, unless the user configures it.
///
/// Mesa's implicit Vulkan layer VK_LAYER_MESA_device_select connects to Wayland and X11 to find
/// the display's GPU when adapters are enumerated; on a headless machine (a server, a
/// container, CI) libwayland then prints "error: XDG_RUNTIME_DIR is invalid or not set in the
/// environment." (twice), which reads like a failure. pathlab picks its adapter itself
/// (`--adapter`, PATHLAB_ADAPTER), so the layer is switched off by the variable its manifest
/// names (NODEVICE_SELECT), unless the user configures the layer (MESA_VK_DEVICE_SELECT) or has
/// decided (NODEVICE_SELECT set). Every Vulkan instance of the library (the CLI's, Python's,
/// the tests') is made after this; the CLI also calls it first thing, before any thread starts.
pub fn quiet_device_select() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("NODEVICE_SELECT").is_none() && std::env::var_os("MESA_VK_DEVICE_SELECT").is_none() {
            // SAFETY: called once, before the process's first Vulkan instance: the loader, which
            // reads the variable, has not started, and pathlab's own threads read no
            // environment meanwhile (the CLI calls this while single-threaded).
            unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
        }
    });
}

/// An instance on the native compute-capable APIs (Vulkan, Metal, DX12), unless `WGPU_BACKEND`
/// says otherwise. OpenGL is left out: it is not a supported target and probing it is noisy.
fn new_instance() -> wgpu::Instance {
    quiet_device_select();
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    wgpu::Instance::new(desc)
}

/// Every adapter wgpu can see, best first.
pub fn list_adapters() -> Vec<wgpu::Adapter> {
    let instance = new_instance();
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters.sort_by_key(|a| rank(&a.get_info()));
    adapters
}

/// Lower is better: hardware before software, native APIs before OpenGL.
fn rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let device = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    let backend = match info.backend {
        wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12 => 0,
        _ => 1,
    };
    (backend, device)
}

/// One line describing an adapter: name, type, backend, driver.
pub fn adapter_summary(info: &wgpu::AdapterInfo) -> String {
    format!(
        "{} ({:?}, {:?}, driver {} {})",
        info.name, info.device_type, info.backend, info.driver, info.driver_info
    )
}

impl Gpu {
    /// Opens the best adapter, or the first whose name contains `filter` (falling back to the
    /// `PATHLAB_ADAPTER` environment variable). Only Vulkan, Metal and DX12 adapters qualify.
    pub fn new(filter: Option<&str>) -> Result<Gpu, GpuError> {
        let env_filter = std::env::var(ADAPTER_ENV).ok().filter(|s| !s.is_empty());
        let filter = filter.map(str::to_string).or(env_filter);
        let adapters: Vec<wgpu::Adapter> = list_adapters()
            .into_iter()
            .filter(|a| matches!(a.get_info().backend, wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12))
            .collect();
        if adapters.is_empty() {
            return Err(GpuError::NoAdapter);
        }
        let adapter = match &filter {
            Some(f) => {
                let needle = f.to_lowercase();
                let found = adapters.iter().position(|a| a.get_info().name.to_lowercase().contains(&needle));
                match found {
                    Some(i) => adapters.into_iter().nth(i).ok_or(GpuError::NoAdapter)?,
                    None => {
                        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                        return Err(GpuError::NoMatchingAdapter { filter: f.clone(), available: names.join(", ") });
                    }
                }
            }
            None => adapters.into_iter().next().ok_or(GpuError::NoAdapter)?,
        };
        let info = adapter.get_info();
        let limits = adapter.limits();
        let features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("pathlab"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|source| GpuError::RequestDevice { adapter: info.name.clone(), source })?;
        Ok(Gpu { device, queue, info, limits, features })
    }

    /// Blocks until all submitted work is done (bounded by a timeout, never forever).
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        wait_for_submission(&self.device, None)
    }
}

/// Waits for `submission` (or all work) with a timeout; a hang becomes an error.
pub fn wait_for_submission(device: &wgpu::Device, submission: Option<wgpu::SubmissionIndex>) -> Result<(), GpuError> {
    device
        .poll(wgpu::PollType::Wait { submission_index: submission, timeout: Some(WAIT_TIMEOUT) })
        .map(|_| ())
        .map_err(|e| match e {
            wgpu::PollError::Timeout => GpuError::Timeout(WAIT_TIMEOUT, "waiting for submitted work".into()),
            other => GpuError::Device(other.to_string()),
        })
}
