//! Mitsuba 3's built-in shapes as meshes, so that a Mitsuba scene translates one to one:
//! `rectangle` is [-1, 1]^2 at z = 0 with normal +z; `cube` is [-1, 1]^3 with outward faces.
//! Both have face normals only (their faces are flat).

use glam::DVec3;

use super::MeshData;

/// Two triangles (0, 1, 2) and (2, 3, 0) over the corners (-1, -1), (1, -1), (1, 1), (-1, 1),
/// counter-clockwise seen from +z, as Mitsuba's `rectangle`.
pub fn rectangle() -> MeshData {
    let positions = vec![DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, -1.0, 0.0), DVec3::new(1.0, 1.0, 0.0), DVec3::new(-1.0, 1.0, 0.0)];
    MeshData { positions, normals: Vec::new(), triangles: vec![[0, 1, 2], [2, 3, 0]], notes: Vec::new() }
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
                data.positions.push(n + t * s + b * r);
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
}
