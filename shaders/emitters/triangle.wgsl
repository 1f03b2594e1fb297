// emitters/triangle.wgsl — an emissive mesh triangle: a diffuse area light emitting on the side
// of its winding normal, or on both (src/scene/emitters/triangle.rs), one colour or a texture
// over its uv parametrisation (Material::emission_texture). light_entry(l).object
// names the triangle (its index in the BVH's leaf order); it is sampled by area or by solid
// angle (TRIANGLE_SAMPLING, lights.wgsl), or by a researcher's technique (technique.wgsl).

// A direction from ctx towards triangle light l. It emits towards x when x is on the front
// side of the sampled point (in its shading frame), or it is two-sided.
fn sample_triangle_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let i = light_entry(l).object;
    let tri = triangle_record(i);
    var ls: LightSample;
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_TRIANGLES) {
        // A researcher's technique (technique.wgsl).
        ls = sample_triangle_light_with_technique(TriangleLight(tri.p0, tri.p1, tri.p2), ctx.x, ctx.n, u);
    } else {
        ls = sample_triangle_light(tri.p0, tri.p1, tri.p2, ctx.x, u);
    }
    var n_s = cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    if (HAS_SHADING_NORMALS) {
        n_s = triangle_shading_normal(i, tri, normalize(n_s), triangle_barycentrics(tri, ctx.x + ls.wi * ls.dist));
    }
    var radiance = material_record(tri.material).emission;
    if (HAS_EMISSION_TEXTURES) {
        // The sampled point's barycentrics, and from them its uv parametrisation.
        let p = ctx.x + ls.wi * ls.dist;
        let bary = triangle_barycentrics(tri, p);
        radiance = triangle_emission(tri.material, TextureEvalContext(triangle_uv(i, tri, bary), p, i, bary));
    }
    let emission = select(vec3f(0.0), radiance, triangle_emits_along(tri, n_s, ls.wi));
    return EmitterSample(ls.wi, ls.dist, ls.pdf, emission, INVALID, false);
}

// Solid-angle density with which sample_triangle_emitter gives wi from ctx.
fn pdf_triangle_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    let tri = triangle_record(light_entry(l).object);
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_TRIANGLES) {
        return pdf_triangle_light_with_technique(TriangleLight(tri.p0, tri.p1, tri.p2), ctx.x, ctx.n, wi);
    }
    return pdf_triangle_light(tri.p0, tri.p1, tri.p2, ctx.x, wi);
}

// Radiance a ray along ray_d receives from the triangle it hit: the emission on its emitting
// side(s), else none.
fn eval_triangle_emitter(hit: Hit, ray_d: vec3f) -> vec3f {
    let tri = triangle_record(hit.object - first_triangle_object());
    var radiance = material_record(hit.material).emission;
    if (HAS_EMISSION_TEXTURES) {
        radiance = triangle_emission(hit.material, texture_context(hit, vec3f(0.0)));
    }
    return select(vec3f(0.0), radiance, triangle_emits_along(tri, hit.shading_normal, ray_d));
}

// Some material's emission is a texture (SceneFeatures::has_emission_textures).
override HAS_EMISSION_TEXTURES: bool = false;

// The radiance material m emits at the surface point the context names: its emission texture's
// value there (Mitsuba's area emitter evaluates its radiance texture at the surface
// interaction: a bitmap at its uv, a mesh attribute at the triangle's barycentrics), else its
// one colour. Triangles alone carry emission textures (validation refuses them elsewhere); no
// grid volumes (refused), so the context's point may be left out.
fn triangle_emission(m: u32, ctx: TextureEvalContext) -> vec3f {
    let t = material_record(m).emission_texture;
    if (HAS_EMISSION_TEXTURES && HAS_UVS && t != NO_EMISSION_TEXTURE) {
        return eval_texture(t, ctx);
    }
    return material_record(m).emission;
}
