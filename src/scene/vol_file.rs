//! Mitsuba's `.vol` grid files (`src/render/volumegrid.cpp`), as grid volumes (textures, media)
//! and the `sdfgrid` shape read them: "VOL", version 3, encoding 1 (float32), the cell counts
//! along x, y and z, the channel count, the bounding box (xmin, ymin, zmin, xmax, ymax, zmax),
//! then the values, little-endian, data[((z * ny + y) * nx + x) * channels + c]. What the values
//! may be (a colour's are finite and >= 0, a distance's any finite number) is the reader's
//! caller's to check.

use std::path::Path;

/// The largest cell count a file may declare (about 4 GiB of floats at three channels).
const MAX_CELLS: u64 = 1 << 28;

/// A `.vol` file's contents.
#[derive(Debug, Clone, PartialEq)]
pub struct VolFile {
    /// Values along x, y, z.
    pub res: [u32; 3],
    pub channels: u32,
    /// The values as in the file (x fastest, then y, then z, channels innermost).
    pub data: Vec<f32>,
    /// The box the file gives: xmin, ymin, zmin, xmax, ymax, zmax.
    pub bbox: [f32; 6],
}

impl VolFile {
    /// The grid point (x, y, z) of value index `i` (channel 0 of it).
    pub fn position(&self, i: usize) -> [usize; 3] {
        let c = i / self.channels as usize;
        let [nx, ny, _] = self.res.map(|n| n as usize);
        [c % nx, (c / nx) % ny, c / (nx * ny)]
    }
}

/// The contents of a `.vol` file, or what is wrong with its format.
pub fn read_vol(path: &Path) -> Result<VolFile, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read it: {e}"))?;
    if bytes.len() < 48 || &bytes[..3] != b"VOL" {
        return Err("not a Mitsuba .vol grid (it must begin with \"VOL\" and a 48-byte header)".into());
    }
    if bytes[3] != 3 {
        return Err(format!("version {} (Mitsuba's grids are version 3)", bytes[3]));
    }
    let int = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let encoding = int(4);
    if encoding != 1 {
        return Err(format!("encoding {encoding} (only 1, float32, is supported, as in Mitsuba)"));
    }
    let (nx, ny, nz, channels) = (int(8), int(12), int(16), int(20));
    if nx <= 0 || ny <= 0 || nz <= 0 {
        return Err(format!("cell counts {nx} x {ny} x {nz} (each must be at least 1)"));
    }
    if channels <= 0 {
        return Err(format!("{channels} channels (at least 1)"));
    }
    let cells = nx as u64 * ny as u64 * nz as u64;
    if cells > MAX_CELLS {
        return Err(format!("{nx} x {ny} x {nz} cells (at most {MAX_CELLS})"));
    }
    let floats = cells * channels as u64;
    let expected = 48 + 4 * floats;
    if bytes.len() as u64 != expected {
        return Err(format!("{} bytes where its header ({nx} x {ny} x {nz} cells, {channels} channels) needs {expected}", bytes.len()));
    }
    let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let bbox = [float(24), float(28), float(32), float(36), float(40), float(44)];
    let data: Vec<f32> = bytes[48..].chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes"))).collect();
    Ok(VolFile { res: [nx as u32, ny as u32, nz as u32], channels: channels as u32, data, bbox })
}
