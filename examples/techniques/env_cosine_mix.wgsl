// env_cosine_mix.wgsl — an environment technique none of the built-ins is: a defensive
// one-sample mixture (Hesterberg 1995) of the cosine about the shading normal and the map's own
// luminance distribution, half the samples each:
//   p(wi) = 1/2 max(0, cos) / pi + 1/2 p_luminance(wi).
// pathlab's built-ins draw by the map's luminance times sin(theta), or uniformly. The cosine
// half wins where the map is smooth and the surface diffuse (it follows the integrand's cosine);
// the luminance half keeps a small bright sun from being found only by chance, and keeps the
// density positive wherever the map is not black, on both sides of the surface.
//
//   pathlab check-technique env:examples/techniques/env_cosine_mix.wgsl --scene tests/fixtures/envmap/envmap.xml

fn sample_env_technique(n: vec3f, u: vec2f) -> vec3f {
    if (u.x < 0.5) {
        return frame_to_world(frame_from_normal(n), square_to_cosine_hemisphere(vec2f(2.0 * u.x, u.y)));
    }
    return sample_environment_map(vec2f(2.0 * u.x - 1.0, u.y)).xyz;
}

fn pdf_env_technique(n: vec3f, wi: vec3f) -> f32 {
    return 0.5 * max(dot(wi, n), 0.0) / PI + 0.5 * pdf_environment_map(wi);
}
