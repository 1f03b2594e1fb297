//! Triangle meshes: read from OBJ (`obj`, through tobj) and PLY (`ply`, through ply-rs-bw)
//! files, or built in (`shapes`: Mitsuba's `rectangle` and `cube`), then placed in the world by
//! a `Transform`. A mesh file's errors name the file and, where the format allows, its line.

mod obj;
mod ply;
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
    pub triangles: Vec<[u32; 3]>,
    /// Findings that do not stop loading (e.g. ignored OBJ materials), with their line.
    pub notes: Vec<(Option<usize>, String)>,
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
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
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

/// Reads an OBJ or PLY file (by extension, case-insensitive).
pub fn read_mesh_file(path: &Path) -> Result<MeshData, MeshFileError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let bytes = std::fs::read(path).map_err(|e| MeshFileError::new(path, None, format!("cannot read mesh file: {e}")))?;
    let data = match ext.as_deref() {
        Some("obj") => obj::read(path, &bytes)?,
        Some("ply") => ply::read(path, &bytes)?,
        _ => return Err(MeshFileError::new(path, None, "unknown mesh format: the file must end in .obj or .ply")),
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

/// The mesh in world space: positions through `transform`, normals through its inverse
/// transpose (dropped when `face_normals`), windings reversed by a mirroring transform so that
/// faces keep their side, and zero-area triangles dropped.
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
}

pub fn place(data: &MeshData, transform: &Transform, face_normals: bool) -> (MeshData, Placement) {
    let positions: Vec<DVec3> = data.positions.iter().map(|&p| transform.point(p)).collect();
    let normals = if face_normals { Vec::new() } else { data.normals.iter().map(|&n| transform.normal(n)).collect() };
    let flip = transform.swaps_handedness();
    let mut placement = Placement::default();
    let triangles = data
        .triangles
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let keep = (b - a).cross(c - a).length() > 0.0;
            placement.degenerate += !keep as usize;
            keep
        })
        .map(|&[a, b, c]| if flip { [a, c, b] } else { [a, b, c] })
        .collect();
    (MeshData { positions, normals, triangles, notes: Vec::new() }, placement)
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
    let n = data.positions.len();
    for (t, tri) in data.triangles.iter().enumerate() {
        if let Some(&i) = tri.iter().find(|&&i| i as usize >= n) {
            return Err(MeshFileError::new(path, line_of_triangle(t), format!("vertex index {i} is out of range (the file has {n} vertices)")));
        }
    }
    Ok(())
}
