// emitters/disk.wgsl — an emissive disk (Mitsuba's disk with an area emitter): a diffuse area
// light emitting on the side of its normal, or on both (src/scene/emitters/disk.rs).
// light_entry(l).object names the quadric (the light disks come first among them). It is
// sampled as Mitsuba samples it: a point uniform in its area, its density converted to solid
// angle at x (sample_disk_light, quadrics/disk.wgsl), or by a researcher's technique
// (technique.wgsl).

// Whether disk q emits along ray_d (a ray travelling towards its surface): on its normal's
// side, or on both.
fn disk_emits_along(q: Quadric, ray_d: vec3f) -> bool {
    return (q.flags & TRIANGLE_TWO_SIDED) != 0u || dot(q.normal, ray_d) < 0.0;
}

// A direction from ctx towards disk light l.
fn sample_disk_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let q = quadric_of(light_entry(l).object);
    var ls: LightSample;
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_DISKS) {
        ls = sample_disk_light_with_technique(q, ctx.x, ctx.n, u);
    } else {
        ls = sample_disk_light(q, ctx.x, u);
    }
    let emission = select(vec3f(0.0), material_record(q.material).emission, disk_emits_along(q, ls.wi));
    return EmitterSample(ls.wi, ls.dist, ls.pdf, emission, INVALID, false);
}

// Solid-angle density with which sample_disk_emitter gives wi from ctx.
fn pdf_disk_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    let q = quadric_of(light_entry(l).object);
    if (LIGHT_TECHNIQUE && LIGHT_TECHNIQUE_DISKS) {
        return pdf_disk_light_with_technique(q, ctx.x, ctx.n, wi);
    }
    return pdf_disk_light(q, ctx.x, wi);
}

// Radiance a ray along ray_d receives from the disk it hit: the emission on its emitting
// side(s), else none.
fn eval_disk_emitter(hit: Hit, ray_d: vec3f) -> vec3f {
    let q = quadric_of(hit.object - first_quadric_object());
    return select(vec3f(0.0), material_record(hit.material).emission, disk_emits_along(q, ray_d));
}
