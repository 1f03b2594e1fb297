//! Mitsuba's `volume` texture around a `gridvolume` (src/textures/volume.cpp,
//! src/volumes/grid.cpp): a 3D grid of colours looked up at the hit's world position, for
//! surfaces without a meaningful uv parametrisation. The grid fills the unit cube of its local
//! space (the volume's `to_world` places it; `use_grid_bbox` uses the box the file gives
//! instead); Dr.Jit's texture lookup, as the bitmap's in 3D: texel centres at (i + 1/2) / n,
//! trilinear or nearest, the indices folded by the wrap mode (clamp by default).
//!
//! The file is Mitsuba's `.vol` format (`scene::vol_file`). One channel is
//! a grey, three a linear RGB colour (Mitsuba's RGB variants read them unchanged, `raw` or
//! not); six, or anything else, are refused.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use sha2::{Digest, Sha256};

use super::bitmap::Wrap;
use crate::scene::bsdf_data::BsdfData;

/// The kind's number in the BSDF data (`TEXTURE_VOLUME` in texture.wgsl).
pub const TEXTURE_VOLUME: u32 = 2;
/// Numbers of its record before the cells: kind, nx, ny, nz, channels, filter, wrap, and the
/// 3x4 world-to-grid transform by rows.
pub const VOLUME_HEADER: usize = 19;
/// A grid volume as a texture.
#[derive(Debug, Clone)]
pub struct GridVolume {
    /// The `.vol` file as found.
    pub file: PathBuf,
    /// Cells along x, y, z.
    pub res: [u32; 3],
    /// 1 (grey) or 3 (RGB).
    pub channels: u32,
    /// The cells, as in the file.
    pub data: Arc<Vec<f32>>,
    /// SHA-256 of the cells (the scene hash's record of the file's content).
    pub content_hash: String,
    /// Trilinear (default) or nearest.
    pub trilinear: bool,
    pub wrap: Wrap,
    /// `raw` as given (no effect in an RGB renderer: Mitsuba's spectral variants alone convert).
    pub raw: bool,
    /// World to the grid's unit cube: rows of a 3x4 affine map (the inverse of the volume's
    /// `to_world`, then, with `use_grid_bbox`, the file's box onto the unit cube).
    pub to_local: [[f64; 4]; 3],
}

impl PartialEq for GridVolume {
    fn eq(&self, o: &GridVolume) -> bool {
        self.file == o.file && self.content_hash == o.content_hash && self.trilinear == o.trilinear && self.wrap == o.wrap && self.raw == o.raw && self.to_local == o.to_local
    }
}

/// The cells of a `.vol` file as a texture's colours: (res, channels, cells, bounding box), or
/// what is wrong with it.
pub fn read_vol(path: &Path) -> Result<([u32; 3], u32, Vec<f32>, [f32; 6]), String> {
    let vol = crate::scene::vol_file::read_vol(path)?;
    if vol.channels != 1 && vol.channels != 3 {
        return Err(format!("{} channels (a texture reads 1, a grey, or 3, an RGB colour)", vol.channels));
    }
    if let Some(i) = vol.data.iter().position(|x| !x.is_finite() || *x < 0.0) {
        let [x, y, z] = vol.position(i);
        return Err(format!("cell ({x}, {y}, {z}) holds {} (a colour must be finite and >= 0)", vol.data[i]));
    }
    Ok((vol.res, vol.channels, vol.data, vol.bbox))
}

impl GridVolume {
    pub fn new(file: PathBuf, res: [u32; 3], channels: u32, data: Vec<f32>, trilinear: bool, wrap: Wrap, raw: bool, to_local: [[f64; 4]; 3]) -> GridVolume {
        let mut h = Sha256::new();
        for x in &data {
            h.update(x.to_le_bytes());
        }
        let content_hash = format!("{:x}", h.finalize());
        GridVolume { file, res, channels, data: Arc::new(data), content_hash, trilinear, wrap, raw, to_local }
    }

    fn to_local_f32(&self) -> [f32; 12] {
        let m = self.to_local;
        std::array::from_fn(|i| m[i / 4][i % 4] as f32)
    }

    /// Cell (x, y, z), wrapped, as RGB.
    fn cell(&self, x: i32, y: i32, z: i32) -> [f32; 3] {
        let [nx, ny, nz] = self.res.map(|n| n as i32);
        let (x, y, z) = (self.wrap.apply(x, nx), self.wrap.apply(y, ny), self.wrap.apply(z, nz));
        let i = ((z * ny + y) * nx + x) as usize * self.channels as usize;
        if self.channels == 1 { [self.data[i]; 3] } else { [self.data[i], self.data[i + 1], self.data[i + 2]] }
    }

    /// Its value at world position `p`, in f32 as the kernel computes it
    /// (`eval_volume_texture`).
    pub fn eval(&self, p: [f32; 3]) -> [f32; 3] {
        let m = self.to_local_f32();
        let q: [f32; 3] = std::array::from_fn(|r| m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3]);
        let n = self.res.map(|n| n as f32);
        if !self.trilinear {
            let c: [i32; 3] = std::array::from_fn(|k| (q[k] * n[k]).floor() as i32);
            return self.cell(c[0], c[1], c[2]);
        }
        let pos: [f32; 3] = std::array::from_fn(|k| q[k] * n[k] - 0.5);
        let base = pos.map(f32::floor);
        let f: [f32; 3] = std::array::from_fn(|k| pos[k] - base[k]);
        let [x0, y0, z0] = base.map(|b| b as i32);
        let lerp = |a: [f32; 3], b: [f32; 3], t: f32| -> [f32; 3] { std::array::from_fn(|c| a[c] + t * (b[c] - a[c])) };
        let plane = |z: i32| {
            let bottom = lerp(self.cell(x0, y0, z), self.cell(x0 + 1, y0, z), f[0]);
            let top = lerp(self.cell(x0, y0 + 1, z), self.cell(x0 + 1, y0 + 1, z), f[0]);
            lerp(bottom, top, f[1])
        };
        lerp(plane(z0), plane(z0 + 1), f[2])
    }

    /// The mean of its cells (Mitsuba's `mean()` of a grid is that of its data).
    pub fn mean(&self) -> [f64; 3] {
        let cells = (self.data.len() / self.channels as usize) as f64;
        let mut sum = [0.0f64; 3];
        for cell in self.data.chunks_exact(self.channels as usize) {
            for (c, s) in sum.iter_mut().enumerate() {
                *s += cell[if self.channels == 1 { 0 } else { c }] as f64;
            }
        }
        sum.map(|s| s / cells)
    }

    /// Numbers of its record in the BSDF data.
    pub fn record_len(&self) -> u64 {
        VOLUME_HEADER as u64 + self.data.len() as u64
    }

    /// Its record: kind, nx, ny, nz, channels, filter (0 nearest, 1 trilinear), wrap (0 repeat,
    /// 1 mirror, 2 clamp), the world-to-grid map's 12 numbers by rows; then the cells as in the
    /// file.
    pub fn pack(&self, data: &mut BsdfData) -> u32 {
        let mut header = vec![
            TEXTURE_VOLUME as f32,
            self.res[0] as f32,
            self.res[1] as f32,
            self.res[2] as f32,
            self.channels as f32,
            self.trilinear as u32 as f32,
            self.wrap.code(),
        ];
        header.extend(self.to_local_f32());
        debug_assert_eq!(header.len(), VOLUME_HEADER);
        let start = data.push(&header);
        data.0.extend(self.data.iter());
        start
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(trilinear: bool, wrap: Wrap) -> GridVolume {
        // 2 x 1 x 2 cells, one channel: x and z ramps.
        GridVolume::new(PathBuf::from("g.vol"), [2, 1, 2], 1, vec![0.0, 1.0, 2.0, 3.0], trilinear, wrap, false, [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    }

    #[test]
    fn lookups_are_drjits_texture_lookups() {
        let g = grid(true, Wrap::Clamp);
        // Cell centres at 1/4 and 3/4: exact there, halfway between them at 1/2.
        assert_eq!(g.eval([0.25, 0.5, 0.25]), [0.0; 3]);
        assert_eq!(g.eval([0.75, 0.5, 0.75]), [3.0; 3]);
        assert_eq!(g.eval([0.5, 0.5, 0.25]), [0.5; 3]);
        assert_eq!(g.eval([0.5, 0.5, 0.5]), [1.5; 3]);
        // Clamped beyond the centres.
        assert_eq!(g.eval([-3.0, 0.5, 0.25]), [0.0; 3]);
        let n = grid(false, Wrap::Repeat);
        assert_eq!(n.eval([0.6, 0.1, 0.4]), [1.0; 3]);
        assert_eq!(n.eval([1.6, 0.1, 1.6]), [3.0; 3]);
        assert_eq!(g.mean(), [1.5; 3]);
    }
}
