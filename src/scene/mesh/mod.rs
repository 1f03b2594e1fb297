//! Triangle meshes: read from OBJ (`obj`, through tobj) and PLY (`ply`, through ply-rs-bw)
//! files, or built in (`shapes`: Mitsuba's `rectangle` and `cube`), then placed in the world by
//! a `Transform`. A mesh file's errors name the file and, where the format allows, its line.

mod obj;
mod ply;
pub mod serialized;
pub mod shapes;

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::transform::Transform;

/// A mesh in object space, as read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<DVec3>,
    /// Per-vertex normals (one per position), or empty.
    pub normals: Vec<DVec3>,
    /// Per-vertex texture coordinates (u, v), one per position, or empty: as the file writes
    /// them (`flip_tex_coords` turns v into 1 - v), or the built-in shape's parametrisation.
    pub uvs: Vec<[f64; 2]>,
    pub triangles: Vec<[u32; 3]>,
    /// Named per-vertex or per-face values (a PLY file's vertex colours), for Mitsuba's
    /// `mesh_attribute` texture; a face attribute has one row per triangle.
    pub attributes: Vec<MeshAttribute>,
    /// Findings that do not stop loading (e.g. ignored OBJ materials), with their line.
    pub notes: Vec<(Option<usize>, String)>,
}

/// A named attribute of a mesh, as Mitsuba's meshes hold them (`Mesh::add_attribute`): its name
/// starts with `vertex_` (one row per vertex, interpolated across a triangle by barycentrics)
/// or `face_` (one row per triangle), and each row has `channels` numbers (1 or 3 are what a
/// texture reads; Mitsuba's PLY reader also makes 4 from r, g, b, a).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshAttribute {
    pub name: String,
    pub channels: usize,
    /// Row-major: row i's channels at `channels * i ..`.
    pub values: Vec<f32>,
}

impl MeshAttribute {
    /// Whether it has one row per vertex (else per face).
    pub fn per_vertex(&self) -> bool {
        self.name.starts_with("vertex_")
    }

    /// Row i as RGB: three channels as they are, one as grey.
    pub fn rgb(&self, i: usize) -> [f32; 3] {
        let r = &self.values[self.channels * i..self.channels * (i + 1)];
        if self.channels >= 3 { [r[0], r[1], r[2]] } else { [r[0]; 3] }
    }

    /// Its value at the three corners of triangle t (vertex indices `corners`): each corner's
    /// row for a vertex attribute, the face's row thrice for a face attribute.
    pub fn corners(&self, t: usize, corners: [u32; 3]) -> [[f32; 3]; 3] {
        if self.per_vertex() { corners.map(|v| self.rgb(v as usize)) } else { [self.rgb(t); 3] }
    }
}

/// A validated mesh in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Where it came from, for messages: its file, or `rectangles[0]`.
    pub source: String,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// An emissive mesh emits on the side its normals face (counter-clockwise winding seen
    /// from that side) unless `two_sided_emission`.
    pub two_sided_emission: bool,
    pub positions: Vec<DVec3>,
    /// Per-vertex shading normals, or empty (face normals).
    pub normals: Vec<DVec3>,
    /// Per-vertex texture coordinates, or empty: where textures are looked up, and the tangent of
    /// an anisotropic BSDF (part of the scene's hash where some material reads them).
    pub uvs: Vec<[f64; 2]>,
    pub triangles: Vec<[u32; 3]>,
    /// Its named attributes (`MeshData::attributes`; face rows follow `triangles`).
    pub attributes: Vec<MeshAttribute>,
}

impl Mesh {
    /// Its attribute named `name`.
    pub fn attribute(&self, name: &str) -> Option<&MeshAttribute> {
        self.attributes.iter().find(|a| a.name == name)
    }

    /// The triangle's vertices.
    pub fn vertices(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// Area of triangle `t`: half the length of the cross product of two edges.
    pub fn triangle_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.vertices(t);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Total area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len()).map(|t| self.triangle_area(t)).sum()
    }
}

/// A mesh file that cannot be used: the file, the line (1-based) where known, what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshFileError {
    pub path: PathBuf,
    pub line: Option<usize>,
    pub message: String,
}

impl MeshFileError {
    pub(crate) fn new(path: &Path, line: Option<usize>, message: impl Into<String>) -> MeshFileError {
        MeshFileError { path: path.to_path_buf(), line, message: message.into() }
    }
}

/// Reads an OBJ, PLY or Mitsuba serialized file (by extension, case-insensitive).
pub fn read_mesh_file(path: &Path) -> Result<MeshData, MeshFileError> {
    read_mesh_shape(path, 0)
}

/// Whether a mesh file is Mitsuba's serialized format (by its extension), which holds several
/// shapes (`shape_index`) and whose texture coordinates are not flipped by default.
pub fn is_serialized(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("serialized"))
}

/// `read_mesh_file`, reading shape `shape_index` of a serialized file (0 for the others).
pub fn read_mesh_shape(path: &Path, shape_index: u32) -> Result<MeshData, MeshFileError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let bytes = std::fs::read(path).map_err(|e| MeshFileError::new(path, None, format!("cannot read mesh file: {e}")))?;
    let data = match ext.as_deref() {
        Some("obj") => obj::read(path, &bytes)?,
        Some("ply") => ply::read(path, &bytes)?,
        Some("serialized") => serialized::read(path, &bytes, shape_index)?,
        _ => return Err(MeshFileError::new(path, None, "unknown mesh format: the file must end in .obj, .ply or .serialized")),
    };
    if data.triangles.is_empty() {
        return Err(MeshFileError::new(path, None, "the file holds no triangles"));
    }
    Ok(data)
}

/// What `place` did besides placing the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Placement {
    /// Triangles of zero area in world space, dropped.
    pub degenerate: usize,
}

impl MeshData {
    /// Reverses every triangle's winding and every vertex normal: front and back swap
    /// (Mitsuba's `flip_normals`).
    pub fn flip_normals(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
        for n in &mut self.normals {
            *n = -*n;
        }
    }

    /// Turns every v into 1 - v (Mitsuba's `flip_tex_coords`, on by default for OBJ and PLY
    /// files, whose images start at the bottom row).
    pub fn flip_tex_coords(&mut self) {
        for uv in &mut self.uvs {
            uv[1] = 1.0 - uv[1];
        }
    }
}

/// How a placed mesh is shaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shading {
    /// Face normals throughout (Mitsuba's `face_normals`; the built-in shapes).
    Faceted,
    /// The file's vertex normals, or, for a file without any, smooth normals recomputed from
    /// the faces as Mitsuba does (`vertex_normals`).
    Smooth,
}

/// The mesh in world space: positions through `transform`, normals through its inverse
/// transpose (recomputed from the world-space faces where the file has none; none with
/// `Shading::Faceted`), windings reversed by a mirroring transform so that faces keep their
/// side, and zero-area triangles dropped.
pub fn place(data: &MeshData, transform: &Transform, shading: Shading) -> (MeshData, Placement) {
    let positions: Vec<DVec3> = data.positions.iter().map(|&p| transform.point(p)).collect();
    let flip = transform.swaps_handedness();
    let mut placement = Placement::default();
    let kept: Vec<bool> = data
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let keep = (b - a).cross(c - a).length() > 0.0;
            placement.degenerate += !keep as usize;
            keep
        })
        .collect();
    let triangles: Vec<[u32; 3]> = data
        .triangles
        .iter()
        .zip(&kept)
        .filter(|(_, keep)| **keep)
        .map(|(&[a, b, c], _)| if flip { [a, c, b] } else { [a, b, c] })
        .collect();
    // A face attribute's rows follow the triangles kept; a vertex attribute's the vertices.
    let attributes = data
        .attributes
        .iter()
        .map(|a| match a.per_vertex() {
            true => a.clone(),
            false => MeshAttribute {
                values: a.values.chunks_exact(a.channels).zip(&kept).filter(|(_, keep)| **keep).flat_map(|(row, _)| row.iter().copied()).collect(),
                ..a.clone()
            },
        })
        .collect();
    let normals = match shading {
        Shading::Faceted => Vec::new(),
        Shading::Smooth if data.normals.is_empty() => vertex_normals(&positions, &triangles),
        Shading::Smooth => data.normals.iter().map(|&n| transform.normal(n)).collect(),
    };
    (MeshData { positions, normals, uvs: data.uvs.clone(), triangles, attributes, notes: Vec::new() }, placement)
}

/// Smooth vertex normals for a mesh without any, as Mitsuba's `Mesh::recompute_vertex_normals`
/// makes them (Thürmer and Wüthrich 1998, "Computing vertex normals from polygonal facets"):
/// at each vertex, the sum of the unit normals of the faces around it, each weighted by the
/// face's interior angle at that vertex, normalised. Faces of zero area add nothing; a vertex no
/// face uses gets the zero vector (the kernel then takes the face normal). Vertices are shared
/// as the file shares them: an OBJ vertex is one distinct position/texture/normal index triple,
/// as in Mitsuba's OBJ reader.
pub fn vertex_normals(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for t in triangles {
        let p = t.map(|i| positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for k in 0..3 {
            // The interior angle at corner k, between its two edges.
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            normals[t[k] as usize] += n * a.cross(b).length().atan2(a.dot(b));
        }
    }
    normals.iter().map(|n| n.normalize_or_zero()).collect()
}

/// Checks every vertex, normal and index: finite values, indices within the vertex list.
/// `line_of_vertex` maps a vertex index to its line in the file, where known.
pub(crate) fn check(path: &Path, data: &MeshData, line_of_vertex: impl Fn(usize) -> Option<usize>, line_of_triangle: impl Fn(usize) -> Option<usize>) -> Result<(), MeshFileError> {
    if let Some(i) = data.positions.iter().position(|p| !p.is_finite()) {
        return Err(MeshFileError::new(path, line_of_vertex(i), format!("vertex {i} is not finite ({})", data.positions[i])));
    }
    if let Some(i) = data.positions.iter().position(|p| p.abs().max_element() > f32::MAX as f64) {
        return Err(MeshFileError::new(path, line_of_vertex(i), format!("vertex {i} is too large for 32-bit floats")));
    }
    if let Some(i) = data.normals.iter().position(|n| !n.is_finite()) {
        return Err(MeshFileError::new(path, line_of_vertex(i), format!("normal {i} is not finite ({})", data.normals[i])));
    }
    if let Some(i) = data.uvs.iter().position(|uv| !(uv[0].is_finite() && uv[1].is_finite())) {
        return Err(MeshFileError::new(path, line_of_vertex(i), format!("texture coordinate {i} is not finite ({:?})", data.uvs[i])));
    }
    let n = data.positions.len();
    for (t, tri) in data.triangles.iter().enumerate() {
        if let Some(&i) = tri.iter().find(|&&i| i as usize >= n) {
            return Err(MeshFileError::new(path, line_of_triangle(t), format!("vertex index {i} is out of range (the file has {n} vertices)")));
        }
    }
    Ok(())
}

/// Each triangle's corners as numbers of distinct positions, in order of first appearance.
/// Positions are the same when their bits are (so 0 and -0 stay apart: their sheared values may
/// differ in sign). How the small scenes' kernel shares its sheared vertices
/// (`accel::SharedVertices`) and `Scene::shadow_tests_of` finds the triangles that share
/// positions.
pub fn position_ids(triangles: &[[[f32; 3]; 3]]) -> Vec<[usize; 3]> {
    let mut ids: std::collections::HashMap<[u32; 3], usize> = std::collections::HashMap::new();
    triangles
        .iter()
        .map(|t| {
            t.map(|p| {
                let n = ids.len();
                *ids.entry(p.map(f32::to_bits)).or_insert(n)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's 8 shared corners, each face split into two triangles along one diagonal
    /// or the other: a corner lies in one or two triangles of each of its three faces, but its
    /// angles there sum to a right angle either way, so angle weighting gives every corner the
    /// symmetric normal (+-1, +-1, +-1) / sqrt(3), where area or count weighting would tilt it
    /// towards the faces whose diagonal runs through it.
    #[test]
    fn recomputed_vertex_normals_weigh_faces_by_their_angle_at_the_vertex() {
        let positions: Vec<DVec3> = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) * 2.0 - 1.0).collect();
        // Faces outward, counter-clockwise: (a, b, c, d), split as (a, b, c) + (a, c, d), or along the other diagonal.
        let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let mut triangles = Vec::new();
        for (k, [a, b, c, d]) in faces.into_iter().enumerate() {
            if k % 2 == 0 { triangles.extend([[a, b, c], [a, c, d]]) } else { triangles.extend([[a, b, d], [b, c, d]]) }
        }
        let normals = vertex_normals(&positions, &triangles);
        for (p, n) in positions.iter().zip(&normals) {
            assert!((*n - *p / 3f64.sqrt()).length() < 1e-12, "corner {p}: normal {n}");
        }
        // A vertex no face uses has none.
        let mut more = positions.clone();
        more.push(DVec3::ZERO);
        assert_eq!(vertex_normals(&more, &triangles)[8], DVec3::ZERO);
    }
}
