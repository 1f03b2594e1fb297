//! Triangles no shadow ray needs to test: faces on the scene's hull, and the faces of closed
//! convex meshes turned away from every light (issue 31).
//!
//! A shadow ray runs from a path vertex to a point of a light. Where every object of the scene
//! and every light lies on one side of a triangle's plane (or on it), and every camera ray
//! leaves from strictly inside that side, each path vertex and each light point lies in that
//! closed half-space: every ray starts there, and a ray that crosses the plane finds nothing
//! beyond it, so no vertex is seen from the far side. The segment between two points of a closed
//! half-space stays in it and meets the plane at most where it ends, or along it (parallel to
//! the triangle, where the watertight test finds no hit), so the triangle cannot block it.
//!
//! The Cornell box's ceiling, back wall and side walls are such faces, and so is the bottom of
//! its tall box, which reaches 0.01 below the floor (so the floor is not one): 10 of its 36
//! triangles. lavapipe runs every triangle test of a small scene (it skips no branch), so its
//! shadow rays now test 26 (`SharedVertices::shadow_tests`, the `SMALL_SHADOW_TESTS_<k>`
//! overrides): 6.5% fewer kernel instructions (README, issue 31).
//!
//! Conservative: where any shadow ray may run to infinity (a directional light, or an
//! environment that next event estimation samples: `gpu::PipelineKey::new`), where an infinite
//! plane is in the scene, or where media are (their vertices lie off the surfaces, in a
//! medium that may be unbounded), every triangle is tested. Points within a relative 1e-6 of
//! the plane count as on it (the corners of a quad's other triangle, a box standing on the
//! floor); the camera must be further inside than a relative 1e-4.
//!
//! **Back faces of closed convex meshes** (`closed_back_faces`). Where the triangles of a
//! connected part of the scene (sharing vertex positions) close a convex solid, every edge met
//! once in each direction (`convex_parts.rs` finds them), a shadow segment that crosses one of its faces at a point and enters
//! the solid there must leave it again before it reaches the light, provided the light lies
//! outside the solid: the last crossing is an exit, through a face G, moving along G's outward
//! normal, so the light point lies strictly in front of G's plane. A face whose plane has every
//! point of every light strictly behind it is therefore never that exit, and every segment
//! that crosses it also crosses a face that shadow rays still test (a segment through a shared
//! edge or a vertex, where the watertight test may report either face, has measure zero). The
//! light lies outside the solid where one face's plane has every light point in front of it, by
//! more than a shadow ray stops short of its light (`SEPARATION`). Every triangle blocks a
//! shadow ray whatever its material (the kernel's `occluded`), so materials do not matter;
//! what disables the hull's faces (rays to infinity, infinite planes, media, where shadow rays
//! cross null surfaces) disables this too. The Cornell box's two boxes are such solids under
//! its ceiling light: 10 more of its triangles, two sides and the bottom of the short box, two
//! sides of the tall one (whose bottom is on the hull). Its shadow rays test 16 of its 36
//! triangles.
//!
//! Not left out, though no shadow segment can meet them before it ends: the triangles of a
//! planar light, where every light point lies in their plane. A light's two triangles are
//! coplanar only to f32 rounding, so a shadow ray at a grazing angle can find the other
//! triangle before it stops short: leaving them out changed 4 pixels of 1,728 of a Cornell box
//! render (by at most 1e-3 relative), and the images must stay those of the BVH's traversal,
//! bit for bit (`tests/mesh_scenes.rs`).

use glam::DVec3;

use super::convex_parts::{closed_convex_parts, ON_PLANE};
use super::Scene;
/// Camera ray origins must lie further inside than this relative distance.
const CAMERA_MARGIN: f64 = 1e-4;
/// Lights must lie further than this relative distance in front of a closed mesh's separating
/// face for its back faces to be left out (`Scene::closed_back_faces`): more than the 1e-4 of
/// the scene's diagonal (2 sqrt(3) times the scale) by which a shadow ray stops short.
const SEPARATION: f64 = 1e-3;

impl Scene {
    /// Bit k set where shadow rays must test `triangles[k]` (at most 64, kernel order, as the
    /// kernel holds them): clear only for the faces of the scene's hull and the faces of closed
    /// convex meshes turned away from every light (see the module).
    pub fn shadow_tests_of(&self, triangles: &[[[f32; 3]; 3]]) -> u64 {
        let all = if triangles.len() >= 64 { u64::MAX } else { (1u64 << triangles.len()) - 1 };
        if !self.planes.is_empty() || !self.directional_lights.is_empty() || !self.media.is_empty() || self.camera_medium.is_some() {
            return all;
        }
        // Every point the scene's surfaces and lights reach, as (point, radius): mesh vertices,
        // spheres, the boxes around quadrics, point-like lights.
        let mut points: Vec<(DVec3, f64)> = self.meshes.iter().flat_map(|m| m.positions.iter().map(|&p| (p, 0.0))).collect();
        points.extend(self.spheres.iter().map(|s| (s.center, s.radius)));
        points.extend(self.quadrics.iter().flat_map(|q| q.box_corners().map(|c| (c, 0.0))));
        points.extend(self.point_lights.iter().map(|l| (l.position, 0.0)));
        points.extend(self.spot_lights.iter().map(|l| (l.position, 0.0)));
        points.extend(self.projector_lights.iter().map(|l| (l.position, 0.0)));
        let mut origins = self.camera.ray_origin_corners(self.render.width, self.render.height);
        origins.push(self.camera.position);
        let scale = points.iter().copied().chain(origins.iter().map(|&o| (o, 0.0))).fold(1.0f64, |m, (p, r)| m.max(p.abs().max_element() + r));
        let back_faces = self.closed_back_faces(triangles, scale);
        let mut tests = all;
        for (k, t) in triangles.iter().enumerate().take(64) {
            let [p0, p1, p2] = t.map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
            let n = (p1 - p0).cross(p2 - p0);
            let len = n.length();
            if !(len > 0.0) {
                continue;
            }
            // Signed distance from the triangle's plane.
            let n = n / len;
            let side = |x: DVec3| n.dot(x - p0);
            let outermost = points.iter().map(|&(p, r)| side(p) + r).fold(f64::NEG_INFINITY, f64::max);
            let innermost = points.iter().map(|&(p, r)| side(p) - r).fold(f64::INFINITY, f64::min);
            // The side the scene lies on: -1 (behind n) or +1; camera rays must leave from inside it.
            let sign = if outermost <= ON_PLANE * scale {
                -1.0
            } else if innermost >= -ON_PLANE * scale {
                1.0
            } else {
                continue;
            };
            if origins.iter().all(|&o| sign * side(o) > CAMERA_MARGIN * scale) {
                tests &= !(1u64 << k);
            }
        }
        tests & !back_faces
    }

    /// Every point a shadow ray may end at, as (point, radius): the emissive spheres, meshes and
    /// quadrics (their boxes' corners) and the point-like lights.
    fn light_points(&self) -> Vec<(DVec3, f64)> {
        let emits = |m: usize| self.materials[m].is_emissive();
        let mut points: Vec<(DVec3, f64)> = self.spheres.iter().filter(|s| emits(s.material)).map(|s| (s.center, s.radius)).collect();
        points.extend(self.meshes.iter().filter(|m| emits(m.material)).flat_map(|m| m.positions.iter().map(|&p| (p, 0.0))));
        points.extend(self.quadrics.iter().filter(|q| emits(q.material)).flat_map(|q| q.box_corners().map(|c| (c, 0.0))));
        points.extend(self.point_lights.iter().map(|l| (l.position, 0.0)));
        points.extend(self.spot_lights.iter().map(|l| (l.position, 0.0)));
        points.extend(self.projector_lights.iter().map(|l| (l.position, 0.0)));
        points
    }

    /// Bit k set where `triangles[k]` (at most 64) is a face of a closed convex mesh whose plane
    /// has every light point strictly behind it, the light lying outside that mesh (see the
    /// module). Conservative: a part whose edges do not pair up, that is not convex within a
    /// relative 1e-6, or with a degenerate face, keeps every face.
    ///
    /// `scale` bounds every coordinate of the scene's surfaces and of its camera's ray origins
    /// (so every path vertex lies within it). A shadow ray stops short of its light point by
    /// 1e-4 of its length (`shadow_ray_to`), at most 1e-4 times the scene's diagonal, 2 sqrt(3)
    /// `scale`: the separating plane must leave the lights more than `SEPARATION` `scale` in
    /// front of the solid, so that the exit through a tested face comes before the ray stops.
    fn closed_back_faces(&self, triangles: &[[[f32; 3]; 3]], scale: f64) -> u64 {
        let triangles = &triangles[..triangles.len().min(64)];
        let lights = self.light_points();
        if lights.is_empty() {
            return 0;
        }
        let tol = ON_PLANE * scale;
        let mut culled = 0u64;
        for part in closed_convex_parts(triangles, scale) {
            let side = |i: usize, (y, r): (DVec3, f64)| (part.side(i, y) - r, part.side(i, y) + r);
            // The lights outside the solid: one face's plane has all of them strictly in front.
            if !(0..part.faces.len()).any(|i| lights.iter().all(|&l| side(i, l).0 > SEPARATION * scale)) {
                continue;
            }
            for (i, &k) in part.faces.iter().enumerate() {
                if lights.iter().all(|&l| side(i, l).1 < -tol) {
                    culled |= 1 << k;
                }
            }
        }
        culled
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corners(scene: &Scene) -> Vec<[[f32; 3]; 3]> {
        scene.meshes.iter().flat_map(|m| m.triangles.iter().map(|t| t.map(|i| m.positions[i as usize].as_vec3().to_array()))).collect()
    }

    fn scene(extra: &str, camera_z: f64) -> Scene {
        // An open box: floor, back wall and a light panel below the top, seen from the front.
        let text = format!(
            "[camera]\nposition = [0, 0, {camera_z}]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 3\n\
             [materials.white]\ndiffuse = 0.5\n[materials.lamp]\nemission = 1\n\
             [[rectangles]]\nmaterial = \"white\"\ntransform = {{ translate = [0, -1, 0], rotate = {{ axis = [1, 0, 0], angle = -90 }} }}\n\
             [[rectangles]]\nmaterial = \"white\"\ntransform = {{ translate = [0, 0, -1] }}\n\
             [[rectangles]]\nmaterial = \"lamp\"\ntransform = {{ translate = [0, 0.9, 0], rotate = {{ axis = [1, 0, 0], angle = 90 }}, scale = [0.3, 0.3, 0.3] }}\n{extra}"
        );
        Scene::parse(&text, "test.toml").unwrap()
    }

    /// The unit outward normal of a triangle's winding, and a corner.
    fn plane(tri: &[[f32; 3]; 3]) -> (DVec3, DVec3) {
        let [a, b, c] = tri.map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
        ((b - a).cross(c - a).normalize(), a)
    }

    #[test]
    fn the_cornell_boxs_walls_and_its_boxes_back_faces_meet_no_shadow_ray() {
        let s = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
        let t = corners(&s);
        assert_eq!(t.len(), 36);
        let tests = s.shadow_tests_of(&t);
        assert_eq!(tests.count_ones(), 16, "{tests:036b}");
        // The hull: ceiling, back and side walls (x, y or z = +-1, all but the floor, which the
        // tall box reaches 0.01 below) and that box's bottom (y = -1.01); the short box's bottom
        // (y = -1, where the floor is, which stays).
        let axis_planes: Vec<String> = t
            .iter()
            .enumerate()
            .filter(|(k, _)| tests & (1 << k) == 0)
            .filter_map(|(_, tri)| (0..3).find(|&a| tri.iter().all(|p| (p[a] - tri[0][a]).abs() < 1e-5)).map(|a| format!("{}={:.2}", ["x", "y", "z"][a], tri[0][a])))
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        assert_eq!(axis_planes, ["x=-1.00", "x=1.00", "y=-1.00", "y=-1.01", "y=1.00", "z=-1.00"]);
        // The boxes' faces left out (all but the bottoms are rotated 17 degrees about y): each
        // has every corner of the light strictly behind its outward plane (the winding's, which
        // points out of both cubes), and the faces that see the light, the tops, are tested.
        let light: Vec<DVec3> = t[..2].iter().flatten().map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect();
        let boxes = 12..36;
        let culled: Vec<usize> = boxes.clone().filter(|k| tests & (1 << k) == 0).collect();
        assert_eq!(culled.len(), 12, "{culled:?}");
        for &k in &culled {
            let (n, p) = plane(&t[k]);
            assert!(light.iter().all(|&y| n.dot(y - p) < -0.05), "box face {k} (normal {n:?}) sees the light");
        }
        for k in boxes.filter(|k| tests & (1 << k) != 0) {
            let (n, p) = plane(&t[k]);
            assert!(light.iter().any(|&y| n.dot(y - p) > 0.0), "box face {k} is tested without seeing the light");
        }
    }

    /// A scene of a unit cube (a mesh: `cubes`, 12 triangles) under a lamp panel 8 x 0.2 wide at
    /// height `lamp_y`, with `extra` appended.
    fn cube_scene(lamp_y: f64, extra: &str) -> Scene {
        let text = format!(
            "[camera]\nposition = [0, 0, 6]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n\
             [render]\nwidth = 8\nheight = 8\nmax_depth = 3\n\
             [materials.white]\ndiffuse = 0.5\n[materials.lamp]\nemission = 1\n\
             [[rectangles]]\nmaterial = \"lamp\"\ntransform = {{ translate = [0, {lamp_y}, 0], rotate = {{ axis = [1, 0, 0], angle = 90 }}, scale = [4, 0.1, 1] }}\n\
             [[cubes]]\nmaterial = \"white\"\n{extra}"
        );
        Scene::parse(&text, "cube.toml").unwrap()
    }

    #[test]
    fn a_closed_cube_leaves_out_its_faces_turned_away_from_every_light() {
        // The lamp panel spans x in [-4, 4] at y = 3: the cube's bottom (y = -1) and its faces
        // towards +z and -z (the panel is 0.2 deep) see none of it; its top and its x sides do.
        let s = cube_scene(3.0, "");
        let t = corners(&s);
        assert_eq!(t.len(), 14);
        let back = s.closed_back_faces(&t, 4.0);
        let normals: std::collections::BTreeSet<[i64; 3]> = (0..t.len()).filter(|k| back & (1 << k) != 0).map(|k| plane(&t[k]).0.round().as_i64vec3().to_array()).collect();
        assert_eq!(back.count_ones(), 6, "{back:014b}");
        assert_eq!(normals.into_iter().collect::<Vec<_>>(), [[0, -1, 0], [0, 0, -1], [0, 0, 1]]);
    }

    #[test]
    fn a_cube_keeps_every_face_where_it_is_open_or_holds_or_touches_the_light() {
        // A lamp inside the cube: no plane separates it, every face is tested.
        let inside = cube_scene(0.5, "");
        assert_eq!(inside.closed_back_faces(&corners(&inside), 4.0), 0);
        // A lamp resting on the cube's top (y = 1): closer than a shadow ray stops short of it.
        let touching = cube_scene(1.0 + 1e-4, "");
        assert_eq!(touching.closed_back_faces(&corners(&touching), 4.0), 0);
        // A cube without its top face is no closed solid: a ray entering through the bottom
        // leaves through the opening.
        let s = cube_scene(3.0, "");
        let mut t = corners(&s);
        let tops: Vec<usize> = (0..t.len()).filter(|&k| plane(&t[k]).0.dot(DVec3::Y) > 0.99 && t[k][0][1] > 0.99 && t[k][0][1] < 1.01).collect();
        assert_eq!(tops.len(), 2);
        for k in tops.into_iter().rev() {
            t.remove(k);
        }
        assert_eq!(s.closed_back_faces(&t, 4.0), 0);
        // A spherical light behind the cube's bottom and one above it: every face sees one.
        let two = cube_scene(3.0, "[[spheres]]\ncenter = [0, -3, 0]\nradius = 0.5\nmaterial = \"lamp\"\n");
        assert_eq!(two.closed_back_faces(&corners(&two), 4.0), 0);
    }

    #[test]
    fn a_face_is_tested_where_the_camera_light_or_an_object_is_beyond_it() {
        let s = scene("", 4.0);
        let t = corners(&s);
        // Floor and back wall lie on the hull; the lamp, below the rest, does not.
        assert_eq!(s.shadow_tests_of(&t), 0b110000);
        // The camera behind the back wall (it may see the wall's far side): the wall is tested.
        let s = scene("", -4.0);
        assert_eq!(s.shadow_tests_of(&corners(&s)), 0b111100);
        // A point light below the floor, a sphere through it: the floor is tested.
        let s = scene("[[point_lights]]\nposition = [0, -2, 0]\nintensity = 1\n", 4.0);
        assert_eq!(s.shadow_tests_of(&corners(&s)), 0b110011);
        let s = scene("[[spheres]]\ncenter = [0, -1, 0]\nradius = 0.2\nmaterial = \"white\"\n", 4.0);
        assert_eq!(s.shadow_tests_of(&corners(&s)), 0b110011);
        // Shadow rays to infinity, an infinite plane: every triangle is tested.
        let s = scene("[[directional_lights]]\ndirection = [0, -1, 0]\nirradiance = 1\n", 4.0);
        assert_eq!(s.shadow_tests_of(&corners(&s)), 0b111111);
        let s = scene("[[planes]]\npoint = [0, -3, 0]\nnormal = [0, 1, 0]\nmaterial = \"white\"\n", 4.0);
        assert_eq!(s.shadow_tests_of(&corners(&s)), 0b111111);
    }
}
