// bump_map.wgsl — Mitsuba's bumpmap (src/bsdfs/bumpmap.cpp; host: src/scene/bsdfs/bump_map.rs):
// a height texture around a material's BSDF, which then scatters in the frame of the bumped
// surface. The frame's normal comes from the texture's gradient and the surface's partials
// (surface_partials, intersect.wgsl); from there on it is the normal map's perturbed frame
// (perturbed_frame, normal_map.wgsl), which bsdf.wgsl's eval_pdf_bsdf and sample_bsdf apply with
// the same side tests and shadowing term.

// Some material is bump-mapped (SceneFeatures::has_bump_maps): without, all of it compiles out.
override HAS_BUMP_MAPS: bool = false;

// The BSDF b perturbed by the bump map whose record starts at `at` (its scale, then its
// texture's record), at a point with uv parametrisation uv, partials dp_du and dp_dv
// (surface_partials), geometric normal n_g and shading normal n (both on the surface's front,
// Hit.normal and Hit.shading_normal), viewed along wo, with n_s the shading normal turned to
// the viewer (Mitsuba's BumpMap::frame):
//   g = scale grad h(uv), the bitmap's gradient in uv (texture_gradient);
//   dp/du' = dp/du + n (g.x - n . dp/du), dp/dv' = dp/dv + n (g.y - n . dp/dv): the partials'
//   components along n replaced by the heights';
//   n_b = normalize(dp/du' x dp/dv'), negated where against n_g;
// then n_b in the local shading frame, whose flip and frame are the normal map's. Where the
// bumped partials are parallel (a degenerate parametrisation with no gradient), the shading
// normal itself (Mitsuba would give NaN).
fn bump_mapped(b: Bsdf, at: u32, uv: vec2f, dp_du_s: vec3f, dp_dv_s: vec3f, n_g: vec3f, n: vec3f, n_s: vec3f, wo: vec3f) -> Bsdf {
    let g = bsdf_data[at] * texture_gradient(at + 1u, uv);
    let dp_du = dp_du_s + n * (g.x - dot(n, dp_du_s));
    let dp_dv = dp_dv_s + n * (g.y - dot(n, dp_dv_s));
    let c = cross(dp_du, dp_dv);
    let len2 = dot(c, c);
    var n_b = select(n, c * inverseSqrt(len2), len2 > 0.0);
    n_b = select(n_b, -n_b, dot(n_g, n_b) < 0.0);
    let f = bsdf_frame(b, n);
    return perturbed_frame(b, vec3f(dot(n_b, f.t), dot(n_b, f.b), dot(n_b, n)), f, n_s, wo);
}
