// emitters/cylinder.wgsl — an emissive cylinder (Mitsuba's cylinder with an area emitter): a
// diffuse area light emitting on the side of its normals (outwards; inwards with
// flip_normals), or on both (src/scene/emitters/cylinder.rs). light_entry(l).object names the
// quadric. It is sampled as Mitsuba samples it: a point uniform in its area, its density
// converted to solid angle at x (sample_cylinder_light, quadrics/cylinder.wgsl), or by a
// researcher's technique (technique.wgsl).

// Whether a cylinder whose unit normal is n where the ray meets it emits along ray_d.
fn cylinder_emits_along(q: Quadric, n: vec3f, ray_d: vec3f) -> bool {
    return (q.flags & TRIANGLE_TWO_SIDED) != 0u || dot(n, ray_d) < 0.0;
}

// Where the rays from ctx towards cylinder light l (quadric q) start: past the root at ctx.x
// where ctx is a point of that cylinder itself.
fn cylinder_emitter_t_min(l: u32, q: Quadric, ctx: LightSampleContext) -> f32 {
    return select(0.0, 1e-4 * sqrt(q.area), ctx.object == first_quadric_object() + light_entry(l).object);
}

// A direction from ctx towards cylinder light l.
fn sample_cylinder_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let q = quadric_of(light_entry(l).object);
    var s: CylinderLightSample;
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_CYLINDERS) {
        s = sample_cylinder_light_with_technique(q, ctx.x, ctx.n, u, cylinder_emitter_t_min(l, q, ctx));
    } else {
        s = sample_cylinder_light(q, ctx.x, u);
    }
    let emission = select(vec3f(0.0), material_record(q.material).emission, cylinder_emits_along(q, s.n, s.ls.wi));
    return EmitterSample(s.ls.wi, s.ls.dist, s.ls.pdf, emission, INVALID, false);
}

// Solid-angle density with which sample_cylinder_emitter gives wi from ctx (pdf_cylinder_light:
// at the first point the ray meets). From a point of the cylinder itself, the root at that
// point is skipped.
fn pdf_cylinder_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    let q = quadric_of(light_entry(l).object);
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_CYLINDERS) {
        return pdf_cylinder_light_with_technique(q, ctx.x, ctx.n, wi, cylinder_emitter_t_min(l, q, ctx));
    }
    return pdf_cylinder_light(q, ctx.x, wi, cylinder_emitter_t_min(l, q, ctx));
}

// Radiance a ray along ray_d receives from the cylinder it hit: the emission on its emitting
// side(s), else none.
fn eval_cylinder_emitter(hit: Hit, ray_d: vec3f) -> vec3f {
    let q = quadric_of(hit.object - first_quadric_object());
    return select(vec3f(0.0), material_record(hit.material).emission, cylinder_emits_along(q, hit.normal, ray_d));
}
