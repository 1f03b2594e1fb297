//! Stanford PLY (ASCII or binary) through ply-rs-bw: `vertex` elements with `x y z` and
//! optionally `nx ny nz`, `face` elements with a `vertex_indices` (or `vertex_index`) list,
//! polygons split into fans. In an ASCII file every element is one line, so an error in the
//! payload names its line; in a binary file it names the element.

use std::path::Path;

use glam::DVec3;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Encoding, Property};

use super::{check, MeshData, MeshFileError};

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

/// Vertex indices of a face's list, refusing negative ones.
fn indices(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&i| i as i64).collect(),
        _ => return None,
    })
}

pub(super) fn read(path: &Path, bytes: &[u8]) -> Result<MeshData, MeshFileError> {
    let parser = Parser::<DefaultElement>::new();
    let ply = parser
        .read_ply(&mut &bytes[..])
        .map_err(|e| MeshFileError::new(path, e.line(), format!("PLY: {}", e.to_string().lines().next().unwrap_or(""))))?;
    let ascii = matches!(ply.header.encoding, Encoding::Ascii);
    // Lines of the header: the payload's first element is on the next one.
    let header_lines = bytes.windows(10).position(|w| w == b"end_header").map(|at| bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1);
    let first_line_of = |element: &str| -> Option<usize> {
        if !ascii {
            return None;
        }
        let before: usize = ply.header.elements.iter().take_while(|(name, _)| name.as_str() != element).map(|(_, e)| e.count).sum();
        header_lines.map(|h| h + before + 1)
    };
    let vertex_line = first_line_of("vertex");
    let face_line = first_line_of("face");
    let at = |first: Option<usize>, i: usize| first.map(|l| l + i);
    let empty = Vec::new();
    let vertices = ply.payload.get("vertex").unwrap_or(&empty);
    let faces = ply.payload.get("face").unwrap_or(&empty);
    if vertices.is_empty() {
        return Err(MeshFileError::new(path, None, "the PLY file has no `vertex` element"));
    }
    let mut data = MeshData::default();
    let has_normals = ["nx", "ny", "nz"].iter().all(|k| vertices[0].contains_key(*k));
    // Texture coordinates under any of the names PLY writers use (Mitsuba reads the same).
    let uv_names = [["u", "v"], ["s", "t"], ["texture_u", "texture_v"], ["texture_s", "texture_t"]]
        .into_iter()
        .find(|names| names.iter().all(|k| vertices[0].contains_key(*k)));
    for (i, v) in vertices.iter().enumerate() {
        let get = |k: &str| {
            v.get(k).and_then(scalar).ok_or_else(|| MeshFileError::new(path, at(vertex_line, i), format!("vertex {i} has no numeric property `{k}`")))
        };
        data.positions.push(DVec3::new(get("x")?, get("y")?, get("z")?));
        if has_normals {
            data.normals.push(DVec3::new(get("nx")?, get("ny")?, get("nz")?));
        }
        if let Some([u, v]) = uv_names {
            data.uvs.push([get(u)?, get(v)?]);
        }
    }
    let mut triangle_lines = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        let line = at(face_line, f);
        let list = face
            .get("vertex_indices")
            .or_else(|| face.get("vertex_index"))
            .and_then(indices)
            .ok_or_else(|| MeshFileError::new(path, line, format!("face {f} has no integer list `vertex_indices`")))?;
        if list.len() < 3 {
            return Err(MeshFileError::new(path, line, format!("face {f} has {} vertices, a face needs at least 3", list.len())));
        }
        if let Some(&bad) = list.iter().find(|&&i| i < 0 || i as usize >= vertices.len()) {
            return Err(MeshFileError::new(
                path,
                line,
                format!("face {f}: vertex index {bad} is out of range (the file has {} vertices)", vertices.len()),
            ));
        }
        for k in 1..list.len() - 1 {
            data.triangles.push([list[0] as u32, list[k] as u32, list[k + 1] as u32]);
            triangle_lines.push(line);
        }
    }
    check(path, &data, |i| at(vertex_line, i), |t| triangle_lines.get(t).copied().flatten())?;
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                          element face 1\nproperty list uchar int vertex_indices\nend_header\n";

    #[test]
    fn texture_coordinates_under_their_usual_names() {
        for (u, v) in [("u", "v"), ("s", "t"), ("texture_u", "texture_v")] {
            let text = format!(
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 property float {u}\nproperty float {v}\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                 0 0 0 0 0\n1 0 0 1 0.25\n1 1 0 1 1\n3 0 1 2\n"
            );
            let d = read(Path::new("t.ply"), text.as_bytes()).unwrap();
            assert_eq!(d.uvs, vec![[0.0, 0.0], [1.0, 0.25], [1.0, 1.0]], "{u} {v}");
        }
        let d = read(Path::new("q.ply"), format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n").as_bytes()).unwrap();
        assert!(d.uvs.is_empty());
    }

    #[test]
    fn an_ascii_quad_and_its_errors() {
        let good = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
        let d = read(Path::new("q.ply"), good.as_bytes()).unwrap();
        assert_eq!(d.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let bad_index = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 7\n");
        let e = read(Path::new("q.ply"), bad_index.as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(14), "{e:?}");
        assert!(e.message.contains("out of range"), "{}", e.message);
        let nan = format!("{HEADER}0 0 0\n1 nan 0\n1 1 0\n0 1 0\n3 0 1 2\n");
        let e = read(Path::new("q.ply"), nan.as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(11), "{e:?}");
        let garbage = format!("{HEADER}0 0 0\n1 zero 0\n1 1 0\n0 1 0\n3 0 1 2\n");
        let e = read(Path::new("q.ply"), garbage.as_bytes()).unwrap_err();
        assert!(e.line.is_some(), "{e:?}");
    }
}
