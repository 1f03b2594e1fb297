//! Image files as textures and environment maps read them (Mitsuba 3's `Bitmap`): PNG, JPEG and BMP
//! (8 or 16 bits per channel, sRGB-encoded), Radiance HDR and OpenEXR (linear floats). Grey
//! images become grey RGB, alpha is dropped (as Mitsuba's bitmap texture drops it).
//!
//! 8-bit images keep their bytes, decoded per texel on lookup through a 256-entry table (as
//! Mitsuba 3.9 stores them and decodes on lookup): 4 bytes per texel on the GPU instead of 12.
//! 16-bit images are decoded here into linear floats (Mitsuba converts them at load, too).

use std::path::Path;

/// An image's texels, row by row from the top (Mitsuba's uv (0, 0) is the top-left corner).
#[derive(Clone, PartialEq)]
pub enum Texels {
    /// 8-bit channels as stored; decoded by `decode_table`.
    Bytes(Vec<[u8; 3]>),
    /// Linear values.
    Float(Vec<[f32; 3]>),
}

/// A decoded image.
#[derive(Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub texels: Texels,
    /// 8-bit channels are sRGB-encoded (PNG and JPEG unless read `raw`).
    pub srgb: bool,
}

impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match (&self.texels, self.srgb) {
            (Texels::Bytes(_), true) => "8-bit sRGB",
            (Texels::Bytes(_), false) => "8-bit linear",
            (Texels::Float(_), _) => "float",
        };
        write!(f, "Image({}x{}, {kind})", self.width, self.height)
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1): an encoded value in [0, 1] to linear.
pub fn srgb_to_linear(v: f64) -> f64 {
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

/// The linear value of each 8-bit code: sRGB-decoded, or code / 255 (Mitsuba's `raw`). Built
/// once per process: texel reads on the host (means, luminance distributions, twins) go
/// through it per texel.
pub fn decode_table(srgb: bool) -> &'static [f32; 256] {
    static TABLES: std::sync::OnceLock<[[f32; 256]; 2]> = std::sync::OnceLock::new();
    let tables = TABLES.get_or_init(|| {
        [false, true].map(|srgb| std::array::from_fn(|c| if srgb { srgb_to_linear(c as f64 / 255.0) as f32 } else { c as f32 * (1.0f32 / 255.0) }))
    });
    &tables[srgb as usize]
}

impl Image {
    /// Texel (x, y) as linear RGB (x from the left, y from the top).
    pub fn texel(&self, x: u32, y: u32) -> [f32; 3] {
        let i = (y * self.width + x) as usize;
        match &self.texels {
            Texels::Float(t) => t[i],
            Texels::Bytes(b) => {
                let table = decode_table(self.srgb);
                b[i].map(|c| table[c as usize])
            }
        }
    }

    /// The mean of its linear texels, per channel.
    pub fn mean(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for y in 0..self.height {
            for x in 0..self.width {
                let t = self.texel(x, y);
                for c in 0..3 {
                    sum[c] += t[c] as f64;
                }
            }
        }
        let n = (self.width as f64 * self.height as f64).max(1.0);
        sum.map(|s| s / n)
    }

    /// SHA-256 (first 16 hex digits) of its size, encoding and texels: the scene hash's record
    /// of an image's content.
    pub fn content_hash(&self) -> String {
        use sha2::Digest;
        let mut h = sha2::Sha256::new();
        h.update(self.width.to_le_bytes());
        h.update(self.height.to_le_bytes());
        h.update([self.srgb as u8]);
        match &self.texels {
            Texels::Bytes(b) => b.iter().for_each(|t| h.update(t)),
            Texels::Float(f) => f.iter().for_each(|t| t.iter().for_each(|c| h.update(c.to_le_bytes()))),
        }
        h.finalize().iter().take(8).map(|b| format!("{b:02x}")).collect()
    }

    /// Bytes on the GPU: 4 per 8-bit texel (its three codes in one number), 12 per float texel.
    pub fn gpu_bytes(&self) -> u64 {
        let per = match self.texels {
            Texels::Bytes(_) => 4,
            Texels::Float(_) => 12,
        };
        self.width as u64 * self.height as u64 * per
    }
}

/// Reads an image file by its extension (png, jpg/jpeg, bmp, hdr, exr). `raw`: 8- and 16-bit channels
/// are linear (code / max), not sRGB. Errors say what is wrong (the caller names the file).
pub fn read_image(path: &Path, raw: bool) -> Result<Image, String> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let image = match ext.as_str() {
        "exr" => read_exr(path)?,
        "png" | "jpg" | "jpeg" | "bmp" | "hdr" => read_with_image_crate(path, raw)?,
        _ => return Err(format!("unsupported image format \".{ext}\" (pathlab reads .png, .jpg, .jpeg, .bmp, .hdr and .exr)")),
    };
    if image.width == 0 || image.height == 0 {
        return Err("the image has no pixels".into());
    }
    if let Texels::Float(t) = &image.texels
        && let Some(i) = t.iter().position(|p| p.iter().any(|c| !c.is_finite()))
    {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        return Err(format!("pixel ({x}, {y}) (from the top left) is not finite: {:?}", t[i]));
    }
    Ok(image)
}

fn read_with_image_crate(path: &Path, raw: bool) -> Result<Image, String> {
    use image::DynamicImage as D;
    let reader = image::ImageReader::open(path).map_err(|e| format!("cannot read it: {e}"))?;
    let reader = reader.with_guessed_format().map_err(|e| format!("cannot read it: {e}"))?;
    let decoded = reader.decode().map_err(|e| format!("cannot decode it: {e}"))?;
    let (width, height) = (decoded.width(), decoded.height());
    let float = |pixels: Vec<[f32; 3]>| Image { width, height, texels: Texels::Float(pixels), srgb: false };
    let sixteen = |pixels: Vec<[u16; 3]>| {
        let decode = |c: u16| {
            let v = c as f64 / 65535.0;
            (if raw { v } else { srgb_to_linear(v) }) as f32
        };
        float(pixels.into_iter().map(|p| p.map(decode)).collect())
    };
    Ok(match decoded {
        D::ImageLuma8(_) | D::ImageLumaA8(_) | D::ImageRgb8(_) | D::ImageRgba8(_) => {
            let rgb = decoded.to_rgb8();
            Image { width, height, texels: Texels::Bytes(rgb.pixels().map(|p| p.0).collect()), srgb: !raw }
        }
        D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_) => {
            sixteen(decoded.to_rgb16().pixels().map(|p| p.0).collect())
        }
        D::ImageRgb32F(_) | D::ImageRgba32F(_) => float(decoded.to_rgb32f().pixels().map(|p| p.0).collect()),
        other => return Err(format!("unsupported channel layout {:?} (pathlab reads grey, grey+alpha, RGB and RGBA)", other.color())),
    })
}

fn read_exr(path: &Path) -> Result<self::Image, String> {
    use exr::prelude::*;
    // The first layer's R, G, B channels (alpha and other channels ignored), or its Y channel.
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| (resolution.width(), vec![[0.0f32; 3]; resolution.width() * resolution.height()]),
        |(width, pixels), position, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[position.y() * *width + position.x()] = [r, g, b];
        },
    );
    match image {
        Ok(image) => {
            let size = image.layer_data.size;
            Ok(self::Image { width: size.width() as u32, height: size.height() as u32, texels: Texels::Float(image.layer_data.channel_data.pixels.1), srgb: false })
        }
        Err(Error::NotSupported(what)) if what.contains("channel") || what.contains("rgb") || what.contains("RGB") => read_exr_grey(path),
        Err(e) => Err(format!("cannot read it as OpenEXR: {e}")),
    }
}

/// A grey EXR (one `Y` channel) as grey RGB.
fn read_exr_grey(path: &Path) -> Result<self::Image, String> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required("Y")
        .collect_pixels(
            |resolution, _| (resolution.width(), vec![[0.0f32; 3]; resolution.width() * resolution.height()]),
            |(width, pixels), position, (y,): (f32,)| {
                pixels[position.y() * *width + position.x()] = [y; 3];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| format!("cannot read it as OpenEXR (pathlab reads R, G, B or Y channels): {e}"))?;
    let size = image.layer_data.size;
    Ok(self::Image { width: size.width() as u32, height: size.height() as u32, texels: Texels::Float(image.layer_data.channel_data.pixels.1), srgb: false })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_decode_table_is_the_srgb_curve() {
        let t = decode_table(true);
        assert_eq!(t[0], 0.0);
        assert_eq!(t[255], 1.0);
        // The linear segment below 0.04045 (code 10) and the power above.
        assert!((t[10] as f64 - 10.0 / 255.0 / 12.92).abs() < 1e-9);
        assert!((t[128] as f64 - 0.2158605).abs() < 1e-6);
        assert!((decode_table(false)[51] - 0.2).abs() < 1e-7);
    }

    /// A BMP (mitsuba-data's projector scenes use one) reads as the same 8-bit sRGB texels as a
    /// PNG of the same pixels.
    #[test]
    fn a_bmp_reads_as_the_png_of_its_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let pixels = image::RgbImage::from_fn(3, 2, |x, y| image::Rgb([(40 * x + 7) as u8, (90 * y + 3) as u8, 200]));
        for ext in ["bmp", "png"] {
            pixels.save(dir.path().join(format!("p.{ext}"))).unwrap();
        }
        let bmp = read_image(&dir.path().join("p.bmp"), false).unwrap();
        assert_eq!(bmp, read_image(&dir.path().join("p.png"), false).unwrap());
        assert!(bmp.srgb && matches!(&bmp.texels, Texels::Bytes(t) if t[4] == [47, 93, 200]), "{bmp:?}");
    }
}
