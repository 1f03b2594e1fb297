//! Mitsuba 3's built-in shapes as meshes, so that a Mitsuba scene translates one to one:
//! `rectangle` is [-1, 1]^2 at z = 0 with normal +z; `cube` is [-1, 1]^3 with outward faces.
//! Both have face normals only (their faces are flat), and Mitsuba's texture coordinates.

use glam::DVec3;

use super::MeshData;

/// Two triangles (0, 1, 2) and (2, 3, 0) over the corners (-1, -1), (1, -1), (1, 1), (-1, 1),
/// counter-clockwise seen from +z, as Mitsuba's `rectangle`, with its parametrisation
/// (u, v) = ((x + 1) / 2, (y + 1) / 2).
pub fn rectangle() -> MeshData {
    let positions = vec![DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, -1.0, 0.0), DVec3::new(1.0, 1.0, 0.0), DVec3::new(-1.0, 1.0, 0.0)];
    let uvs = positions.iter().map(|p| [(p.x + 1.0) / 2.0, (p.y + 1.0) / 2.0]).collect();
    MeshData { positions, normals: Vec::new(), uvs, triangles: vec![[0, 1, 2], [2, 3, 0]], attributes: Vec::new(), notes: Vec::new() }
}

/// Mitsuba's parametrisation of the cube's face with outward normal `n` at point `p`: every
/// face maps onto [0, 1]^2, each by its own affine map of two coordinates (read from the
/// vertex table of Mitsuba 3's `cube`).
fn cube_uv(n: DVec3, p: DVec3) -> [f64; 2] {
    let (x, y, z) = ((p.x + 1.0) / 2.0, (p.y + 1.0) / 2.0, (p.z + 1.0) / 2.0);
    match (n.x as i32, n.y as i32, n.z as i32) {
        (0, -1, 0) => [z, x],
        (0, 1, 0) => [1.0 - x, 1.0 - z],
        (1, 0, 0) => [y, 1.0 - z],
        (-1, 0, 0) => [y, z],
        (0, 0, 1) => [y, x],
        _ => [1.0 - y, x],
    }
}

/// Six faces of two triangles each, every face counter-clockwise seen from outside, each with
/// its own four vertices (24 in all), as Mitsuba's `cube`.
pub fn cube() -> MeshData {
    let mut data = MeshData::default();
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            // The face's normal n, and two tangents with t x b = n.
            let n = DVec3::AXES[axis] * sign;
            let t = DVec3::AXES[(axis + 1) % 3] * sign;
            let b = n.cross(t);
            let base = data.positions.len() as u32;
            for (s, r) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = n + t * s + b * r;
                data.positions.push(p);
                data.uvs.push(cube_uv(n, p));
            }
            data.triangles.push([base, base + 1, base + 2]);
            data.triangles.push([base + 2, base + 3, base]);
        }
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face_normal(d: &MeshData, t: usize) -> DVec3 {
        let [a, b, c] = d.triangles[t].map(|i| d.positions[i as usize]);
        (b - a).cross(c - a).normalize()
    }

    #[test]
    fn windings_face_outward() {
        let r = rectangle();
        assert!(face_normal(&r, 0).abs_diff_eq(DVec3::Z, 1e-12) && face_normal(&r, 1).abs_diff_eq(DVec3::Z, 1e-12));
        let c = cube();
        assert_eq!((c.positions.len(), c.triangles.len()), (24, 12));
        for t in 0..12 {
            let [a, b, cc] = c.triangles[t].map(|i| c.positions[i as usize]);
            let centre = (a + b + cc) / 3.0;
            assert!(face_normal(&c, t).dot(centre) > 0.0, "triangle {t} faces inward");
            assert!(c.positions.iter().all(|p| p.abs().max_element() == 1.0));
        }
    }

    /// The texture coordinates of Mitsuba 3's `cube` (its 24-vertex table: position, face
    /// normal, uv) and `rectangle`.
    #[test]
    fn texture_coordinates_are_mitsubas() {
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let mitsuba = [
            (p(1., -1., -1.), DVec3::NEG_Y, [0., 1.]), (p(1., -1., 1.), DVec3::NEG_Y, [1., 1.]),
            (p(-1., -1., 1.), DVec3::NEG_Y, [1., 0.]), (p(-1., -1., -1.), DVec3::NEG_Y, [0., 0.]),
            (p(1., 1., -1.), DVec3::Y, [0., 1.]), (p(-1., 1., -1.), DVec3::Y, [1., 1.]),
            (p(-1., 1., 1.), DVec3::Y, [1., 0.]), (p(1., 1., 1.), DVec3::Y, [0., 0.]),
            (p(1., -1., -1.), DVec3::X, [0., 1.]), (p(1., 1., -1.), DVec3::X, [1., 1.]),
            (p(1., 1., 1.), DVec3::X, [1., 0.]), (p(1., -1., 1.), DVec3::X, [0., 0.]),
            (p(1., -1., 1.), DVec3::Z, [0., 1.]), (p(1., 1., 1.), DVec3::Z, [1., 1.]),
            (p(-1., 1., 1.), DVec3::Z, [1., 0.]), (p(-1., -1., 1.), DVec3::Z, [0., 0.]),
            (p(-1., -1., 1.), DVec3::NEG_X, [0., 1.]), (p(-1., 1., 1.), DVec3::NEG_X, [1., 1.]),
            (p(-1., 1., -1.), DVec3::NEG_X, [1., 0.]), (p(-1., -1., -1.), DVec3::NEG_X, [0., 0.]),
            (p(1., 1., -1.), DVec3::NEG_Z, [0., 1.]), (p(1., -1., -1.), DVec3::NEG_Z, [1., 1.]),
            (p(-1., -1., -1.), DVec3::NEG_Z, [1., 0.]), (p(-1., 1., -1.), DVec3::NEG_Z, [0., 0.]),
        ];
        let c = cube();
        assert_eq!(c.uvs.len(), 24);
        for (position, normal, uv) in mitsuba {
            // Our vertex at this corner of this face (the face of the triangle holding it).
            let i = (0..24)
                .find(|&i| {
                    let t = c.triangles.iter().position(|t| t.contains(&(i as u32))).unwrap();
                    c.positions[i] == position && face_normal(&c, t).abs_diff_eq(normal, 1e-12)
                })
                .unwrap();
            assert_eq!(c.uvs[i], uv, "{position} on the face {normal}");
        }
        let r = rectangle();
        assert_eq!(r.uvs, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    }
}
