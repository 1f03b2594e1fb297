//! Writing films: OpenEXR (linear float32, with metadata and optional variance channels) and
//! PNG images (display-referred, see `display`). Every file is written to a temporary file
//! beside the target and renamed over it, so an interrupted or failed write never leaves a
//! truncated file behind; the file gets the permissions the user's umask gives (0666 & !umask),
//! like any file a program creates. Reading is strict (`attributes`): pathlab's header
//! attributes are checked as written, and images with non-finite values are refused.

pub mod attributes;
pub mod mutation;

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use exr::prelude::*;
// The exr prelude exports its own `Result`; ours is the standard one.
use std::result::Result;

use crate::display::DisplayImage;
use attributes::{AttributeError, Attributes};
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
    #[error("cannot read {}: not a readable OpenEXR file ({message})", path.display())]
    NotExr { path: PathBuf, message: String },
    #[error(transparent)]
    Attribute(#[from] AttributeError),
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
    let channels = AnyChannels::sort(channels.into());
    // One value per key (a later one replaces an earlier one, as in the file's header).
    let mut unique: std::collections::BTreeMap<String, String> = metadata.iter().cloned().collect();
    unique.remove(CHECKSUM_KEY);
    let mut metadata: Metadata = unique.into_iter().collect();
    metadata.push((CHECKSUM_KEY.to_string(), content_sha256(&metadata, &channels)));
    let layer = Layer::new(size, LayerAttributes::default(), Encoding::FAST_LOSSLESS, channels);
    let mut image = Image::from_layer(layer);
    for (key, value) in &metadata {
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

/// The first layer of an EXR and its `pathlab:KEY` attributes, read strictly (`attributes`).
pub(crate) fn read_exr_layer(path: &Path) -> Result<(Layer<AnyChannels<FlatSamples>>, Attributes), OutputError> {
    let fail = |message: String| OutputError::Read { path: path.to_path_buf(), message };
    if !path.is_file() {
        return Err(fail("no such file".into()));
    }
    // The file as OpenEXR first (a truncated or foreign file is named as such), then its
    // pathlab attributes as written.
    let image = read_all_flat_layers_from_file(path).map_err(|e| OutputError::NotExr { path: path.to_path_buf(), message: e.to_string() })?;
    let attributes = Attributes::read(path)?;
    let layer = image.layer_data.into_iter().next().ok_or_else(|| fail("the EXR has no layer".into()))?;
    if let Some(recorded) = attributes.get(CHECKSUM_KEY) {
        let mut metadata = attributes.metadata();
        metadata.retain(|(k, _)| k != CHECKSUM_KEY);
        if content_sha256(&metadata, &layer.channel_data) != recorded {
            return Err(fail(format!(
                "its content does not match the checksum in its header (pathlab:{CHECKSUM_KEY}): the file was altered or damaged after pathlab wrote it"
            )));
        }
    }
    Ok((layer, attributes))
}

/// The attribute holding `content_sha256` of the rest of the file.
pub const CHECKSUM_KEY: &str = "data_sha256";

/// SHA-256 (hex) of what pathlab reads from a file: its pathlab attributes but the checksum
/// (sorted by key, as `key=value` lines), then every channel in name order (its name, its
/// sample type, its values little-endian, row-major). Every file pathlab writes records it as
/// `pathlab:data_sha256`; a file that records one is refused when it does not match.
pub fn content_sha256(metadata: &[(String, String)], channels: &AnyChannels<FlatSamples>) -> String {
    use sha2::{Digest, Sha256};
    let mut hasher = Sha256::new();
    let mut sorted: Vec<&(String, String)> = metadata.iter().collect();
    sorted.sort();
    for (k, v) in sorted {
        hasher.update(format!("{k}={v}\n").as_bytes());
    }
    for c in &channels.list {
        hasher.update(format!("channel {}\n", c.name).as_bytes());
        match &c.sample_data {
            FlatSamples::F16(v) => {
                hasher.update(b"f16\n");
                v.iter().for_each(|x| hasher.update(x.to_bits().to_le_bytes()));
            }
            FlatSamples::F32(v) => {
                hasher.update(b"f32\n");
                v.iter().for_each(|x| hasher.update(x.to_le_bytes()));
            }
            FlatSamples::U32(v) => {
                hasher.update(b"u32\n");
                v.iter().for_each(|x| hasher.update(x.to_le_bytes()));
            }
        }
    }
    hasher.finalize().iter().map(|b| format!("{b:02x}")).collect()
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

/// Like `read_exr`, also telling whether the file carries variance channels. Refused, naming
/// the file and the first pixel: a non-finite value in any channel, a negative variance.
pub fn read_exr_image(path: &Path) -> Result<ExrImage, OutputError> {
    let fail = |message: String| OutputError::Read { path: path.to_path_buf(), message };
    let (layer, attributes) = read_exr_layer(path)?;
    let (w, h) = (layer.size.width(), layer.size.height());
    // Colour and variance channels are floating point (half or single); each set complete.
    for prefix in ["", "variance."] {
        let present: Vec<&str> = ["R", "G", "B"].into_iter().filter(|c| layer.channel_data.list.iter().any(|ch| ch.name == Text::from(format!("{prefix}{c}").as_str()))).collect();
        if !present.is_empty() && present.len() < 3 {
            return Err(fail(format!("it has channels {} but not all of {prefix}R, {prefix}G, {prefix}B", present.iter().map(|c| format!("{prefix}{c}")).collect::<Vec<_>>().join(", "))));
        }
    }
    if let Some(c) = layer.channel_data.list.iter().find(|c| {
        let n = c.name.to_string();
        ["R", "G", "B", "variance.R", "variance.G", "variance.B"].contains(&n.as_str()) && matches!(c.sample_data, FlatSamples::U32(_))
    }) {
        return Err(fail(format!("channel {} holds integers, not floating-point values", c.name)));
    }
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
    let at = |i: usize| format!("pixel ({}, {})", i % w.max(1), i / w.max(1));
    const RGB: [&str; 3] = ["R", "G", "B"];
    for (i, p) in mean.iter().enumerate() {
        if let Some(c) = (0..3).find(|&c| !p[c].is_finite()) {
            return Err(fail(format!("{} has a non-finite {} ({}): the image cannot be scored or shown", at(i), RGB[c], p[c])));
        }
        if let Some(c) = (0..3).find(|&c| p[c] < 0.0) {
            return Err(fail(format!(
                "{} has a negative {} ({}): radiance is not negative (a reconstruction filter that rings, such as \
                 Lanczos or Mitchell, makes it so: render references with a box filter)",
                at(i),
                RGB[c],
                p[c]
            )));
        }
    }
    if has_variance {
        for (i, v) in variance.iter().enumerate() {
            if let Some(c) = (0..3).find(|&c| !(v[c].is_finite() && v[c] >= 0.0)) {
                return Err(fail(format!("{} has variance.{} = {}: a variance is a finite number of at least 0", at(i), RGB[c], v[c])));
            }
        }
    }
    let spp = attributes.whole_opt("spp", u64::MAX)?.unwrap_or(0);
    let film = Film { width: w as u32, height: h as u32, spp, mean, variance };
    Ok(ExrImage { film, metadata: attributes.metadata(), has_variance })
}
