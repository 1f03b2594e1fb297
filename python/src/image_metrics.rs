//! Metrics on numpy arrays (dtype and shape checked by `pathlab/metrics.py`) and `compare`.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use pathlab::display::{DisplayImage, DisplayTransform, Transfer};
use pathlab::film::Film;

use crate::render_error;

pub(crate) fn pixels(a: &PyReadonlyArray3<'_, f32>) -> PyResult<(u32, u32, Vec<[f32; 3]>)> {
    let shape = a.shape();
    if shape[2] != 3 {
        return Err(PyValueError::new_err(format!("expected an (H, W, 3) array, got shape {shape:?}")));
    }
    let slice = a.as_slice().map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((shape[1] as u32, shape[0] as u32, slice.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect()))
}

pub(crate) fn film_of(mean: &PyReadonlyArray3<'_, f32>, variance: Option<&PyReadonlyArray3<'_, f32>>, spp: u64) -> PyResult<Film> {
    let (width, height, mean) = pixels(mean)?;
    let variance = match variance {
        Some(v) => {
            let (w, h, v) = pixels(v)?;
            if (w, h) != (width, height) {
                return Err(PyValueError::new_err(format!("variance is {w}x{h}, the image {width}x{height}")));
            }
            v
        }
        None => vec![[0.0; 3]; mean.len()],
    };
    Ok(Film { width, height, spp, mean, variance })
}

pub(crate) fn transform_of(display: Option<&str>, exposure: f32) -> PyResult<Option<DisplayTransform>> {
    display
        .map(|d| {
            let transfer: Transfer = d.parse().map_err(|e: pathlab::display::TransferParseError| PyValueError::new_err(format!("display: {}", e.0)))?;
            Ok(DisplayTransform { transfer, exposure })
        })
        .transpose()
}

/// A display image: the array as given (`display` None: already display-referred, as
/// scikit-image takes it), or the array through the display transform.
pub(crate) fn display_image(a: &PyReadonlyArray3<'_, f32>, transform: Option<&DisplayTransform>) -> PyResult<DisplayImage> {
    let (width, height, pixels) = pixels(a)?;
    Ok(match transform {
        Some(t) => t.film(&Film { width, height, spp: 0, variance: vec![[0.0; 3]; pixels.len()], mean: pixels }),
        None => DisplayImage { width, height, pixels },
    })
}

/// One metric of `test` against `reference`: psnr, ssim, flip (display-referred), mse,
/// rel_mse (linear).
#[pyfunction]
#[pyo3(signature = (name, test, reference, display, exposure))]
pub(crate) fn metric(name: &str, test: PyReadonlyArray3<'_, f32>, reference: PyReadonlyArray3<'_, f32>, display: Option<&str>, exposure: f32) -> PyResult<f64> {
    if test.shape() != reference.shape() {
        return Err(PyValueError::new_err(format!("test is {:?} and reference {:?}: the shapes differ", test.shape(), reference.shape())));
    }
    let transform = transform_of(display, exposure)?;
    match name {
        "mse" | "rel_mse" => {
            let (t, r) = (film_of(&test, None, 0)?, film_of(&reference, None, 0)?);
            Ok(if name == "mse" { pathlab::metrics::mse(&t, &r) } else { pathlab::metrics::rel_mse(&t, &r) })
        }
        _ => {
            let (t, r) = (display_image(&test, transform.as_ref())?, display_image(&reference, transform.as_ref())?);
            let min = pathlab::metrics::ssim::MIN_SIZE;
            match name {
                "psnr" => Ok(pathlab::metrics::psnr(&r, &t)),
                "ssim" | "flip" if t.width < min || t.height < min => {
                    Err(PyValueError::new_err(format!("{name} needs images of at least {min}x{min} pixels, not {}x{}", t.width, t.height)))
                }
                "ssim" => Ok(pathlab::metrics::ssim(&r, &t)),
                "flip" => Ok(pathlab::metrics::flip(&r, &t)),
                _ => Err(PyValueError::new_err(format!("unknown metric {name}"))),
            }
        }
    }
}

/// Every metric of `pathlab compare --json`, as JSON.
#[pyfunction]
#[pyo3(signature = (test, test_variance, test_spp, reference, reference_variance, reference_spp, display, exposure, block))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn compare_json(
    test: PyReadonlyArray3<'_, f32>,
    test_variance: Option<PyReadonlyArray3<'_, f32>>,
    test_spp: u64,
    reference: PyReadonlyArray3<'_, f32>,
    reference_variance: Option<PyReadonlyArray3<'_, f32>>,
    reference_spp: u64,
    display: &str,
    exposure: f32,
    block: u32,
) -> PyResult<String> {
    let with_variance = test_variance.is_some() && reference_variance.is_some();
    let t = film_of(&test, test_variance.as_ref(), test_spp)?;
    let r = film_of(&reference, reference_variance.as_ref(), reference_spp)?;
    let transform = transform_of(Some(display), exposure)?.expect("a display was given");
    let result = pathlab::metrics::compare_blocks(&t, &r, transform, with_variance, block).map_err(|e| PyValueError::new_err(e.to_string()))?;
    serde_json::to_string(&result).map_err(render_error)
}

/// The display image of linear radiance (float32 (H, W, 3), values in [0, 1]): what PNGs,
/// figures and the display-referred metrics see.
#[pyfunction]
#[pyo3(signature = (image, display, exposure))]
pub(crate) fn to_display<'py>(py: Python<'py>, image: PyReadonlyArray3<'py, f32>, display: &str, exposure: f32) -> PyResult<Bound<'py, PyAny>> {
    let transform = transform_of(Some(display), exposure)?.expect("a display was given");
    let shape = image.shape().to_vec();
    let shown = display_image(&image, Some(&transform))?;
    PyArray1::from_vec(py, shown.pixels.into_iter().flatten().collect()).reshape(shape).map(Bound::into_any)
}
