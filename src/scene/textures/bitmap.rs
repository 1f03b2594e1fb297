//! Mitsuba 3's `bitmap` texture: an image file looked up at the hit's uv (after `to_uv`), with
//! bilinear or nearest filtering and repeat, mirror or clamp wrapping, as Dr.Jit's `Texture`
//! does it on the CPU (uv (0, 0) is the image's top-left corner; a texel's centre is at
//! ((x + 1/2) / width, (y + 1/2) / height)). The kernel's lookup is `eval_bitmap_texture` in
//! shaders/texture.wgsl; `Bitmap::eval` is its host twin, in the same f32 steps.

use std::path::PathBuf;
use std::sync::Arc;

use crate::scene::bsdf_data::BsdfData;
use crate::scene::image_file::{Image, Texels, decode_table};

/// The kinds' number in the BSDF data (`TEXTURE_BITMAP` in texture.wgsl).
pub const TEXTURE_BITMAP: u32 = 1;
/// Numbers of a bitmap's record before its decode table or texels.
pub const BITMAP_HEADER: usize = 12;

/// How a lookup between texel centres is filtered (Mitsuba's `filter_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Bilinear,
}

/// What a lookup outside [0, 1)^2 reads (Mitsuba's `wrap_mode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles the plane.
    Repeat,
    /// The image tiles the plane, every other tile mirrored.
    Mirror,
    /// The edge texels extend outwards.
    Clamp,
}

impl Filter {
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
        }
    }
    pub fn parse(s: &str) -> Option<Filter> {
        [Filter::Nearest, Filter::Bilinear].into_iter().find(|f| f.name() == s)
    }
}

impl Wrap {
    pub fn name(self) -> &'static str {
        match self {
            Wrap::Repeat => "repeat",
            Wrap::Mirror => "mirror",
            Wrap::Clamp => "clamp",
        }
    }
    pub fn parse(s: &str) -> Option<Wrap> {
        [Wrap::Repeat, Wrap::Mirror, Wrap::Clamp].into_iter().find(|w| w.name() == s)
    }

    /// Its number in a texture record (`bitmap_wrap` in texture.wgsl): 0 repeat, 1 mirror,
    /// 2 clamp.
    pub fn code(self) -> f32 {
        match self {
            Wrap::Repeat => 0.0,
            Wrap::Mirror => 1.0,
            Wrap::Clamp => 2.0,
        }
    }

    /// Texel index `i` of `n` wrapped into [0, n).
    pub fn apply(self, i: i32, n: i32) -> i32 {
        match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let p = i.rem_euclid(2 * n);
                if p >= n { 2 * n - 1 - p } else { p }
            }
        }
    }
}

/// A bitmap texture and its parameters.
#[derive(Debug, Clone)]
pub struct Bitmap {
    /// The image file as found (for messages, `convert` and the scene hash).
    pub file: PathBuf,
    pub image: Arc<Image>,
    /// SHA-256 of the decoded texels (the scene hash's record of the image's content).
    pub content_hash: String,
    pub filter: Filter,
    pub wrap: Wrap,
    /// The image's channels are read as linear (no sRGB decoding).
    pub raw: bool,
    /// `to_uv`'s first two rows: uv' = (m00 u + m01 v + m02, m10 u + m11 v + m12) (Mitsuba's
    /// 3x3 `to_uv`, the upper-left 3x3 of the XML's 4x4 transform).
    pub to_uv: [[f64; 3]; 2],
}

impl PartialEq for Bitmap {
    fn eq(&self, o: &Bitmap) -> bool {
        self.file == o.file && self.content_hash == o.content_hash && self.filter == o.filter && self.wrap == o.wrap && self.raw == o.raw && self.to_uv == o.to_uv
    }
}

/// `to_uv` that changes nothing.
pub const IDENTITY_UV: [[f64; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

impl Bitmap {
    pub fn new(file: PathBuf, image: Image, filter: Filter, wrap: Wrap, raw: bool, to_uv: [[f64; 3]; 2]) -> Bitmap {
        let content_hash = image.content_hash();
        Bitmap { file, image: Arc::new(image), content_hash, filter, wrap, raw, to_uv }
    }

    /// The uv transform in f32, as the kernel has it.
    fn to_uv_f32(&self) -> [f32; 6] {
        let m = self.to_uv;
        [m[0][0] as f32, m[0][1] as f32, m[0][2] as f32, m[1][0] as f32, m[1][1] as f32, m[1][2] as f32]
    }

    fn texel(&self, x: i32, y: i32) -> [f32; 3] {
        let (w, h) = (self.image.width as i32, self.image.height as i32);
        self.image.texel(self.wrap.apply(x, w) as u32, self.wrap.apply(y, h) as u32)
    }

    /// `uv` after `to_uv`, in f32 as the kernel computes it (`bitmap_uv`).
    fn apply_to_uv(&self, uv: [f32; 2]) -> (f32, f32) {
        let m = self.to_uv_f32();
        (m[0] * uv[0] + m[1] * uv[1] + m[2], m[3] * uv[0] + m[4] * uv[1] + m[5])
    }

    /// The cell of a bilinear lookup at (u, v) after `to_uv` (`bilinear_cell`): texel centres at
    /// integers, position - 1/2, its floor the lower-left texel; that texel and the fractions.
    fn bilinear_cell(&self, u: f32, v: f32) -> (i32, i32, f32, f32) {
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        let (px, py) = (u * w - 0.5, v * h - 0.5);
        let (x0, y0) = (px.floor(), py.floor());
        (x0 as i32, y0 as i32, px - x0, py - y0)
    }

    /// Its value at `uv`, in f32 as the kernel computes it (`eval_bitmap_texture`).
    pub fn eval(&self, uv: [f32; 2]) -> [f32; 3] {
        let (u, v) = self.apply_to_uv(uv);
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        match self.filter {
            Filter::Nearest => self.texel((u * w).floor() as i32, (v * h).floor() as i32),
            Filter::Bilinear => {
                let (x0, y0, fx, fy) = self.bilinear_cell(u, v);
                let (t00, t10, t01, t11) = (self.texel(x0, y0), self.texel(x0 + 1, y0), self.texel(x0, y0 + 1), self.texel(x0 + 1, y0 + 1));
                std::array::from_fn(|c| {
                    let top = t00[c] + fx * (t10[c] - t00[c]);
                    let bottom = t01[c] + fx * (t11[c] - t01[c]);
                    top + fy * (bottom - top)
                })
            }
        }
    }

    /// Its gradient in uv as Mitsuba's `eval_1_grad` gives it, in f32 as the kernel computes it
    /// (`bitmap_gradient`): zero for nearest filtering; for bilinear, the partials of the
    /// interpolant of the four texels' luminances in pixel coordinates,
    ///   df/dx = (1 - fy)(f10 - f00) + fy (f11 - f01),  df/dy = (1 - fx)(f01 - f00) + fx (f11 - f10),
    /// taken through `to_uv` by its transpose and times the resolution, (m00 df/dx + m10 df/dy) w
    /// and (m01 df/dx + m11 df/dy) h, as Mitsuba writes it.
    pub fn eval_1_grad(&self, uv: [f32; 2]) -> [f32; 2] {
        if self.filter == Filter::Nearest {
            return [0.0; 2];
        }
        let (u, v) = self.apply_to_uv(uv);
        let (x0, y0, fx, fy) = self.bilinear_cell(u, v);
        let lum = super::luminance_f32;
        let (f00, f10, f01, f11) = (lum(self.texel(x0, y0)), lum(self.texel(x0 + 1, y0)), lum(self.texel(x0, y0 + 1)), lum(self.texel(x0 + 1, y0 + 1)));
        let dx = (1.0 - fy) * (f10 - f00) + fy * (f11 - f01);
        let dy = (1.0 - fx) * (f01 - f00) + fx * (f11 - f10);
        let m = self.to_uv_f32();
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        [(m[0] * dx + m[3] * dy) * w, (m[1] * dx + m[4] * dy) * h]
    }

    /// Numbers of its record in the BSDF data.
    pub fn record_len(&self) -> u64 {
        let texels = self.image.width as u64 * self.image.height as u64;
        BITMAP_HEADER as u64
            + match self.image.texels {
                Texels::Bytes(_) => 256 + texels,
                Texels::Float(_) => 3 * texels,
            }
    }

    /// Its record: kind, width, height, filter (0 nearest, 1 bilinear), wrap (0 repeat,
    /// 1 mirror, 2 clamp), storage (0 float RGB, 1 bytes), to_uv's six numbers; then for bytes
    /// the 256-entry decode table and one number per texel (r + 256 g + 65536 b, exact in f32),
    /// for floats three per texel; rows from the top.
    pub fn pack(&self, data: &mut BsdfData) -> u32 {
        let bytes = matches!(self.image.texels, Texels::Bytes(_));
        let mut header = vec![
            TEXTURE_BITMAP as f32,
            self.image.width as f32,
            self.image.height as f32,
            (self.filter == Filter::Bilinear) as u32 as f32,
            self.wrap.code(),
            bytes as u32 as f32,
        ];
        header.extend(self.to_uv_f32());
        debug_assert_eq!(header.len(), BITMAP_HEADER);
        let start = data.push(&header);
        match &self.image.texels {
            Texels::Bytes(b) => {
                data.push(decode_table(self.image.srgb));
                data.0.extend(b.iter().map(|t| (t[0] as u32 + 256 * t[1] as u32 + 65536 * t[2] as u32) as f32));
            }
            Texels::Float(f) => data.0.extend(f.iter().flatten()),
        }
        start
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient is the bilinear interpolant's: central differences of `eval`'s luminance
    /// inside a texel cell agree with it (to f32 rounding of the differences), through a
    /// `to_uv` that scales and shifts (where Mitsuba's order of the resolution factor and the
    /// transpose equals the chain rule's), on a 5x3 image; nearest filtering has none.
    #[test]
    fn the_gradient_is_the_interpolants() {
        let texels: Vec<[f32; 3]> = (0..15).map(|i| [((i * 7) % 11) as f32 / 10.0, ((i * 3) % 5) as f32 / 4.0, (i % 2) as f32]).collect();
        let image = Image { width: 5, height: 3, texels: Texels::Float(texels), srgb: false };
        let to_uv = [[1.5, 0.25, 0.1], [-0.5, 2.0, 0.3]];
        let diagonal = Bitmap::new(PathBuf::from("t.exr"), image.clone(), Filter::Bilinear, Wrap::Repeat, true, [[1.5, 0.0, 0.1], [0.0, 2.0, 0.3]]);
        let lum_d = |uv: [f32; 2]| {
            let (c, w) = (diagonal.eval(uv), crate::scene::emitters::LUMINANCE_WEIGHTS);
            w[0] * c[0] as f64 + w[1] * c[1] as f64 + w[2] * c[2] as f64
        };
        for (u, v) in [(0.13f32, 0.41f32), (0.57, 0.77), (0.9, 0.05), (0.33, 0.63)] {
            let g = diagonal.eval_1_grad([u, v]);
            let h = 1e-3f32;
            let du = (lum_d([u + h, v]) - lum_d([u - h, v])) / (2.0 * h as f64);
            let dv = (lum_d([u, v + h]) - lum_d([u, v - h])) / (2.0 * h as f64);
            assert!((g[0] as f64 - du).abs() < 2e-3 * (1.0 + du.abs()) && (g[1] as f64 - dv).abs() < 2e-3 * (1.0 + dv.abs()), "at ({u}, {v}): {g:?} against ({du}, {dv})");
        }
        let nearest = Bitmap::new(PathBuf::from("t.exr"), image, Filter::Nearest, Wrap::Repeat, true, to_uv);
        assert_eq!(nearest.eval_1_grad([0.3, 0.3]), [0.0, 0.0]);
    }

    #[test]
    fn wrap_modes_fold_indices_as_drjit_does() {
        let n = 3;
        let got = |w: Wrap| (-7..8).map(|i| w.apply(i, n)).collect::<Vec<_>>();
        assert_eq!(got(Wrap::Repeat), [2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1]);
        assert_eq!(got(Wrap::Clamp), [0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2]);
        // Mirror: ... 2 1 0 | 0 1 2 | 2 1 0 ...
        assert_eq!(got(Wrap::Mirror), [0, 0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]);
    }
}
