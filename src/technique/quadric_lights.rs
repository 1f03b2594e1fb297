//! The check's configurations of a light technique for disk and cylinder lights (Mitsuba's disk
//! and cylinder with an area emitter): up to four distinct lights of each shape from the scene
//! (a unit disk, a cylinder of radius 1 and length 2 where it has none), each seen from four
//! points, the technique through the wrappers the path tracer calls
//! (`sample_disk_light_with_technique`, `sample_cylinder_light_with_technique` and their pdfs,
//! shaders/technique.wgsl) against the built-in area sampling. The samples are binned where they
//! land on the light, on a unit square the light is the image of, so that no cell is cut by the
//! light's rim or by the edge of what the point sees.

use glam::{DAffine3, DVec3};

use super::{planar_light_configuration, planar_viewpoint, v3, Configuration, Pair, SQUARE_AS_DIRECTIONS};
use crate::scene::{EmitterKind, Light, Scene};

/// Lights of each shape a technique is checked on, at most.
const MAX_LIGHTS: usize = 4;

/// The scene's distinct disk or cylinder lights (distinct in shape: their linear maps differ),
/// the first `MAX_LIGHTS`, each moved so that its centre is at the origin (the technique's maths
/// is the same anywhere; f32 keeps its precision), and where they came from; `default` where the
/// scene has none.
fn distinct_lights(scene: &Scene, kind: EmitterKind, default: (DAffine3, &str), what: &str) -> (Vec<DAffine3>, String) {
    let mut maps: Vec<DAffine3> = Vec::new();
    for l in scene.lights_of(kind) {
        if let Light::Disk(i) | Light::Cylinder(i) = l {
            let linear = scene.quadrics[i].to_world.matrix3;
            if !maps.iter().any(|m| m.matrix3 == linear) {
                // The disk's centre is its origin; the cylinder's, halfway along its axis.
                let centre = if kind == EmitterKind::Cylinder { 0.5 * linear.z_axis } else { DVec3::ZERO };
                maps.push(DAffine3 { matrix3: linear, translation: -centre });
            }
            if maps.len() == MAX_LIGHTS {
                break;
            }
        }
    }
    if maps.is_empty() {
        (vec![default.0], format!("{} (the scene has no {what} light, where a {what}-light technique applies)", default.1))
    } else {
        (maps.clone(), format!("{} of the scene's {what} lights", maps.len()))
    }
}

/// The kernel's `Quadric` (quadrics/quadric.wgsl) of the unit shape placed by `m`, as a WGSL
/// expression: its rows both ways, the plane's normal (a disk's), its area. (Its material,
/// light and flags are not read by the routines.)
fn quadric_literal(m: DAffine3, area: f64) -> String {
    let rows = |a: DAffine3| {
        let c = a.to_cols_array();
        [0, 1, 2].map(|r| format!("vec4f({:?}, {:?}, {:?}, {:?})", c[r] as f32, c[3 + r] as f32, c[6 + r] as f32, c[9 + r] as f32)).join(", ")
    };
    let normal = m.matrix3.x_axis.cross(m.matrix3.y_axis).normalize();
    format!("Quadric({}, {}, {}, 0u, {:?}, 1.0, INVALID, 0u)", rows(m.inverse()), rows(m), v3(normal.to_array()), area as f32)
}

/// A disk technique's configurations: each disk seen as `triangle_configurations` sees a
/// triangle, from half its size (sqrt(area)) on its normal and 60 degrees off it, from its size
/// at 80 degrees (nearly in its plane) and from 30 sizes with the normal tilted 70 degrees.
pub(super) fn disk_configurations(scene: &Scene) -> (Vec<Configuration>, String) {
    let (maps, source) = distinct_lights(scene, EmitterKind::Disk, (DAffine3::IDENTITY, "a unit disk"), "disk");
    let configs = maps
        .iter()
        .enumerate()
        .flat_map(|(k, &m)| [(0.5, 0.0, 0.0), (0.5, 60.0, 0.0), (1.0, 80.0, 0.0), (30.0, 0.0, 70.0)].map(move |(dist, angle, tilt)| disk_configuration(k, m, dist, angle, tilt)))
        .collect();
    (configs, source)
}

/// Disk `k` (the unit disk placed by `m`, centred at the origin) seen from a point at `dist`
/// times its size from its centre, `angle` degrees off its normal (towards its first axis),
/// whose shading normal is tilted `tilt` degrees from the direction to the centre
/// (`planar_viewpoint`). The samples are binned where they land on the disk, on the unit square
/// it is the image of under the polar area map (u0 = r^2, u1 = phi / 2 pi of its object space,
/// of constant area density): the cells tile the disk exactly (`planar_light_configuration`).
fn disk_configuration(k: usize, m: DAffine3, dist: f64, angle: f64, tilt: f64) -> Configuration {
    let (u, v) = (m.matrix3.x_axis, m.matrix3.y_axis);
    let c = u.cross(v);
    let (area, normal) = (std::f64::consts::PI * c.length(), c.normalize());
    let (x, n) = planar_viewpoint(normal, u.normalize(), area, dist, angle, tilt);
    let light = format!(
        "const ROUTINE_X: vec3f = {};\nconst ROUTINE_N: vec3f = {};\nconst ROUTINE_NT: vec3f = {};\nconst ROUTINE_AREA: f32 = {:?};\n\
         const ROUTINE_U: vec3f = {};\nconst ROUTINE_V: vec3f = {};\n\
         fn routine_q() -> Quadric {{ return {}; }}\n\
         // The disk's point at (u0, u1) of the polar area map.\n\
         fn routine_point(uv: vec2f) -> vec3f {{ let r = sqrt(uv.x); return r * (cos(2.0 * PI * uv.y) * ROUTINE_U + sin(2.0 * PI * uv.y) * ROUTINE_V); }}\n\
         // (u0, u1) of a point of the disk, from its object-space polar coordinates.\n\
         fn routine_uv_of(p: vec3f) -> vec2f {{\n\
             let l = quadric_point_to_object(routine_q(), p);\n\
             var u1 = atan2_accurate(l.y, l.x) * (0.5 * INV_PI);\n\
             u1 = u1 - floor(u1);\n\
             return vec2f(clamp(dot(l.xy, l.xy), 0.0, 1.0), clamp(u1, 0.0, 0.99999994));\n\
         }}\n",
        v3(x.to_array()),
        v3(n.to_array()),
        v3(normal.to_array()),
        area as f32,
        v3(u.to_array()),
        v3(v.to_array()),
        quadric_literal(m, area),
    );
    planar_light_configuration(
        format!("disk {k} (area {area:.4}) seen from {dist} sizes, {angle} degrees off its normal, normal tilted {tilt} degrees"),
        light,
        ("pdf_disk_light_technique(ROUTINE_X, ROUTINE_N, disk_light_of(routine_q()), p)", "sample_disk_light_with_technique(routine_q(), ROUTINE_X, ROUTINE_N, u)"),
        ("pdf_disk_light(routine_q(), ROUTINE_X, normalize(p - ROUTINE_X))", "sample_disk_light(routine_q(), ROUTINE_X, u)"),
        vec![],
    )
}

/// A cylinder technique's configurations: each cylinder seen from points of its object space
/// (rho, 0, z), rho in radii from its axis, z along it (its length is 1), all within its length,
/// where what a point sees has a closed form: from 1.5 radii at half its length (the normal
/// towards the axis), from 1.5 radii near an end (z = 0.1, the normal tilted 70 degrees), from
/// 30 radii (tilted 70 degrees), and from inside, half a radius from the axis (it sees the whole
/// inner surface).
pub(super) fn cylinder_configurations(scene: &Scene) -> (Vec<Configuration>, String) {
    let unit = DAffine3::from_translation(DVec3::new(0.0, 0.0, -1.0)) * DAffine3::from_scale(DVec3::new(1.0, 1.0, 2.0));
    let (maps, source) = distinct_lights(scene, EmitterKind::Cylinder, (unit, "a cylinder of radius 1 and length 2"), "cylinder");
    let configs = maps
        .iter()
        .enumerate()
        .flat_map(|(k, &m)| [(1.5, 0.5, 0.0), (1.5, 0.1, 70.0), (30.0, 0.5, 70.0), (0.5, 0.5, 0.0)].map(move |(rho, z, tilt)| cylinder_configuration(k, m, rho, z, tilt)))
        .collect();
    (configs, source)
}

/// Cylinder `k` (the unit cylinder placed by `m`: the points base + cos(phi) U + sin(phi) V + z W)
/// seen from its object-space point (rho, 0, z), 0 < z < 1, whose shading normal is tilted `tilt`
/// degrees from the direction to the axis. From outside (rho > 1) such a point sees exactly the
/// points with |phi| <= beta = acos(1 / rho), of the outer surface (a segment to any other point
/// of the cylinder enters it first within its length: a hit); from inside, all of the inner
/// surface. The samples are binned where they land on the cylinder, on the unit square of
/// u0 = (phi - phi_start) / 2 pi (mod 1), phi_start = -beta (0 from inside), and u1 = z, written
/// as the direction at phi = 2 pi u1, s = 2 u0: the visible arc is s in [0, 2 beta / pi], a bin
/// edge, and the points it hides are lost samples, which contribute nothing. The density there is
/// the solid-angle density at x times d(omega) / d(bins) = |dot(C, x - p)| / (2 dist^3), with C =
/// dp/dphi x W the area element per dphi dz (the square's area per cell times 2 pi / 4 pi). The
/// integrand is that Jacobian where x sees p: the coverage test compares estimates of the
/// cylinder's visible solid angle.
fn cylinder_configuration(k: usize, m: DAffine3, rho: f64, z: f64, tilt: f64) -> Configuration {
    let (u, v, w) = (m.matrix3.x_axis, m.matrix3.y_axis, m.matrix3.z_axis);
    let x = m.transform_point3(DVec3::new(rho, 0.0, z));
    let axis_point = m.transform_point3(DVec3::new(0.0, 0.0, z));
    let towards = (axis_point - x).normalize();
    let side = towards.cross(w).try_normalize().unwrap_or_else(|| towards.any_orthonormal_vector());
    let t = tilt.to_radians();
    let n = t.cos() * towards + t.sin() * side;
    let (phi_start, arc) = if rho > 1.0 {
        let beta = (1.0 / rho).acos();
        (-beta, beta / std::f64::consts::PI)
    } else {
        (0.0, 1.0)
    };
    // Mitsuba's area, as the kernel's record has it (src/scene/quadrics/cylinder.rs).
    let area = std::f64::consts::TAU * u.length() * w.length();
    let common = format!(
        "const ROUTINE_X: vec3f = {};\nconst ROUTINE_N: vec3f = {};\n\
         const ROUTINE_BASE: vec3f = {};\nconst ROUTINE_U: vec3f = {};\nconst ROUTINE_V: vec3f = {};\nconst ROUTINE_W: vec3f = {};\n\
         const ROUTINE_PHI_START: f32 = {:?};\nconst ROUTINE_ARC: f32 = {:?};\n\
         fn routine_q() -> Quadric {{ return {}; }}\n\
         // The angle of u0, and the cylinder's point at (u0, u1).\n\
         fn routine_phi(u0: f32) -> f32 {{ return ROUTINE_PHI_START + 2.0 * PI * u0; }}\n\
         fn routine_point(uv: vec2f) -> vec3f {{ let phi = routine_phi(uv.x); return ROUTINE_BASE + cos(phi) * ROUTINE_U + sin(phi) * ROUTINE_V + uv.y * ROUTINE_W; }}\n\
         fn routine_visible(uv: vec2f) -> bool {{ return uv.x <= ROUTINE_ARC; }}\n\
         {SQUARE_AS_DIRECTIONS}\
         // (u0, u1) of a point of the cylinder, from its object-space angle and height.\n\
         fn routine_uv_of(p: vec3f) -> vec2f {{\n\
             let l = quadric_point_to_object(routine_q(), p);\n\
             var u0 = (atan2_accurate(l.y, l.x) - ROUTINE_PHI_START) * (0.5 * INV_PI);\n\
             u0 = u0 - floor(u0);\n\
             return vec2f(clamp(u0, 0.0, 1.0), clamp(l.z, 0.0, 0.99999994));\n\
         }}\n\
         // d(solid angle at x) / d(binning solid angle) at the cylinder's point of (u0, u1).\n\
         fn routine_jacobian(uv: vec2f) -> f32 {{\n\
             let phi = routine_phi(uv.x);\n\
             let c = cross(-sin(phi) * ROUTINE_U + cos(phi) * ROUTINE_V, ROUTINE_W);\n\
             let to_x = ROUTINE_X - routine_point(uv);\n\
             let dist2 = dot(to_x, to_x);\n\
             return abs(dot(c, to_x)) / (2.0 * sqrt(dist2) * dist2);\n\
         }}\n\
         fn routine_integrand(d: vec3f) -> f32 {{ let uv = routine_uv(d); return select(0.0, routine_jacobian(uv), routine_visible(uv)); }}\n",
        v3(x.to_array()),
        v3(n.to_array()),
        v3(m.translation.to_array()),
        v3(u.to_array()),
        v3(v.to_array()),
        v3(w.to_array()),
        phi_start as f32,
        arc as f32,
        quadric_literal(m, area),
    );
    // A sample on a point x does not see is lost (check.y = 1): it contributes nothing.
    let draw = "let p = ROUTINE_X + s.ls.wi * s.ls.dist;\n\
             let uv = routine_uv_of(p);\n\
             let d = routine_dir(uv);\n\
             let seen = routine_visible(uv);\n\
             let estimate = select(0.0, 1.0 / s.ls.pdf, seen && s.ls.pdf > 0.0);\n\
             return Drawn(vec4f(d, routine_pdf(d)), vec4f(0.0, select(1.0, 0.0, seen), estimate, 0.0));\n";
    let technique = format!(
        "{common}\
         fn routine_technique_pdf(p: vec3f) -> f32 {{\n\
             technique_iterations = 0u;\n\
             return technique_density(pdf_cylinder_light_technique(ROUTINE_X, ROUTINE_N, cylinder_light_of(routine_q()), p));\n\
         }}\n\
         fn routine_pdf(d: vec3f) -> f32 {{\n\
             let uv = routine_uv(d);\n\
             if (!routine_visible(uv)) {{ return 0.0; }}\n\
             return routine_technique_pdf(routine_point(uv)) * routine_jacobian(uv);\n\
         }}\n\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let s = sample_cylinder_light_with_technique(routine_q(), ROUTINE_X, ROUTINE_N, u, 0.0);\n\
             // (The technique reports no density of its own: pathlab asks its pdf, as here.)\n\
             {draw}\
         }}\n"
    );
    let builtin = format!(
        "{common}\
         fn routine_pdf(d: vec3f) -> f32 {{\n\
             let uv = routine_uv(d);\n\
             if (!routine_visible(uv)) {{ return 0.0; }}\n\
             let p = routine_point(uv);\n\
             return pdf_cylinder_light(routine_q(), ROUTINE_X, normalize(p - ROUTINE_X), 0.0) * routine_jacobian(uv);\n\
         }}\n\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let s = sample_cylinder_light(routine_q(), ROUTINE_X, u);\n\
             {draw}\
         }}\n"
    );
    let where_ = if rho > 1.0 { format!("from {rho} radii") } else { format!("from inside, {rho} radii from its axis") };
    let name = format!("cylinder {k} (area {area:.4}) seen {where_} at {z} of its length, normal tilted {tilt} degrees");
    // The edge of the visible arc is a bin edge.
    Pair::light(name, (technique, vec![("LIGHT_TECHNIQUE", 1.0)]), (builtin, vec![]), 2.0 * arc, (64, 64), Vec::new())
}
