//! Mitsuba's `serialized` mesh format (`src/shapes/serialized.cpp`), read through flate2 (zlib):
//! a file of one or more shapes, each a little-endian header (u16 0x041C, u16 version 3 or 4)
//! then a zlib stream: u32 flags (0x0001 vertex normals, 0x0002 texture coordinates, 0x0008
//! vertex colours, 0x0010 face normals, 0x1000 single, 0x2000 double precision), the shape's
//! name (version 4: a NUL-terminated string), u64 vertex and u64 triangle counts, the positions,
//! normals, texture coordinates and colours (3, 3, 2, 3 numbers per vertex, f32 or f64), then
//! 3 u32 indices per triangle. The file ends with each shape's byte offset (u64 in version 4,
//! u32 in version 3) and a u32 count of shapes, which `shape_index` reads. As Mitsuba 3.9.1:
//! colours are skipped, texture coordinates are kept as written (no v flip), and the file's
//! face-normals flag does not decide the shading (the shape's `face_normals` does).

use std::io::Read;
use std::path::Path;

use glam::DVec3;

use super::{check, MeshData, MeshFileError};

const HEADER: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;

/// Reads shape `shape_index` (0 the first) of a serialized file's bytes.
pub fn read(path: &Path, bytes: &[u8], shape_index: u32) -> Result<MeshData, MeshFileError> {
    let fail = |message: String| MeshFileError::new(path, None, message);
    let u16_at = |at: usize| bytes.get(at..at + 2).map(|b| u16::from_le_bytes([b[0], b[1]]));
    let (Some(format), Some(version)) = (u16_at(0), u16_at(2)) else {
        return Err(fail("not a Mitsuba serialized mesh: the file is shorter than its header".into()));
    };
    if format != HEADER {
        return Err(fail(format!("not a Mitsuba serialized mesh: the file starts with 0x{format:04X}, not 0x041C")));
    }
    if version != 3 && version != 4 {
        return Err(fail(format!("serialized mesh version {version} is not supported (Mitsuba writes 3 and 4)")));
    }
    // Where the shape starts: the table of offsets at the file's end.
    let start = if shape_index == 0 {
        0
    } else {
        let n = bytes.len();
        let count = bytes.get(n.saturating_sub(4)..).filter(|b| b.len() == 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        let Some(count) = count else { return Err(fail("the file has no table of shapes".into())) };
        if shape_index >= count {
            return Err(fail(format!("shape_index {shape_index} is out of range: the file holds {count} shapes (0 to {})", count.saturating_sub(1))));
        }
        let entry = if version == 4 { 8 } else { 4 };
        let at = n.checked_sub(4 + entry * (count - shape_index) as usize).ok_or_else(|| fail("the table of shapes is cut short".into()))?;
        let offset = if version == 4 {
            u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes")) as usize
        } else {
            u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as usize
        };
        if offset + 4 > n || u16_at(offset) != Some(HEADER) {
            return Err(fail(format!("the table of shapes points shape {shape_index} to byte {offset}, where no shape starts")));
        }
        offset
    };
    let mut z = flate2::read::ZlibDecoder::new(&bytes[start + 4..]);
    let mut read_exact = |n: usize, what: &str| -> Result<Vec<u8>, MeshFileError> {
        let mut buf = vec![0u8; n];
        z.read_exact(&mut buf).map_err(|e| fail(format!("shape {shape_index}: cannot read its {what}: {e}")))?;
        Ok(buf)
    };
    let flags = u32::from_le_bytes(read_exact(4, "flags")?.try_into().expect("4 bytes"));
    if version == 4 {
        // The shape's name, NUL-terminated.
        let mut len = 0;
        while read_exact(1, "name")?[0] != 0 {
            len += 1;
            if len > 1 << 16 {
                return Err(fail(format!("shape {shape_index}: its name does not end")));
            }
        }
    }
    let vertices = u64::from_le_bytes(read_exact(8, "vertex count")?.try_into().expect("8 bytes"));
    let triangles = u64::from_le_bytes(read_exact(8, "triangle count")?.try_into().expect("8 bytes"));
    // Refuse counts the file cannot hold before allocating for them.
    let width = if flags & DOUBLE_PRECISION != 0 { 8 } else { 4 };
    if vertices > u32::MAX as u64 || triangles > (u32::MAX / 3) as u64 || (vertices * 3 * width) as usize > 64 * bytes.len().max(1 << 20) {
        return Err(fail(format!("shape {shape_index}: {vertices} vertices and {triangles} triangles cannot be in a file of {} bytes", bytes.len())));
    }
    let mut numbers = |count: u64, what: &str| -> Result<Vec<f64>, MeshFileError> {
        let raw = read_exact((count * width) as usize, what)?;
        Ok(if width == 8 {
            raw.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes"))).collect()
        } else {
            raw.chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")) as f64).collect()
        })
    };
    let vec3s = |v: Vec<f64>| v.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect::<Vec<_>>();
    let positions = vec3s(numbers(vertices * 3, "positions")?);
    let normals = if flags & HAS_NORMALS != 0 { vec3s(numbers(vertices * 3, "normals")?) } else { Vec::new() };
    let uvs = if flags & HAS_TEXCOORDS != 0 { numbers(vertices * 2, "texture coordinates")?.chunks_exact(2).map(|c| [c[0], c[1]]).collect() } else { Vec::new() };
    if flags & HAS_COLORS != 0 {
        numbers(vertices * 3, "vertex colours")?;
    }
    let raw = read_exact((triangles * 12) as usize, "triangles")?;
    let triangles: Vec<[u32; 3]> = raw
        .chunks_exact(12)
        .map(|c| [0, 1, 2].map(|k| u32::from_le_bytes(c[4 * k..4 * k + 4].try_into().expect("4 bytes"))))
        .collect();
    let mut notes = Vec::new();
    if flags & HAS_COLORS != 0 {
        notes.push((None, format!("shape {shape_index}: its vertex colours are ignored (as Mitsuba's RGB variants do)")));
    }
    let data = MeshData { positions, normals, uvs, triangles, attributes: Vec::new(), notes };
    check(path, &data, |_| None, |_| None)?;
    Ok(data)
}

/// The bytes of a serialized file holding `shapes` (version 4, single precision, each with its
/// normals and texture coordinates where it has them): Mitsuba's layout, for tests and tools.
pub fn write(shapes: &[MeshData]) -> Vec<u8> {
    use std::io::Write;
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for (i, m) in shapes.iter().enumerate() {
        offsets.push(out.len() as u64);
        out.extend(HEADER.to_le_bytes());
        out.extend(4u16.to_le_bytes());
        let mut body = Vec::new();
        let flags = 0x1000 | if m.normals.is_empty() { 0 } else { HAS_NORMALS } | if m.uvs.is_empty() { 0 } else { HAS_TEXCOORDS };
        body.extend((flags as u32).to_le_bytes());
        body.extend(format!("shape{i}\0").as_bytes());
        body.extend((m.positions.len() as u64).to_le_bytes());
        body.extend((m.triangles.len() as u64).to_le_bytes());
        let mut push = |x: f64| body.extend((x as f32).to_le_bytes());
        m.positions.iter().for_each(|p| p.to_array().into_iter().for_each(&mut push));
        m.normals.iter().for_each(|n| n.to_array().into_iter().for_each(&mut push));
        m.uvs.iter().for_each(|uv| uv.iter().for_each(|x| push(*x)));
        m.triangles.iter().flatten().for_each(|i| body.extend(i.to_le_bytes()));
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&body).expect("writing to memory");
        out.extend(z.finish().expect("writing to memory"));
    }
    offsets.iter().for_each(|o| out.extend(o.to_le_bytes()));
    out.extend((shapes.len() as u32).to_le_bytes());
    out
}
