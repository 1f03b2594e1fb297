//! Writing films: OpenEXR (linear float32, with metadata and optional variance channels) and
//! PNG images (display-referred, see `display`). Every file is written to a temporary file
//! beside the target and renamed over it, so an interrupted or failed write never leaves a
//! truncated file behind; the file gets the permissions the user's umask gives (0666 & !umask),
//! like any file a program creates.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use exr::prelude::*;
// The exr prelude exports its own `Result`; ours is the standard one.
use std::result::Result;

use crate::display::DisplayImage;
use crate::film::Film;

#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot write {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot encode {}: {message}", path.display())]
    Encode { path: PathBuf, message: String },
    #[error("cannot read {}: {message}", path.display())]
    Read { path: PathBuf, message: String },
}

/// Writes through a temporary file in the target's directory, renamed into place on success.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut std::fs::File>) -> Result<(), String>,
) -> Result<(), OutputError> {
    let io_err = |source| OutputError::Io { path: path.to_path_buf(), source };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".pathlab-").suffix(".tmp");
    // open(2) applies the umask to this mode: the file ends up as any newly created file would
    // (tempfile's own default, 0600, would survive the rename).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder
        .tempfile_in(dir)
        .map_err(io_err)?;
    {
        let mut writer = BufWriter::new(tmp.as_file_mut());
        write(&mut writer).map_err(|message| OutputError::Encode { path: path.to_path_buf(), message })?;
        writer.flush().map_err(io_err)?;
    }
    tmp.as_file().sync_all().map_err(io_err)?;
    tmp.persist(path).map_err(|e| io_err(e.error))?;
    Ok(())
}

/// Key-value metadata stored in the EXR header (as `pathlab:KEY` text attributes).
pub type Metadata = Vec<(String, String)>;

/// Linear RGB float32 EXR; with `variance`, also `variance.R/G/B` (variance of the mean).
pub fn write_exr(path: &Path, film: &Film, metadata: &Metadata, variance: bool) -> Result<(), OutputError> {
    let channel = |name: &str, data: &[[f32; 3]], c: usize| {
        AnyChannel::new(name, FlatSamples::F32(data.iter().map(|p| p[c]).collect()))
    };
    let mut list = Vec::new();
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        list.push(channel(name, &film.mean, c));
        if variance {
            list.push(channel(&format!("variance.{name}"), &film.variance, c));
        }
    }
    write_exr_layer(path, (film.width as usize, film.height as usize), list, metadata)
}

/// One EXR layer of `channels` with `metadata` as `pathlab:KEY` text attributes, written
/// atomically (lossless compression).
pub(crate) fn write_exr_layer(
    path: &Path,
    size: (usize, usize),
    channels: Vec<AnyChannel<FlatSamples>>,
    metadata: &Metadata,
) -> Result<(), OutputError> {
    let layer = Layer::new(size, LayerAttributes::default(), Encoding::FAST_LOSSLESS, AnyChannels::sort(channels.into()));
    let mut image = Image::from_layer(layer);
    for (key, value) in metadata {
        image
            .attributes
            .other
            .insert(Text::from(format!("pathlab:{key}").as_str()), AttributeValue::Text(Text::from(value.as_str())));
    }
    write_atomically(path, |w| {
        let mut cursor = std::io::Cursor::new(Vec::new());
        image.write().to_buffered(&mut cursor).map_err(|e| e.to_string())?;
        w.write_all(cursor.get_ref()).map_err(|e| e.to_string())
    })
}

/// The first layer of an EXR and its `pathlab:KEY` attributes (sorted by key).
pub(crate) fn read_exr_layer(path: &Path) -> Result<(Layer<AnyChannels<FlatSamples>>, Metadata), String> {
    let image = read_all_flat_layers_from_file(path).map_err(|e| e.to_string())?;
    let mut metadata = Metadata::new();
    let layer = image.layer_data.into_iter().next().ok_or("the EXR has no layer")?;
    // Custom attributes may come back as image or as layer attributes.
    for (key, value) in image.attributes.other.iter().chain(&layer.attributes.other) {
        if let (Some(k), AttributeValue::Text(t)) = (key.to_string().strip_prefix("pathlab:"), value) {
            metadata.push((k.to_string(), t.to_string()));
        }
    }
    metadata.sort();
    Ok((layer, metadata))
}

/// 8-bit RGB PNG of a display image.
pub fn write_png(path: &Path, image: &DisplayImage) -> Result<(), OutputError> {
    write_rgb8_png(path, image.width, image.height, image.to_rgb8())
}

/// 8-bit RGB PNG from raw bytes (3 per pixel, row-major).
pub fn write_rgb8_png(path: &Path, width: u32, height: u32, bytes: Vec<u8>) -> Result<(), OutputError> {
    let img = image::RgbImage::from_raw(width, height, bytes).ok_or_else(|| OutputError::Encode {
        path: path.to_path_buf(),
        message: "image size does not match its pixels".into(),
    })?;
    write_atomically(path, |w| {
        let mut cursor = std::io::Cursor::new(Vec::new());
        img.write_to(&mut cursor, image::ImageFormat::Png).map_err(|e| e.to_string())?;
        w.write_all(cursor.get_ref()).map_err(|e| e.to_string())
    })
}

/// An EXR read back: the film (variance 0 where the file has no variance channels), its
/// pathlab metadata, and whether it had variance channels.
#[derive(Debug, Clone)]
pub struct ExrImage {
    pub film: Film,
    pub metadata: Metadata,
    pub has_variance: bool,
}

/// Reads the RGB channels and pathlab metadata of an EXR written by `write_exr`.
pub fn read_exr(path: &Path) -> Result<(Film, Metadata), OutputError> {
    read_exr_image(path).map(|e| (e.film, e.metadata))
}

/// Like `read_exr`, also telling whether the file carries variance channels.
pub fn read_exr_image(path: &Path) -> Result<ExrImage, OutputError> {
    let fail = |message: String| OutputError::Read { path: path.to_path_buf(), message };
    if !path.is_file() {
        return Err(fail("no such file".into()));
    }
    let (layer, metadata) = read_exr_layer(path).map_err(|e| fail(format!("not a readable OpenEXR file ({e})")))?;
    let (w, h) = (layer.size.width(), layer.size.height());
    let find = |name: &str| -> Option<Vec<f32>> {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == Text::from(name))
            .map(|c| c.sample_data.values_as_f32().collect())
    };
    let get = |prefix: &str| -> Option<Vec<[f32; 3]>> {
        let (r, g, b) = (find(&format!("{prefix}R"))?, find(&format!("{prefix}G"))?, find(&format!("{prefix}B"))?);
        Some((0..w * h).map(|i| [r[i], g[i], b[i]]).collect())
    };
    let mean = get("").ok_or_else(|| fail("the EXR has no R, G and B channels".into()))?;
    let variance = get("variance.");
    let has_variance = variance.is_some();
    let variance = variance.unwrap_or_else(|| vec![[0.0; 3]; w * h]);
    let spp = metadata.iter().find(|(k, _)| k == "spp").and_then(|(_, v)| v.parse().ok()).unwrap_or(0);
    Ok(ExrImage { film: Film { width: w as u32, height: h as u32, spp, mean, variance }, metadata, has_variance })
}
