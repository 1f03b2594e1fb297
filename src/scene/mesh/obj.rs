//! Wavefront OBJ through tobj (triangulated as fans, one index per vertex). tobj's errors carry
//! no line, so the file is first checked statement by statement here: every `v` and `vn` has
//! three finite numbers, every `f` at least three vertex references that exist at that point
//! of the file. What this pass accepts, tobj reads; its errors then name the line.

use std::path::Path;

use glam::DVec3;

use super::{check, MeshData, MeshFileError};

/// Resolves an OBJ index (1-based, or negative: relative to the end) against `count` items.
fn resolve(token: &str, count: usize) -> Result<usize, String> {
    let i: i64 = token.parse().map_err(|_| format!("`{token}` is not an index"))?;
    let resolved = if i > 0 { i - 1 } else { count as i64 + i };
    if i == 0 || resolved < 0 || resolved >= count as i64 {
        return Err(format!("index {i} refers to no element (only {count} defined before this line)"));
    }
    Ok(resolved as usize)
}

/// Line (1-based) of every `v` statement, and of every triangle tobj will make (fans of the
/// `f` statements, in order), after checking each statement.
struct Lines {
    vertices: Vec<usize>,
    triangles: Vec<usize>,
    materials: Option<usize>,
}

fn prescan(path: &Path, text: &str) -> Result<Lines, MeshFileError> {
    let mut lines = Lines { vertices: Vec::new(), triangles: Vec::new(), materials: None };
    let (mut normals, mut texcoords) = (0usize, 0usize);
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let err = |m: String| MeshFileError::new(path, Some(line), m);
        let mut words = raw.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        let rest: Vec<&str> = words.collect();
        let numbers = |what: &str, min: usize| -> Result<(), MeshFileError> {
            if rest.len() < min {
                return Err(err(format!("`{what}` needs {min} numbers, found {}", rest.len())));
            }
            for w in &rest {
                let v: f64 = w.parse().map_err(|_| err(format!("`{w}` is not a number")))?;
                if !v.is_finite() {
                    return Err(err(format!("`{what}` has a non-finite value `{w}`")));
                }
            }
            Ok(())
        };
        match keyword {
            "v" => {
                numbers("v", 3)?;
                lines.vertices.push(line);
            }
            "vn" => {
                numbers("vn", 3)?;
                normals += 1;
            }
            "vt" => {
                numbers("vt", 1)?;
                texcoords += 1;
            }
            "f" => {
                if rest.len() < 3 {
                    return Err(err(format!("a face needs at least 3 vertices, found {}", rest.len())));
                }
                for r in &rest {
                    let mut parts = r.split('/');
                    let v = parts.next().unwrap_or("");
                    resolve(v, lines.vertices.len()).map_err(|m| err(format!("vertex {m}")))?;
                    if let Some(t) = parts.next().filter(|t| !t.is_empty()) {
                        resolve(t, texcoords).map_err(|m| err(format!("texture coordinate {m}")))?;
                    }
                    if let Some(n) = parts.next().filter(|n| !n.is_empty()) {
                        resolve(n, normals).map_err(|m| err(format!("normal {m}")))?;
                    }
                }
                lines.triangles.extend(std::iter::repeat_n(line, rest.len() - 2));
            }
            "mtllib" | "usemtl" => {
                lines.materials.get_or_insert(line);
            }
            _ => {}
        }
    }
    Ok(lines)
}

pub(super) fn read(path: &Path, bytes: &[u8]) -> Result<MeshData, MeshFileError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        MeshFileError::new(path, Some(line), "the OBJ file is not UTF-8 text")
    })?;
    let lines = prescan(path, text)?;
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ignore_points: true, ignore_lines: true, ..Default::default() };
    let (models, _materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| MeshFileError::new(path, None, format!("OBJ: {e}")))?;
    let mut data = MeshData::default();
    // tobj duplicates vertices per (position, normal) pair; map them back to file lines by
    // position only where the counts agree (messages only).
    let mut any_without_normals = false;
    for model in &models {
        let m = &model.mesh;
        let base = data.positions.len() as u32;
        let count = m.positions.len() / 3;
        data.positions.extend(m.positions.chunks_exact(3).map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)));
        if m.normals.len() == m.positions.len() {
            data.normals.extend(m.normals.chunks_exact(3).map(|n| DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64)));
        } else {
            any_without_normals = true;
            data.normals.extend(std::iter::repeat_n(DVec3::ZERO, count));
        }
        if m.texcoords.len() == 2 * count {
            data.uvs.extend(m.texcoords.chunks_exact(2).map(|t| [t[0] as f64, t[1] as f64]));
        } else {
            data.uvs.extend(std::iter::repeat_n([0.0, 0.0], count));
        }
        data.triangles.extend(m.indices.chunks_exact(3).map(|t| [base + t[0], base + t[1], base + t[2]]));
    }
    // Texture coordinates where some model has them (the others at (0, 0), as Mitsuba fills).
    if !models.iter().any(|model| !model.mesh.texcoords.is_empty()) {
        data.uvs.clear();
    }
    if any_without_normals {
        // Normals for some faces only: a shading normal of zero falls back to the face normal
        // per triangle; none at all: face normals throughout.
        if data.normals.iter().all(|n| *n == DVec3::ZERO) {
            data.normals.clear();
        }
    }
    if let Some(line) = lines.materials {
        data.notes.push((Some(line), "OBJ materials (mtllib/usemtl) are ignored: the scene's `material` applies to the whole mesh".into()));
    }
    let vertex_line = |i: usize| if data.positions.len() == lines.vertices.len() { lines.vertices.get(i).copied() } else { None };
    check(path, &data, vertex_line, |t| lines.triangles.get(t).copied())?;
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str) -> Result<MeshData, MeshFileError> {
        read(Path::new("m.obj"), text.as_bytes())
    }

    #[test]
    fn a_quad_becomes_two_triangles_with_its_normals() {
        let d = read_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n").unwrap();
        assert_eq!(d.triangles.len(), 2);
        assert_eq!(d.normals.len(), d.positions.len());
        let d = read_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\n").unwrap();
        assert_eq!(d.triangles.len(), 1);
        assert!(d.normals.is_empty());
    }

    #[test]
    fn texture_coordinates_follow_their_vertices() {
        let d = read_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0.25\nvt 1 1\nf 1/1 2/2 3/3\n").unwrap();
        assert_eq!(d.uvs, vec![[0.0, 0.0], [1.0, 0.25], [1.0, 1.0]]);
        let mut flipped = d.clone();
        flipped.flip_tex_coords();
        assert_eq!(flipped.uvs, vec![[0.0, 1.0], [1.0, 0.75], [1.0, 0.0]]);
        assert!(read_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n").unwrap().uvs.is_empty());
    }

    #[test]
    fn errors_name_the_line() {
        let cases = [
            ("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n", 4, "refers to no element"),
            ("v 0 0 0\nv 1 nan 0\nv 1 1 0\nf 1 2 3\n", 2, "non-finite"),
            ("v 0 0 0\nv 1 0\nv 1 1 0\nf 1 2 3\n", 2, "needs 3 numbers"),
            ("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\n", 4, "at least 3"),
            ("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1//2 2 3\n", 4, "normal index"),
            ("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 x 3\n", 4, "not an index"),
        ];
        for (text, line, message) in cases {
            let e = read_text(text).unwrap_err();
            assert_eq!(e.line, Some(line), "{text}: {e:?}");
            assert!(e.message.contains(message), "{text}: {}", e.message);
        }
    }
}
