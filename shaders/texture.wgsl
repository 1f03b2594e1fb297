// texture.wgsl — textures: BSDF parameters that vary over a surface, looked up at the hit's uv
// parametrisation (src/scene/textures.rs; Mitsuba's src/textures/). A colour slot of a BSDF's
// parameter block holds its value, or, where its first number is negative, the reference
// -(start + 1) of a texture's record in bsdf_data (bsdf.wgsl); the slots a kind lets be textures
// are resolved by the generated `bsdf_apply_textures` before the BSDF is evaluated, which the
// kernel calls only where some material reads uvs (HAS_UVS, scene.wgsl): scenes without
// textures compile all of it out. Records: the kind (src/scene/textures.rs numbers them), then
// its parameters.
//
//   checkerboard: color0 (3), color1 (3), to_uv scale (2): color0 where the fractional parts of
//   the scaled u and v are both above 1/2 or both not (Mitsuba's checkerboard.cpp).

fn eval_checkerboard_texture(at: u32, uv: vec2f) -> vec3f {
    let scaled = uv * vec2f(bsdf_data[at + 7u], bsdf_data[at + 8u]);
    let above = (scaled - floor(scaled)) > vec2f(0.5);
    let first = 1u + select(3u, 0u, above.x == above.y);
    return vec3f(bsdf_data[at + first], bsdf_data[at + first + 1u], bsdf_data[at + first + 2u]);
}

// The texture whose record starts at `at`, at uv.
fn eval_texture(at: u32, uv: vec2f) -> vec3f {
    return eval_checkerboard_texture(at, uv);
}

// A colour slot's value at uv: itself, or its texture's value.
fn texture_slot(slot: vec3f, uv: vec2f) -> vec3f {
    if (slot.x >= 0.0) {
        return slot;
    }
    return eval_texture(u32(-slot.x - 1.0), uv);
}
