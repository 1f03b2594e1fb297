// technique.wgsl — the seam for a researcher's own sampling technique (`--technique
// KIND:FILE.wgsl`, README "Your own technique"): the contract a technique file implements, and
// the wrappers that call it where the built-in strategy of its kind would run. The technique's
// file follows this one in the module (or, where none is loaded, shaders/techniques/none_*.wgsl,
// never called: BSDF_TECHNIQUE, LIGHT_TECHNIQUE and ENV_TECHNIQUE are false).
//
// THE CONTRACT
//
// kind `bsdf` — for Phong materials, microfacet materials or both: a file defines the pair of
// functions of each it samples, and materials it does not sample keep the built-in strategies.
// Phong materials (pathlab's `phong`, the study's BRDF f = kd / pi + ks (n + 2) / (2 pi)
// cos^n(alpha)): a direction, in place of their own strategy, whatever the method's BSDF
// strategy is for other kinds of material:
//   fn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f
//   fn pdf_bsdf_technique(wo: vec3f, m: PhongMaterial, wi: vec3f) -> f32
// in the local shading frame: +z is the shading normal, wo (unit, towards the viewer) has
// wo.z > 0. sample_ returns a unit direction wi anywhere on the sphere (one below the surface,
// wi.z <= 0, is allowed: f is 0 there, and it counts as a sample that scatters nothing); pdf_
// returns the density with which sample_ draws wi, per unit solid angle over the whole sphere.
// Microfacet materials (roughconductor, roughdielectric, roughplastic, principled's specular
// lobe): a microfacet normal, in place of `--microfacet-sampling`, under the materials' own
// strategy (the reflection or refraction about it, the lobes' choice and MIS stay pathlab's):
//   fn sample_microfacet_technique(wo: vec3f, alpha: f32, distribution: u32, u: vec2f) -> vec3f
//   fn pdf_microfacet_technique(wo: vec3f, m: vec3f, alpha: f32, distribution: u32) -> f32
// in the same frame, wo.z > 0 (from inside a dielectric, the frame is turned to wo's side);
// alpha is the material's roughness (> 0) and distribution DISTRIBUTION_BECKMANN or
// DISTRIBUTION_GGX (eval_microfacet_d, smith_g1, sample_microfacet_ndf of microfacet.wgsl are
// the technique's to call; pdf_microfacet and sample_microfacet call the technique). sample_
// returns a unit normal m with m.z > 0; pdf_ the density with which it draws m, per unit solid
// angle of normals. A reflection-only material needs every normal whose mirror direction of wo
// is above the surface; a rough dielectric every normal wo sees (it refracts about them).
// These sample isotropic materials only (a scene with an anisotropic one is refused); for
// anisotropic roughness too, a file defines instead
//   fn sample_microfacet_uv_technique(wo: vec3f, alpha_uv: vec2f, distribution: u32, u: vec2f) -> vec3f
//   fn pdf_microfacet_uv_technique(wo: vec3f, m: vec3f, alpha_uv: vec2f, distribution: u32) -> f32
// alpha_uv = (alpha_u, alpha_v), the roughness along the frame's x (the surface's dp/du, made
// orthogonal to the normal) and y; (alpha, alpha) for an isotropic material. The `_uv` forms of
// microfacet.wgsl (eval_microfacet_d_uv, smith_g1_uv, sample_microfacet_ndf_uv) are the
// technique's to call. A file defines one of the two pairs, not both.
//
// kind `light` — sampling a point on a light, for spherical, triangle, disk or cylinder lights,
// any of them: a file defines the pair of functions of each shape it samples, and lights of a
// shape it does not define keep the built-in strategy (the host finds which it defines). Spherical lights,
// seen from outside, in place of the uniform cone (from inside a light, its area is still
// sampled uniformly):
//   fn sample_light_technique(x: vec3f, n: vec3f, light: SphereLight, u: vec2f) -> vec3f
//   fn pdf_light_technique(x: vec3f, n: vec3f, light: SphereLight, p: vec3f) -> f32
// triangle lights (every emissive triangle of a mesh, a rectangle, a cube), in place of
// `--triangle-sampling` (area or solid angle):
//   fn sample_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, u: vec2f) -> vec3f
//   fn pdf_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, p: vec3f) -> f32
// disk lights (Mitsuba's disk with an area emitter, an ellipse where its to_world stretches it),
// and cylinder lights (Mitsuba's cylinder, open at both ends), in place of sampling their area
// uniformly:
//   fn sample_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, u: vec2f) -> vec3f
//   fn pdf_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, p: vec3f) -> f32
//   fn sample_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, u: vec2f) -> vec3f
//   fn pdf_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, p: vec3f) -> f32
// in world space: x is the shading point, n its unit shading normal on the viewer's side (a
// technique may ignore it). sample_ returns a point p on the light's surface; pdf_ returns, for
// a point p of the light that x sees, the density per unit solid angle at x of the direction
// towards p with which sample_ produces it. A point sample_ returns on the far side of a
// sphere or a cylinder, hidden from x by the light itself, is no sample of that direction: it
// contributes nothing (drawing only what x sees wastes no samples). Which side of a triangle
// or a disk emits, and whether a cylinder emits outwards, inwards or both, is pathlab's
// business: a technique samples the whole shape, and pathlab is not asked about points seen
// from a triangle's or a disk's own plane (they receive nothing).
//
// kind `env` — sampling a direction towards the environment map where next event estimation
// samples the environment (`+env`), in place of the map's luminance distribution:
//   fn sample_env_technique(n: vec3f, u: vec2f) -> vec3f
//   fn pdf_env_technique(n: vec3f, wi: vec3f) -> f32
// in world space: n is the shading normal on the viewer's side; sample_ returns a unit
// direction, pdf_ its density per unit solid angle over the whole sphere. The map is the
// technique's to read: environment_map_radiance(d) (its radiance, scale included),
// sample_environment_map(u) (a direction in xyz, its density in w, by luminance times
// sin(theta)) and pdf_environment_map(d) (emitters/environment.wgsl). The density must be
// positive wherever the map is not black, on both sides of the surface (a surface that
// transmits takes light from below it).
//
// Every kind: u (and u_lobe) are the only random numbers, uniform in [0, 1): the same sample
// dimensions the built-in strategy uses at that vertex (the layout of integrator.wgsl does not
// change). A technique must be a pure function of its arguments: it may call pathlab's
// functions (the warps of warp.wgsl, frame_from_normal, INV_PI, ...) and declare functions,
// structs and constants of its own (named after the technique, not to collide with pathlab's),
// but no bindings, no `var<private>`/`var<workgroup>`, no `override`s and no entry points. Its
// loops are stopped after TECHNIQUE_MAX_ITERATIONS iterations per call (the host writes a guard
// into each); a stopped call, a non-finite or negative number, a direction that is not unit or
// a point off the light is a fault: that sample contributes 0, and faults are counted and
// reported.

// Whether a technique samples materials / lights / the environment map (set by the method's
// `+bsdf=NAME` / `+light=NAME` / `+env=NAME`; which materials and lights: the generated
// BSDF_TECHNIQUE_* and LIGHT_TECHNIQUE_* constants).
override BSDF_TECHNIQUE: bool = false;
override LIGHT_TECHNIQUE: bool = false;
override ENV_TECHNIQUE: bool = false;

// A Phong material as a technique sees it: diffuse kd, specular ks, exponent n, and the
// probability with which pathlab's own mixture samples the Phong lobe, lum(ks) / (lum(kd) +
// lum(ks)) (a technique may use it or not).
struct PhongMaterial {
    kd: vec3f,
    ks: vec3f,
    n: f32,
    specular_probability: f32,
}

// A spherical light: centre and radius.
struct SphereLight {
    center: vec3f,
    radius: f32,
}

// A triangle light: its vertices (its winding normal cross(p1 - p0, p2 - p0); which side emits is
// not the technique's concern).
struct TriangleLight {
    p0: vec3f,
    p1: vec3f,
    p2: vec3f,
}

// A disk light: the points center + a axis_u + b axis_v with a^2 + b^2 <= 1 (a circle of radius
// |axis_u| where the axes are orthogonal and equally long, an ellipse otherwise); its area is
// pi |cross(axis_u, axis_v)|, its plane's normal along cross(axis_u, axis_v).
struct DiskLight {
    center: vec3f,
    axis_u: vec3f,
    axis_v: vec3f,
}

// A cylinder light, open at both ends: the points base + cos(phi) axis_u + sin(phi) axis_v +
// z axis with phi in [0, 2 pi), z in [0, 1] (a circular cylinder of radius |axis_u| where
// axis_u, axis_v and axis are orthogonal and the first two equally long; elliptical or
// leaning where to_world makes it so). Its area element is |cross(dp/dphi, axis)| dphi dz.
struct CylinderLight {
    base: vec3f,
    axis_u: vec3f,
    axis_v: vec3f,
    axis: vec3f,
}

// Loop iterations of the current call, and the faults of the current sample (TECHNIQUE_FAULT_*).
var<private> technique_iterations: u32;
var<private> technique_faults: u32;

// The guard at the top of every loop body of a technique file: true (break) once the call has
// run TECHNIQUE_MAX_ITERATIONS iterations, which it records as a fault.
fn technique_loop_guard() -> bool {
    technique_iterations += 1u;
    let over = technique_iterations > TECHNIQUE_MAX_ITERATIONS;
    if (over) {
        technique_faults |= TECHNIQUE_FAULT_LOOP;
    }
    return over;
}

// Whether x is finite (by its bits: compilers may fold x != x away).
fn technique_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn technique_finite3(v: vec3f) -> bool {
    return technique_finite(v.x) && technique_finite(v.y) && technique_finite(v.z);
}

// A density from a technique: itself if finite and >= 0, else 0 and a fault.
fn technique_density(pdf: f32) -> f32 {
    if (!technique_finite(pdf) || pdf < 0.0) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return 0.0;
    }
    return pdf;
}

// ---- kind bsdf: the wrappers bsdf.wgsl calls for a Phong material ----

fn phong_material_of(m: Phong) -> PhongMaterial {
    return PhongMaterial(m.kd, m.ks, m.n, m.p_spec);
}

// Solid-angle density of the technique at wi (world space).
fn pdf_phong_technique(m: Phong, n_s: vec3f, wo: vec3f, wi: vec3f) -> f32 {
    let frame = frame_from_normal(n_s);
    technique_iterations = 0u;
    return technique_density(pdf_bsdf_technique(frame_to_local(frame, wo), phong_material_of(m), frame_to_local(frame, wi)));
}

// wi drawn by the technique, weighted by path_weight with the Phong BRDF and the technique's
// density there. A fault gives a sample that scatters nothing.
fn sample_phong_technique(m: Phong, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let frame = frame_from_normal(n_s);
    technique_iterations = 0u;
    let local = sample_bsdf_technique(frame_to_local(frame, wo), phong_material_of(m), u_dir, u_lobe);
    let len = length(local);
    if (!technique_finite3(local) || abs(len - 1.0) > 1e-3) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    let wi = frame_to_world(frame, local / len);
    let pdf = pdf_phong_technique(m, n_s, wo, wi);
    return BsdfSample(wi, pdf, path_weight(eval_phong(m, n_s, wo, wi), dot(wi, n_s), pdf), false, 1.0);
}

// ---- kind bsdf, microfacet normals: the wrappers microfacet.wgsl calls ----

// Density over normals of the technique at m, for the roughness alpha_uv (the one-alpha pair
// is given alpha_u: the host refuses it for anisotropic materials).
fn pdf_microfacet_with_technique(wo: vec3f, m: vec3f, alpha_uv: vec2f, distribution: u32) -> f32 {
    technique_iterations = 0u;
    if (BSDF_TECHNIQUE_MICROFACET_UV) {
        return technique_density(pdf_microfacet_uv_technique(wo, m, alpha_uv, distribution));
    }
    return technique_density(pdf_microfacet_technique(wo, m, alpha_uv.x, distribution));
}

// A normal drawn by the technique, with its density. A normal that is not unit or not above
// the surface is a fault (the sample then contributes 0).
fn sample_microfacet_with_technique(wo: vec3f, u: vec2f, alpha_uv: vec2f, distribution: u32) -> MicrofacetSample {
    technique_iterations = 0u;
    var m: vec3f;
    if (BSDF_TECHNIQUE_MICROFACET_UV) {
        m = sample_microfacet_uv_technique(wo, alpha_uv, distribution, u);
    } else {
        m = sample_microfacet_technique(wo, alpha_uv.x, distribution, u);
    }
    let len = length(m);
    if (!technique_finite3(m) || abs(len - 1.0) > 1e-3 || !(m.z > 0.0)) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return MicrofacetSample(vec3f(0.0, 0.0, 1.0), 0.0);
    }
    let unit = m / len;
    return MicrofacetSample(unit, pdf_microfacet_with_technique(wo, unit, alpha_uv, distribution));
}

// ---- kind light: the wrappers emitters/sphere.wgsl calls from outside a light ----

// Solid-angle density at x with which the technique gives direction wi: its density at the
// near point where the ray (x, wi) meets the sphere (0 for a ray that misses it).
fn pdf_sphere_light_technique(center: vec3f, radius: f32, x: vec3f, n: vec3f, wi: vec3f) -> f32 {
    // Near root of |x + t wi - center| = radius: -b - sqrt(b^2 - c).
    let f = x - center;
    let b = dot(f, wi);
    let c = dot(f, f) - radius * radius;
    let disc = b * b - c;
    let t = -b - safe_sqrt(disc);
    if (disc < 0.0 || t <= 0.0) {
        return 0.0;
    }
    technique_iterations = 0u;
    return technique_density(pdf_light_technique(x, n, SphereLight(center, radius), x + wi * t));
}

// A direction from x (outside the sphere) towards the point the technique draws, with the
// technique's density for it; a point on the far side, hidden by the sphere, gets density 0
// (no contribution), and a fault (a point off the sphere) too.
fn sample_sphere_light_technique(center: vec3f, radius: f32, x: vec3f, n: vec3f, u: vec2f) -> LightSample {
    technique_iterations = 0u;
    let p = sample_light_technique(x, n, SphereLight(center, radius), u);
    let to_p = p - x;
    let dist = length(to_p);
    if (!technique_finite3(p) || abs(length(p - center) - radius) > 1e-3 * radius || dist <= 0.0) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return LightSample(normalize(center - x), 0.0, 0.0);
    }
    let wi = to_p / dist;
    // The near side faces x: the outward normal at p points back towards x.
    let near = dot(p - center, x - p) > 0.0;
    let pdf = pdf_sphere_light_technique(center, radius, x, n, wi);
    return LightSample(wi, dist, select(0.0, pdf, near));
}

// ---- kind light, triangles: the wrappers emitters/triangle.wgsl calls ----

// Whether x lies in the triangle's plane (to 1e-5 of its size), where it sees none of it: the
// technique is not asked there (its solid-angle density would be infinite).
fn technique_in_plane(tri: TriangleLight, x: vec3f) -> bool {
    let c = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    return abs(dot(x - tri.p0, c)) <= 1e-5 * length(c) * sqrt(length(c));
}

// Solid-angle density at x with which the technique gives direction wi: its density at the
// point where the ray (x, wi) meets the triangle's plane (asked for directions that meet the
// triangle; 0 for one parallel to its plane or away from it).
fn pdf_triangle_light_with_technique(tri: TriangleLight, x: vec3f, n: vec3f, wi: vec3f) -> f32 {
    let normal = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    let t = distance_to_plane(tri.p0, normal, x, wi);
    if (t <= 0.0 || technique_in_plane(tri, x)) {
        return 0.0;
    }
    technique_iterations = 0u;
    return technique_density(pdf_triangle_light_technique(x, n, tri, x + wi * t));
}

// A direction from x towards the point the technique draws, with the technique's density at
// that point (the point itself: the direction's ray would find it again only to rounding). A
// point off the triangle, farther from its plane or beyond an edge than 1e-3 of its size
// (barycentrics outside [-1e-3, 1 + 1e-3]), is a fault.
fn sample_triangle_light_with_technique(tri: TriangleLight, x: vec3f, n: vec3f, u: vec2f) -> LightSample {
    let c = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    let normal = normalize(c);
    if (technique_in_plane(tri, x)) {
        return LightSample(normal, 0.0, 0.0);
    }
    technique_iterations = 0u;
    let p = sample_triangle_light_technique(x, n, tri, u);
    // Barycentrics of p1 and p2 (bvh.wgsl) and the distance from the plane.
    let b = plane_barycentrics(tri.p0, tri.p1, tri.p2, p);
    let size = sqrt(length(c));
    let on = abs(dot(p - tri.p0, normal)) <= 1e-3 * size && b.x >= -1e-3 && b.y >= -1e-3 && b.x + b.y <= 1.0 + 1e-3;
    let to_p = p - x;
    let dist = length(to_p);
    if (!technique_finite3(p) || !on || !(dist > 0.0)) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return LightSample(normal, 0.0, 0.0);
    }
    technique_iterations = 0u;
    let pdf = technique_density(pdf_triangle_light_technique(x, n, tri, p));
    return LightSample(to_p / dist, dist, pdf);
}

// ---- kind light, disks and cylinders: the wrappers emitters/disk.wgsl and cylinder.wgsl call ----

// A disk or cylinder light as a technique sees it: the world images of its object space's
// origin and axes (quadrics/quadric.wgsl's rows, read by columns).
fn disk_light_of(q: Quadric) -> DiskLight {
    return DiskLight(vec3f(q.world_x.w, q.world_y.w, q.world_z.w), quadric_vector_to_world(q, vec3f(1.0, 0.0, 0.0)), quadric_vector_to_world(q, vec3f(0.0, 1.0, 0.0)));
}

fn cylinder_light_of(q: Quadric) -> CylinderLight {
    let base = vec3f(q.world_x.w, q.world_y.w, q.world_z.w);
    return CylinderLight(base, quadric_vector_to_world(q, vec3f(1.0, 0.0, 0.0)), quadric_vector_to_world(q, vec3f(0.0, 1.0, 0.0)), quadric_vector_to_world(q, vec3f(0.0, 0.0, 1.0)));
}

// Whether x lies in disk q's plane (to 1e-5 of the unit disk, in its object space), where it
// sees none of it: the technique is not asked there.
fn technique_in_disk_plane(q: Quadric, x: vec3f) -> bool {
    return abs(quadric_point_to_object(q, x).z) <= 1e-5;
}

// Solid-angle density at x with which the technique gives direction wi: its density at the
// point where the ray (x, wi) meets the disk (0 where it misses it).
fn pdf_disk_light_with_technique(q: Quadric, x: vec3f, n: vec3f, wi: vec3f) -> f32 {
    let t = intersect_disk(q, x, wi, 0.0, INFINITY);
    if (!(t > 0.0) || technique_in_disk_plane(q, x)) {
        return 0.0;
    }
    technique_iterations = 0u;
    return technique_density(pdf_disk_light_technique(x, n, disk_light_of(q), x + wi * t));
}

// A direction from x towards the point the technique draws on disk q, with the technique's
// density at that point. A point off the disk (in its object space, farther than 1e-3 from the
// unit disk's plane or beyond its rim) is a fault.
fn sample_disk_light_with_technique(q: Quadric, x: vec3f, n: vec3f, u: vec2f) -> LightSample {
    if (technique_in_disk_plane(q, x)) {
        return LightSample(q.normal, 0.0, 0.0);
    }
    technique_iterations = 0u;
    let p = sample_disk_light_technique(x, n, disk_light_of(q), u);
    let l = quadric_point_to_object(q, p);
    let on = abs(l.z) <= 1e-3 && dot(l.xy, l.xy) <= (1.0 + 1e-3) * (1.0 + 1e-3);
    let to_p = p - x;
    let dist = length(to_p);
    if (!technique_finite3(p) || !on || !(dist > 0.0)) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return LightSample(q.normal, 0.0, 0.0);
    }
    technique_iterations = 0u;
    return LightSample(to_p / dist, dist, technique_density(pdf_disk_light_technique(x, n, disk_light_of(q), p)));
}

// Solid-angle density at x with which the technique gives direction wi: its density at the
// first point beyond t_min where the ray (x, wi) meets cylinder q, the point x sees (0 where it
// misses it). t_min > 0 skips the root at x where x lies on the cylinder itself.
fn pdf_cylinder_light_with_technique(q: Quadric, x: vec3f, n: vec3f, wi: vec3f, t_min: f32) -> f32 {
    let t = intersect_cylinder(q, x, wi, t_min, INFINITY);
    if (!(t > 0.0)) {
        return 0.0;
    }
    technique_iterations = 0u;
    return technique_density(pdf_cylinder_light_technique(x, n, cylinder_light_of(q), x + wi * t));
}

// A direction from x towards the point the technique draws on cylinder q, with the technique's
// density at that point, and the cylinder's normal there. A point off the cylinder (in its
// object space, farther than 1e-3 from the unit circle or beyond its ends) is a fault; a point
// the cylinder hides from x (the ray meets it first elsewhere) gets density 0: it contributes
// nothing.
fn sample_cylinder_light_with_technique(q: Quadric, x: vec3f, n: vec3f, u: vec2f, t_min: f32) -> CylinderLightSample {
    technique_iterations = 0u;
    let p = sample_cylinder_light_technique(x, n, cylinder_light_of(q), u);
    let l = quadric_point_to_object(q, p);
    let on = abs(length(l.xy) - 1.0) <= 1e-3 && l.z >= -1e-3 && l.z <= 1.0 + 1e-3;
    let to_p = p - x;
    let dist = length(to_p);
    if (!technique_finite3(p) || !on || !(dist > 0.0)) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return CylinderLightSample(LightSample(vec3f(0.0, 0.0, 1.0), 0.0, 0.0), vec3f(0.0, 0.0, 1.0));
    }
    let wi = to_p / dist;
    // The point x sees along wi: p itself, unless the ray meets the cylinder well before it.
    let t = intersect_cylinder(q, x, wi, t_min, INFINITY);
    let normal = cylinder_normal(q, p);
    if (!(t > 0.0 && t >= dist * (1.0 - 1e-3))) {
        return CylinderLightSample(LightSample(wi, dist, 0.0), normal);
    }
    technique_iterations = 0u;
    return CylinderLightSample(LightSample(wi, dist, technique_density(pdf_cylinder_light_technique(x, n, cylinder_light_of(q), p))), normal);
}

// ---- kind env: the wrappers emitters/environment.wgsl calls for a map ----

// Solid-angle density of the technique at wi, with shading normal n.
fn pdf_environment_technique(n: vec3f, wi: vec3f) -> f32 {
    technique_iterations = 0u;
    return technique_density(pdf_env_technique(n, wi));
}

// A direction (xyz) by the technique, with its density (w); a fault gives density 0.
fn sample_environment_technique(n: vec3f, u: vec2f) -> vec4f {
    technique_iterations = 0u;
    let d = sample_env_technique(n, u);
    let len = length(d);
    if (!technique_finite3(d) || abs(len - 1.0) > 1e-3) {
        technique_faults |= TECHNIQUE_FAULT_VALUE;
        return vec4f(n, 0.0);
    }
    let wi = d / len;
    return vec4f(wi, pdf_environment_technique(n, wi));
}
