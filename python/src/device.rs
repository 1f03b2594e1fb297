//! The one device of the process: opened at the first render and reused by every call after it.

use std::sync::{Arc, Mutex};

use pyo3::prelude::*;

use pathlab::gpu::{Gpu, PathTracerPipelines};

use crate::GpuError;

pub(crate) struct Device {
    pub(crate) gpu: Gpu,
    pub(crate) pipelines: PathTracerPipelines,
}

pub(crate) static DEVICE: Mutex<Option<Arc<Device>>> = Mutex::new(None);

/// The process's device, opened on first use (a failure is not remembered: installing a
/// driver and calling again works).
pub(crate) fn device(py: Python<'_>) -> PyResult<Arc<Device>> {
    py.detach(|| {
        let mut slot = DEVICE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(d) = slot.as_ref() {
            return Ok(d.clone());
        }
        let gpu = Gpu::new(None).map_err(|e| GpuError::new_err(e.to_string()))?;
        let pipelines = PathTracerPipelines::new(&gpu);
        let d = Arc::new(Device { gpu, pipelines });
        *slot = Some(d.clone());
        Ok(d)
    })
}

/// The adapter a render would use (opening the device if needed): a dict of its details.
#[pyfunction]
pub(crate) fn device_info(py: Python<'_>) -> PyResult<String> {
    let d = device(py)?;
    Ok(adapter_json(&d.gpu.info).to_string())
}

pub(crate) fn adapter_json(info: &wgpu::AdapterInfo) -> serde_json::Value {
    serde_json::json!({
        "name": info.name,
        "device_type": format!("{:?}", info.device_type),
        "backend": format!("{:?}", info.backend),
        "driver": info.driver,
        "driver_info": info.driver_info,
        "summary": pathlab::gpu::adapter_summary(info),
    })
}

/// Every adapter wgpu can see, best first, as JSON.
#[pyfunction]
pub(crate) fn adapters_json(py: Python<'_>) -> String {
    py.detach(|| {
        let list: Vec<serde_json::Value> = pathlab::gpu::list_adapters().iter().map(|a| adapter_json(&a.get_info())).collect();
        serde_json::Value::Array(list).to_string()
    })
}
