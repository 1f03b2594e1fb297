//! Triangles no shadow ray can meet: faces on the scene's hull (issue 31).
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

use glam::DVec3;

use super::Scene;

/// Points of the scene within this relative distance of a plane lie on it.
const ON_PLANE: f64 = 1e-6;
/// Camera ray origins must lie further inside than this relative distance.
const CAMERA_MARGIN: f64 = 1e-4;

impl Scene {
    /// Bit k set where shadow rays must test `triangles[k]` (at most 64, kernel order, as the
    /// kernel holds them): clear only for the faces of the scene's hull (see the module).
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
        tests
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

    #[test]
    fn the_cornell_boxs_walls_and_its_tall_boxs_bottom_meet_no_shadow_ray() {
        let s = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
        let t = corners(&s);
        assert_eq!(t.len(), 36);
        let tests = s.shadow_tests_of(&t);
        assert_eq!(tests.count_ones(), 26, "{tests:036b}");
        // The culled: ceiling, back and side walls (x, y or z = +-1, all but the floor, which the
        // tall box reaches 0.01 below) and that box's bottom (y = -1.01).
        let culled: Vec<(usize, f32)> = t
            .iter()
            .enumerate()
            .filter(|(k, _)| tests & (1 << k) == 0)
            .map(|(_, tri)| (0..3).find(|&a| tri.iter().all(|p| (p[a] - tri[0][a]).abs() < 1e-5)).map_or((9, 0.0), |a| (a, tri[0][a])))
            .collect();
        let mut planes: Vec<String> = culled.iter().map(|(a, v)| format!("{}={v:.2}", ["x", "y", "z", "?"][(*a).min(3)])).collect();
        planes.sort();
        assert_eq!(planes, ["x=-1.00", "x=-1.00", "x=1.00", "x=1.00", "y=-1.01", "y=-1.01", "y=1.00", "y=1.00", "z=-1.00", "z=-1.00"]);
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
