//! Stanford PLY (ASCII or binary) through ply-rs-bw: `vertex` elements with `x y z` and
//! optionally `nx ny nz`, `face` elements with a `vertex_indices` (or `vertex_index`) list,
//! polygons split into fans. In an ASCII file every element is one line, so an error in the
//! payload names its line; in a binary file it names the element.
//!
//! Other properties of a vertex or a face become named attributes, grouped by Mitsuba 3.9.1's
//! rules (`find_other_fields`, src/shapes/ply.h): consecutive properties `{prefix}_{x|y|z|w}`,
//! `{prefix}_{r|g|b|a}`, `{prefix}_{0|1|2|3}` or `{prefix}_{1|2|3|4}` form the attribute
//! `{vertex|face}_{prefix}` (`{prefix}_color` for r, g, b), and `r g b` (or `red green blue`,
//! with an optional alpha) the attribute `{vertex|face}_color`. Only 1 or 3 properties make
//! an attribute (the colour with alpha makes 4); others are ignored with a warning, as Mitsuba
//! does. Every value is taken as written, integers too: Mitsuba 3.9.1 reads a uchar colour of
//! 208 as 208, not 208/255 (measured: `mi.load_dict({"type": "ply", ...}).attribute_buffer(
//! "vertex_color")` of ASCII and binary files), and warns that colour attributes with integer
//! fields "are expected to be in the [0, 1] range"; pathlab warns the same, naming the file.

use std::path::Path;

use glam::DVec3;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Encoding, Property, PropertyType, ScalarType};

use super::{check, MeshAttribute, MeshData, MeshFileError};

/// The properties of one attribute: its name (`vertex_color`) and its properties in order.
#[derive(Debug, Clone, PartialEq)]
struct AttributeFields {
    name: String,
    fields: Vec<String>,
}

/// Groups the properties of an element (`kind`: "vertex_" or "face_"; `properties` in the
/// file's order, of which `integer` are of integer types) into attributes by Mitsuba's rules (module
/// documentation), skipping `reserved` ones (positions, normals, texture coordinates, indices);
/// the warnings are Mitsuba's.
fn group_attributes(kind: &str, properties: &[String], integer: &[&str], reserved: &[&str]) -> (Vec<AttributeFields>, Vec<String>) {
    let has = |n: &str| properties.iter().any(|p| p == n);
    let mut groups = Vec::new();
    let mut notes = Vec::new();
    let mut reserved: Vec<&str> = reserved.to_vec();
    // The colour without a prefix: r, g, b (and a), or red, green, blue (and alpha).
    let colour = if has("r") && has("g") && has("b") {
        Some(if has("a") { vec!["r", "g", "b", "a"] } else { vec!["r", "g", "b"] })
    } else if has("red") && has("green") && has("blue") {
        Some(if has("alpha") { vec!["red", "green", "blue", "alpha"] } else { vec!["red", "green", "blue"] })
    } else {
        None
    };
    reserved.extend(["r", "g", "b", "a"]);
    if let Some(fields) = colour {
        if integer.contains(&fields[0]) {
            notes.push(integer_note(&format!("{kind}color")));
        }
        reserved.extend(fields.iter().copied());
        groups.push(AttributeFields { name: format!("{kind}color"), fields: fields.iter().map(|f| f.to_string()).collect() });
    }
    // Postfix categories: column j of these rows (x y z w, r g b a, 0 1 2 3, 1 2 3 4).
    const POSTFIXES: [&[u8; 4]; 4] = [b"xr01", b"yg12", b"zb23", b"wa34"];
    let mut seen: Vec<String> = Vec::new();
    // The attribute being read: its prefix, category and properties.
    let mut current: Option<(String, usize, Vec<String>)> = None;
    let flush = |current: &mut Option<(String, usize, Vec<String>)>, groups: &mut Vec<AttributeFields>, notes: &mut Vec<String>, seen: &mut Vec<String>| {
        let Some((prefix, category, fields)) = current.take() else { return };
        if fields.len() != 1 && fields.len() != 3 {
            notes.push(format!("attribute \"{kind}{prefix}\" has {} fields where 1 or 3 are read: ignored (as Mitsuba does)", fields.len()));
            return;
        }
        if fields.len() == 3 && integer.contains(&fields[0].as_str()) {
            notes.push(integer_note(&format!("{kind}{prefix}")));
        }
        let name = format!("{kind}{prefix}{}", if category == 1 { "_color" } else { "" });
        seen.push(prefix);
        groups.push(AttributeFields { name, fields });
    };
    for name in properties {
        if reserved.contains(&name.as_str()) {
            continue;
        }
        let Some(at) = name.rfind('_') else {
            notes.push(format!("property \"{name}\" has no postfix (`_x`, `_r`, `_0`, ...): ignored (as Mitsuba does)"));
            flush(&mut current, &mut groups, &mut notes, &mut seen);
            continue;
        };
        let (prefix, postfix) = (&name[..at], name[at + 1..].as_bytes());
        if postfix.len() != 1 {
            notes.push(format!("property \"{name}\": an attribute's postfix is one letter or digit: ignored (as Mitsuba does)"));
            flush(&mut current, &mut groups, &mut notes, &mut seen);
            continue;
        }
        if current.as_ref().is_some_and(|(p, _, _)| p != prefix) {
            flush(&mut current, &mut groups, &mut notes, &mut seen);
        }
        match &mut current {
            None => {
                if seen.iter().any(|p| p == prefix) {
                    notes.push(format!("property \"{name}\": attribute \"{kind}{prefix}\" was read already: ignored (as Mitsuba does)"));
                    continue;
                }
                match POSTFIXES[0].iter().position(|&c| c == postfix[0]) {
                    Some(category) => current = Some((prefix.to_string(), category, vec![name.clone()])),
                    None => notes.push(format!("property \"{name}\": an attribute cannot start with postfix `{}`: ignored (as Mitsuba does)", postfix[0] as char)),
                }
            }
            Some((_, category, fields)) => {
                let level = fields.len();
                if level < 4 && POSTFIXES[level][*category] == postfix[0] {
                    fields.push(name.clone());
                } else {
                    notes.push(format!("property \"{name}\": attribute \"{kind}{prefix}\" has an invalid postfix sequence: ignored (as Mitsuba does)"));
                    current = None;
                    seen.push(prefix.to_string());
                }
            }
        }
    }
    flush(&mut current, &mut groups, &mut notes, &mut seen);
    (groups, notes)
}

/// Mitsuba's warning for a three-channel attribute of integer fields.
fn integer_note(name: &str) -> String {
    format!("attribute \"{name}\" has integer fields: they are read as the integers themselves (as Mitsuba 3.9.1 reads them), where colour attributes are expected to be in the [0, 1] range")
}

/// A property's value as an attribute reads it: as written, an integer as its value (Mitsuba's
/// reading, module documentation).
fn attribute_value(p: &Property) -> Option<f32> {
    scalar(p).map(|v| v as f32)
}

/// The scalar properties of `element` in the header's order, and those of integer types.
fn scalar_properties(ply: &ply_rs_bw::ply::Ply<DefaultElement>, element: &str) -> (Vec<String>, Vec<String>) {
    let (mut all, mut integer) = (Vec::new(), Vec::new());
    for p in ply.header.elements.get(element).map(|e| e.properties.values().collect::<Vec<_>>()).unwrap_or_default() {
        if let PropertyType::Scalar(t) = &p.data_type {
            all.push(p.name.clone());
            if !matches!(t, ScalarType::Float | ScalarType::Double) {
                integer.push(p.name.clone());
            }
        }
    }
    (all, integer)
}

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
    // The other vertex properties, as attributes (one row per vertex).
    let (properties, integer) = scalar_properties(&ply, "vertex");
    let integer: Vec<&str> = integer.iter().map(String::as_str).collect();
    let (vertex_groups, vertex_notes) = group_attributes("vertex_", &properties, &integer, &["x", "y", "z", "nx", "ny", "nz", "u", "v", "s", "t", "texture_u", "texture_v", "texture_s", "texture_t"]);
    data.notes.extend(vertex_notes.into_iter().map(|n| (vertex_line, n)));
    for group in vertex_groups {
        let mut values = Vec::with_capacity(vertices.len() * group.fields.len());
        for (i, v) in vertices.iter().enumerate() {
            for f in &group.fields {
                values.push(v.get(f).and_then(attribute_value).ok_or_else(|| MeshFileError::new(path, at(vertex_line, i), format!("vertex {i} has no numeric property `{f}`")))?);
            }
        }
        data.attributes.push(MeshAttribute { name: group.name, channels: group.fields.len(), values });
    }
    let (properties, integer) = scalar_properties(&ply, "face");
    let integer: Vec<&str> = integer.iter().map(String::as_str).collect();
    let (face_groups, face_notes) = group_attributes("face_", &properties, &integer, &[]);
    data.notes.extend(face_notes.into_iter().map(|n| (face_line, n)));
    let mut face_attributes: Vec<MeshAttribute> =
        face_groups.iter().map(|g| MeshAttribute { name: g.name.clone(), channels: g.fields.len(), values: Vec::new() }).collect();
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
        // The face's attribute rows, once per triangle of its fan.
        let mut row = Vec::new();
        for group in &face_groups {
            for field in &group.fields {
                row.push(face.get(field).and_then(attribute_value).ok_or_else(|| MeshFileError::new(path, line, format!("face {f} has no numeric property `{field}`")))?);
            }
        }
        for k in 1..list.len() - 1 {
            data.triangles.push([list[0] as u32, list[k] as u32, list[k + 1] as u32]);
            triangle_lines.push(line);
            let mut at = 0;
            for a in &mut face_attributes {
                a.values.extend_from_slice(&row[at..at + a.channels]);
                at += a.channels;
            }
        }
    }
    data.attributes.extend(face_attributes);
    if let Some(a) = data.attributes.iter().find(|a| a.values.iter().any(|x| !x.is_finite())) {
        return Err(MeshFileError::new(path, None, format!("attribute \"{}\" has a value that is not finite", a.name)));
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
    fn attributes_are_grouped_as_mitsuba_groups_them() {
        let props = |names: &[&str]| names.iter().map(|n| n.to_string()).collect::<Vec<_>>();
        // The sphere fixture's faces: color_0..2, then weight_0.
        let (g, notes) = group_attributes("face_", &props(&["color_0", "color_1", "color_2", "weight_0"]), &[], &[]);
        assert_eq!(g.iter().map(|a| (a.name.as_str(), a.fields.len())).collect::<Vec<_>>(), vec![("face_color", 3), ("face_weight", 1)]);
        assert!(notes.is_empty(), "{notes:?}");
        // r, g, b without a prefix; {prefix}_r, _g, _b is `{prefix}_color`; x, y: two fields, ignored.
        let (g, notes) = group_attributes("vertex_", &props(&["x", "y", "red", "green", "blue", "albedo_r", "albedo_g", "albedo_b", "dir_x", "dir_y", "t_1"]), &[], &["x", "y"]);
        assert_eq!(g.iter().map(|a| a.name.as_str()).collect::<Vec<_>>(), vec!["vertex_color", "vertex_albedo_color", "vertex_t"]);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("vertex_dir") && notes[0].contains("2 fields"), "{notes:?}");
        // A broken sequence (x then z) is ignored, and so is a property without a postfix.
        let (g, notes) = group_attributes("vertex_", &props(&["q_x", "q_z", "weird"]), &[], &[]);
        assert!(g.is_empty() && notes.len() == 2, "{g:?} {notes:?}");
    }

    #[test]
    fn vertex_and_face_attributes_are_read_with_their_values() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                    property uchar red\nproperty uchar green\nproperty uchar blue\n\
                    element face 1\nproperty list uchar int vertex_indices\nproperty float w_0\nend_header\n\
                    0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 188\n0 1 0 0 0 0\n4 0 1 2 3 0.25\n";
        let d = read(Path::new("a.ply"), text.as_bytes()).unwrap();
        let colour = &d.attributes[0];
        assert_eq!((colour.name.as_str(), colour.channels), ("vertex_color", 3));
        // Bytes are read as their values, as Mitsuba 3.9.1 reads them (with its warning).
        assert_eq!(colour.rgb(0), [255.0, 0.0, 0.0]);
        let b = 188.0;
        assert_eq!(colour.rgb(2), [0.0, 0.0, b]);
        // The quad's face attribute is repeated for both triangles of its fan.
        let w = &d.attributes[1];
        assert_eq!((w.name.as_str(), w.channels, w.values.clone()), ("face_w", 1, vec![0.25, 0.25]));
        assert_eq!(w.corners(1, d.triangles[1]), [[0.25; 3]; 3]);
        assert_eq!(colour.corners(1, d.triangles[1]), [[255.0, 0.0, 0.0], [0.0, 0.0, b], [0.0; 3]]);
        assert!(d.notes.len() == 1 && d.notes[0].1.contains("integer fields"), "{:?}", d.notes);
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
