//! Closed convex solids among a small scene's triangles, and the faces of them that no ray
//! needs to test (issue 31): shadow rays skip the faces turned away from every light
//! (`Scene::closed_back_faces`, in `shadow_hull.rs`), and rays that look for the nearest hit test
//! one face of each pair of opposite parallel faces, the one turned towards the ray
//! (`Scene::front_face_pairs`).
//!
//! **A closed convex part.** The triangles of a connected part of the scene (sharing vertex
//! positions, by their bits) close a solid where every directed edge occurs once and its reverse
//! once; their outward normals are the winding's, or its opposite where the enclosed signed
//! volume is negative; the solid is convex where every vertex of the part lies on or behind
//! every face's plane (within a relative 1e-6).
//!
//! **Opposite faces** (`front_face_pairs`). A ray that starts outside a convex solid and meets
//! it enters it first through a face whose outward normal n has d . n < 0. Of two faces with
//! opposite normals (a box's top and bottom), at most one has d . n < 0 for a given direction d:
//! the nearest hit on the solid is never on the other, so the kernel tests the one turned towards
//! the ray, picked per lane by the sign of d . n (`SMALL_FACING_<k>_<j>`), and the pair costs one
//! test. This holds where every ray starts outside the solid: the camera's ray origins lie in
//! front of one of its faces, nothing lets a ray through its faces (no transmitting, blended,
//! masked or emissive material, whose hidden emitters camera rays pass through; no media), so no
//! path vertex lies inside it, and no other surface reaches into it or near it at an angle
//! (`nothing_reaches_in`), so no ray's origin, offset from its vertex along its surface's normal,
//! lands inside it. A ray that starts on one of its faces and leaves it cannot meet the solid
//! again. (A pane of thin glass standing through a box, at 17 degrees to its faces, had one
//! sample in 27,648 start inside the box and pass through it.) Faces count as opposite where their unit normals sum to less than 1e-6
//! (a box rotated in f32 stays well within): for the directions between two nearly parallel
//! faces, both turned towards the ray, the ray grazes both, and what it would miss by testing
//! one is a set of directions of that measure.

use std::collections::HashMap;

use glam::DVec3;

use super::Scene;

/// Points within this relative distance of a plane lie on it.
pub(super) const ON_PLANE: f64 = 1e-6;
/// Camera ray origins must lie further than this relative distance in front of a face of a
/// solid whose opposite faces are paired.
const CAMERA_MARGIN: f64 = 1e-4;
/// Unit normals of two faces that sum to less than this are opposite.
const OPPOSITE: f64 = 1e-6;
/// Other surfaces further than this relative distance in front of one of a solid's faces are
/// clear of it: more than a ray's origin is offset from its surface (`offset_ray_origin`: 2e-5
/// of the point's magnitude, or four times a triangle's rounding error).
const CLEAR: f64 = 1e-4;
/// Normals whose dot product is within this of 0 or of 1 are perpendicular or parallel.
const ALIGNED: f64 = 1e-6;

/// A closed convex part: its triangles (indices into the given triangles) and each one's outward
/// unit normal and a corner.
pub(super) struct ConvexPart {
    pub faces: Vec<usize>,
    pub planes: Vec<(DVec3, DVec3)>,
}

impl ConvexPart {
    /// Signed distance of x from face i's plane (positive in front, outside).
    pub fn side(&self, i: usize, x: DVec3) -> f64 {
        let (n, p) = self.planes[i];
        n.dot(x - p)
    }
}

/// The closed convex parts of `triangles` (see the module); `scale` bounds the scene's
/// coordinates. Conservative: a part whose edges do not pair up, that is not convex within a
/// relative 1e-6, or with a degenerate face, is none.
pub(super) fn closed_convex_parts(triangles: &[[[f32; 3]; 3]], scale: f64) -> Vec<ConvexPart> {
    // The distinct positions (by their bits, as the kernel shares them) and each corner's.
    let corners = super::mesh::position_ids(triangles);
    let mut positions = vec![DVec3::ZERO; corners.iter().flatten().max().map_or(0, |&m| m + 1)];
    for (c, t) in corners.iter().zip(triangles) {
        for (&i, p) in c.iter().zip(t) {
            positions[i] = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
        }
    }
    // Connected parts: triangles sharing a position (union-find over positions).
    let mut parent: Vec<usize> = (0..positions.len()).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for c in &corners {
        for j in 1..3 {
            let (a, b) = (root(&mut parent, c[0]), root(&mut parent, c[j]));
            parent[a] = b;
        }
    }
    let mut parts: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, c) in corners.iter().enumerate() {
        parts.entry(root(&mut parent, c[0])).or_default().push(k);
    }
    let mut parts: Vec<Vec<usize>> = parts.into_values().collect();
    parts.sort_unstable();
    let tol = ON_PLANE * scale;
    let mut solids = Vec::new();
    for faces in parts {
        // Closed and consistently wound: every directed edge once, and its reverse once.
        let mut edges: HashMap<(usize, usize), u32> = HashMap::new();
        for &k in &faces {
            let c = corners[k];
            for j in 0..3 {
                *edges.entry((c[j], c[(j + 1) % 3])).or_default() += 1;
            }
        }
        if faces.len() < 4 || edges.iter().any(|(&(a, b), &n)| n != 1 || edges.get(&(b, a)) != Some(&1)) {
            continue;
        }
        // Outward unit normals: the winding's, or its opposite where the enclosed signed
        // volume is negative.
        let verts: Vec<usize> = {
            let mut v: Vec<usize> = faces.iter().flat_map(|&k| corners[k]).collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        let centre = verts.iter().map(|&v| positions[v]).sum::<DVec3>() / verts.len() as f64;
        let volume: f64 = faces
            .iter()
            .map(|&k| {
                let [a, b, c] = corners[k].map(|v| positions[v] - centre);
                a.dot(b.cross(c))
            })
            .sum();
        let planes: Option<Vec<(DVec3, DVec3)>> = faces
            .iter()
            .map(|&k| {
                let [a, b, c] = corners[k].map(|v| positions[v]);
                let n = (b - a).cross(c - a) * volume.signum();
                (n.length() > 0.0 && volume != 0.0).then(|| (n.normalize(), a))
            })
            .collect();
        let Some(planes) = planes else { continue };
        let part = ConvexPart { faces, planes };
        // Convex: every vertex of the part on or behind every face's plane.
        if !(0..part.faces.len()).all(|i| verts.iter().all(|&v| part.side(i, positions[v]) <= tol)) {
            continue;
        }
        solids.push(part);
    }
    solids
}

impl Scene {
    /// Pairs (a, b, n) of opposite faces of closed convex solids among `triangles` (at most 64,
    /// kernel order; `materials[k]` is triangle k's material) of which rays that look for the
    /// nearest hit need test only the one turned towards them: a where d . n <= 0, else b (n: a's
    /// outward unit normal). See the module for when this holds; none where it may not.
    pub fn front_face_pairs(&self, triangles: &[[[f32; 3]; 3]], materials: &[u32]) -> Vec<(usize, usize, [f32; 3])> {
        let triangles = &triangles[..triangles.len().min(64)];
        if !self.media.is_empty() || self.camera_medium.is_some() {
            return Vec::new();
        }
        let mut origins = self.camera.ray_origin_corners(self.render.width, self.render.height);
        origins.push(self.camera.position);
        let scale = triangles.iter().flatten().flatten().map(|c| c.abs() as f64).chain(origins.iter().map(|o| o.abs().max_element())).fold(1.0, f64::max);
        // Nothing lets a ray through the face: an opaque, reflecting material that emits nothing.
        let solid = |m: usize| {
            let m = &self.materials[m];
            !m.bsdf.transmits() && !m.bsdf.both_sides() && m.opacity.is_none() && m.blend.is_none() && !m.is_emissive() && m.interior.is_none() && m.exterior.is_none()
        };
        let mut pairs = Vec::new();
        for part in closed_convex_parts(triangles, scale) {
            if !part.faces.iter().all(|&k| materials.get(k).is_some_and(|&m| solid(m as usize))) {
                continue;
            }
            // Every camera ray leaves from outside: in front of one face, with a margin.
            if !origins.iter().all(|&o| (0..part.faces.len()).any(|i| part.side(i, o) > CAMERA_MARGIN * scale)) {
                continue;
            }
            if !self.nothing_reaches_in(&part, triangles, scale) {
                continue;
            }
            let mut paired = vec![false; part.faces.len()];
            for i in 0..part.faces.len() {
                for j in i + 1..part.faces.len() {
                    if !paired[i] && !paired[j] && (part.planes[i].0 + part.planes[j].0).length() < OPPOSITE {
                        paired[i] = true;
                        paired[j] = true;
                        pairs.push((part.faces[i], part.faces[j], part.planes[i].0.as_vec3().to_array()));
                    }
                }
            }
        }
        pairs
    }

    /// Whether no other surface comes near the solid `part` but at a right angle or parallel to
    /// each of its faces: every other triangle (of `triangles`), sphere and quadric lies in front
    /// of one of its faces by more than `CLEAR` of the scene's size, or (a triangle, an infinite
    /// plane) has the whole solid on one side of its plane by as much, or else its normal is
    /// parallel or perpendicular to every face's. A path vertex on a surface that reaches into the solid at
    /// another angle may lie within the offset of a ray's origin (`offset_ray_origin`) of one
    /// of its faces, and the offset along that surface's normal may carry the origin inside;
    /// along a normal perpendicular to the face that keeps the vertex outside, it stays outside
    /// (the Cornell box's floor, on which one box stands and into which the other reaches).
    fn nothing_reaches_in(&self, part: &ConvexPart, triangles: &[[[f32; 3]; 3]], scale: f64) -> bool {
        let margin = CLEAR * scale;
        let clear = |points: &[DVec3], r: f64| (0..part.faces.len()).any(|i| points.iter().all(|&p| part.side(i, p) - r > margin));
        let aligned = |n: DVec3| {
            part.planes.iter().all(|&(m, _)| {
                let c = n.dot(m).abs();
                c < ALIGNED || c > 1.0 - ALIGNED
            })
        };
        let point = |c: [f32; 3]| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64);
        let vertices: Vec<DVec3> = part.faces.iter().flat_map(|&k| triangles[k].map(point)).collect();
        // The whole solid on one side of the plane through p with unit normal n.
        let beside = |n: DVec3, p: DVec3| {
            let (lo, hi) = vertices.iter().map(|&v| n.dot(v - p)).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
            lo > margin || hi < -margin
        };
        let triangles_clear = triangles.iter().enumerate().filter(|(k, _)| !part.faces.contains(k)).all(|(_, t)| {
            let [a, b, c] = t.map(point);
            let n = (b - a).cross(c - a).normalize_or_zero();
            clear(&[a, b, c], 0.0) || beside(n, a) || aligned(n)
        });
        let planes_clear = self.planes.iter().all(|pl| {
            let n = pl.normal.normalize_or_zero();
            beside(n, pl.point) || aligned(n)
        });
        triangles_clear
            && planes_clear
            && self.spheres.iter().all(|s| clear(&[s.center], s.radius))
            && self.quadrics.iter().all(|q| clear(&q.box_corners(), 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corners(scene: &Scene) -> Vec<[[f32; 3]; 3]> {
        scene.meshes.iter().flat_map(|m| m.triangles.iter().map(|t| t.map(|i| m.positions[i as usize].as_vec3().to_array()))).collect()
    }

    fn materials(scene: &Scene) -> Vec<u32> {
        scene.meshes.iter().flat_map(|m| m.triangles.iter().map(|_| m.material as u32)).collect()
    }

    fn cube_scene(material: &str, camera_z: f64) -> Scene {
        cube_with(material, camera_z, "rotate = { axis = [1, 1, 0], angle = 17 }", "")
    }

    /// A cube (`transform`) under a lamp panel, seen from z = `camera_z`, with `extra` appended.
    fn cube_with(material: &str, camera_z: f64, transform: &str, extra: &str) -> Scene {
        let text = format!(
            "[camera]\nposition = [0, 0, {camera_z}]\nlook_at = [0, 0, -10]\nup = [0, 1, 0]\nfov_x = 40\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 3\n\
             [materials.white]\ndiffuse = 0.5\n[materials.glass]\nbsdf = \"dielectric\"\n[materials.pane]\nbsdf = \"thindielectric\"\n[materials.lamp]\nemission = 1\n\
             [[rectangles]]\nmaterial = \"lamp\"\ntransform = {{ translate = [0, 3, 0], rotate = {{ axis = [1, 0, 0], angle = 90 }} }}\n\
             [[cubes]]\nmaterial = \"{material}\"\ntransform = {{ {transform} }}\n{extra}"
        );
        Scene::parse(&text, "cube.toml").unwrap()
    }

    #[test]
    fn a_cubes_opposite_faces_pair_up_and_the_cornell_boxs_boxes_too() {
        let s = cube_scene("white", 6.0);
        let (t, m) = (corners(&s), materials(&s));
        let pairs = s.front_face_pairs(&t, &m);
        // The rotated cube's 12 triangles: 6 pairs, each of two opposite faces, every triangle
        // once; the lamp (open) has none.
        assert_eq!(pairs.len(), 6, "{pairs:?}");
        let mut seen: Vec<usize> = pairs.iter().flat_map(|&(a, b, _)| [a, b]).collect();
        seen.sort_unstable();
        assert_eq!(seen, (2..14).collect::<Vec<_>>());
        for &(a, b, n) in &pairs {
            let normal = |k: usize| {
                let [p, q, r] = t[k].map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64));
                (q - p).cross(r - p).normalize()
            };
            let n = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
            assert!((normal(a) - n).length() < 1e-6 && (normal(b) + n).length() < 1e-6, "{a} {b} {n:?}");
            // n points out of the cube (centred at the origin).
            assert!(n.dot(DVec3::new(t[a][0][0] as f64, t[a][0][1] as f64, t[a][0][2] as f64)) > 0.0);
        }
        let cornell = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
        assert_eq!(cornell.front_face_pairs(&corners(&cornell), &materials(&cornell)).len(), 12);
    }

    #[test]
    fn no_pairs_where_a_ray_may_start_inside_or_pass_through() {
        // The camera inside the cube.
        let s = cube_scene("white", 0.0);
        assert!(s.front_face_pairs(&corners(&s), &materials(&s)).is_empty());
        // A glass cube: rays refract into it and leave through its far faces.
        let s = cube_scene("glass", 6.0);
        assert!(s.front_face_pairs(&corners(&s), &materials(&s)).is_empty());
        // An emissive cube (camera rays pass through hidden emitters).
        let s = cube_scene("lamp", 6.0);
        assert!(s.front_face_pairs(&corners(&s), &materials(&s)).is_empty());
    }

    #[test]
    fn a_surface_through_the_cube_keeps_its_pairs_only_at_right_angles() {
        let floor = |angle: f64| format!("[[rectangles]]\nmaterial = \"pane\"\ntransform = {{ translate = [0, -0.5, 0], rotate = {{ axis = [1, 0, 0], angle = {angle} }}, scale = [3, 3, 3] }}\n");
        // A floor through the cube, parallel to its top and bottom, at right angles to its sides:
        // an origin offset along the floor's normal stays outside.
        let s = cube_with("white", 6.0, "rotate = { axis = [0, 1, 0], angle = 17 }", &floor(-90.0));
        assert_eq!(s.front_face_pairs(&corners(&s), &materials(&s)).len(), 6);
        // Tilted by 17 degrees, it may carry an origin inside: none.
        let s = cube_with("white", 6.0, "rotate = { axis = [0, 1, 0], angle = 17 }", &floor(-73.0));
        assert!(s.front_face_pairs(&corners(&s), &materials(&s)).is_empty());
        // Far below the cube, tilted or not, it is clear of it.
        let far = floor(-73.0).replace("-0.5, 0]", "-5, 0]");
        let s = cube_with("white", 6.0, "rotate = { axis = [0, 1, 0], angle = 17 }", &far);
        assert_eq!(s.front_face_pairs(&corners(&s), &materials(&s)).len(), 6);
    }
}
