// emitters/sphere.wgsl — an emissive sphere: a diffuse area light emitting outwards
// (src/scene/emitters/sphere.rs). The host orders the light spheres first, so sphere light l
// is kernel sphere l. From outside, directions are drawn uniformly in the cone the sphere
// subtends; from inside (reachable only where LIGHT_INTERIORS_REACHABLE), points uniformly on
// its area (lights.wgsl). A point on a light's outer surface sees none of that light.

// True when x is on the inner side of light sphere `s`: inside it, or on its surface reached
// from inside (the vertex lies on the sphere itself and `from_inside` says which side).
fn inside_light(s: u32, sphere: Sphere, ctx: LightSampleContext) -> bool {
    if (!LIGHT_INTERIORS_REACHABLE) {
        return false;
    }
    if (s == ctx.object) {
        return ctx.from_inside;
    }
    let d = ctx.x - sphere.center;
    return dot(d, d) < sphere.radius * sphere.radius;
}

// A direction from ctx towards sphere light l: cone sampling (or a researcher's technique) from
// outside, area sampling from inside.
fn sample_sphere_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let sphere = sphere_of(l);
    var ls: LightSample;
    if (inside_light(l, sphere, ctx)) {
        ls = sample_sphere_light_area(sphere.center, sphere.radius, ctx.x, u);
    } else if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_SPHERES) {
        // A researcher's technique (technique.wgsl); not from a point on the light's own outer
        // surface, which sees none of it (and where the technique's geometry degenerates).
        ls = LightSample(ctx.n, 0.0, 0.0);
        if (l != ctx.object) {
            ls = sample_sphere_light_technique(sphere.center, sphere.radius, ctx.x, ctx.n, u);
        }
    } else {
        ls = sample_sphere_light_cone(sphere.center, sphere.radius, ctx.x, u);
    }
    let on_outer_surface = l == ctx.object && !ctx.from_inside;
    let emission = select(material_record(sphere.material).emission, vec3f(0.0), on_outer_surface);
    return EmitterSample(ls.wi, ls.dist, ls.pdf, emission, l, false);
}

// Solid-angle density with which sample_sphere_emitter gives wi from ctx.
fn pdf_sphere_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    let sphere = sphere_of(l);
    let inside = inside_light(l, sphere, ctx);
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_SPHERES && !inside) {
        return select(pdf_sphere_light_technique(sphere.center, sphere.radius, ctx.x, ctx.n, wi), 0.0, l == ctx.object);
    }
    return pdf_sphere_light(sphere.center, sphere.radius, ctx.x, inside, wi);
}

// Radiance a ray receives from the sphere it hit: its material's emission, on both sides.
fn eval_sphere_emitter(hit: Hit) -> vec3f {
    return material_record(hit.material).emission;
}
