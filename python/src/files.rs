//! EXR files, as `pathlab render` writes and reads them.

use std::path::PathBuf;

use numpy::PyReadonlyArray3;
use pyo3::prelude::*;

use crate::image_metrics::film_of;
use crate::render::film_arrays;
use crate::render_error;

/// Writes an EXR atomically with the render's header (`variance`: with variance channels).
#[pyfunction]
#[pyo3(signature = (path, image, variance, spp, metadata))]
pub(crate) fn write_exr(
    py: Python<'_>,
    path: PathBuf,
    image: PyReadonlyArray3<'_, f32>,
    variance: Option<PyReadonlyArray3<'_, f32>>,
    spp: u64,
    metadata: Vec<(String, String)>,
) -> PyResult<()> {
    let film = film_of(&image, variance.as_ref(), spp)?;
    let metadata: Vec<(String, String)> = metadata.into_iter().filter(|(k, _)| k != pathlab::output::CHECKSUM_KEY).collect();
    let with_variance = variance.is_some();
    py.detach(|| pathlab::output::write_exr(&path, &film, &metadata, with_variance)).map_err(render_error)
}

/// Reads an EXR: image, variance (or None), spp and its pathlab metadata.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub(crate) fn read_exr<'py>(py: Python<'py>, path: PathBuf) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>, u64, Vec<(String, String)>)> {
    if !path.exists() {
        return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!("{}: no such file", path.display())));
    }
    let exr = py.detach(|| pathlab::output::read_exr_image(&path)).map_err(render_error)?;
    let (image, variance) = film_arrays(py, &exr.film)?;
    // The checksum of the file's pixels (checked on reading) is the file's, not the render's.
    let metadata = exr.metadata.into_iter().filter(|(k, _)| k != pathlab::output::CHECKSUM_KEY).collect();
    Ok((image, exr.has_variance.then_some(variance), exr.film.spp, metadata))
}
