// texture.wgsl — textures: BSDF parameters that vary over a surface, looked up at the hit's uv
// parametrisation or, for a grid volume, its world position p (src/scene/textures/; Mitsuba's
// src/textures/). A colour slot of a BSDF's
// parameter block holds its value, or, where its first number is negative, the reference
// -(start + 1) of a texture's record in bsdf_data (bsdf.wgsl); the slots a kind lets be textures
// are resolved by the generated `bsdf_apply_textures` before the BSDF is evaluated, which the
// kernel calls only where some material reads uvs (HAS_UVS, scene.wgsl): scenes without
// textures compile all of it out. Records: the kind (src/scene/textures.rs numbers them), then
// its parameters.
//
//   checkerboard (0): color0 (3), color1 (3), to_uv's scales of u and v (2): color0 where the
//   fractional parts of the scaled u and v are both above 1/2 or both not (Mitsuba's
//   checkerboard.cpp); (4) the same with to_uv any 2D affine map (6: its two rows).
//   bitmap (1): width, height, filter (0 nearest, 1 bilinear), wrap (0 repeat, 1 mirror,
//   2 clamp), storage (0 float RGB, 1 bytes), to_uv (6: two rows of a 2D affine map); then for
//   bytes a 256-entry decode table (sRGB or code/255) and one number per texel holding its
//   codes r + 256 g + 65536 b, for floats three numbers per texel; rows from the top
//   (src/scene/textures/bitmap.rs, whose `Bitmap::eval` is this lookup's host twin).
//   volume (2): nx, ny, nz, channels (1 or 3), filter (0 nearest, 1 trilinear), wrap, the
//   world-to-grid map (12: three rows of an affine map), then the cells, x fastest, `channels`
//   numbers each (src/scene/textures/volume.rs, `GridVolume::eval` its host twin): looked up at
//   the hit's world position p, not its uvs (Mitsuba's `volume` texture around a `gridvolume`).
//   rawconstant (3): the value (3): Mitsuba's rawconstant, the same everywhere.
//   mesh_attribute (5): the attribute's slot, scale, the number of slots: Mitsuba's
//   mesh_attribute, the named attribute of the triangle hit (src/scene/mesh/, `MeshAttribute`)
//   at its barycentrics, times the scale; its values are `mesh_attributes`, not bsdf_data.

// Where a texture is looked up (pbrt-v4's TextureEvalContext; Mitsuba passes its
// SurfaceInteraction): the uv parametrisation, the world position (a grid volume's), and the
// triangle hit, its index in the kernel's order (INVALID: no triangle) and barycentrics (of p1
// and p2), for a mesh attribute (`texture_context`, intersect.wgsl).
struct TextureEvalContext {
    uv: vec2f,
    p: vec3f,
    triangle: u32,
    bary: vec2f,
}

// A lookup at uv alone (an emitter's texture, a projector's image).
fn uv_context(uv: vec2f) -> TextureEvalContext {
    return TextureEvalContext(uv, vec3f(0.0), INVALID, vec2f(0.0));
}

// The mesh attributes that mesh_attribute textures read, at each triangle's three corners as RGB:
// triangle k's corner c of slot s at (k slots + s) 3 + c (`PackedTriangles::attributes`).
@group(0) @binding(BINDING_MESH_ATTRIBUTES) var<storage, read> mesh_attributes: array<vec4f>;

// The mesh attribute of the record at `at` at the context's triangle: its corners' values
// blended by the barycentrics (b0 = 1 - b1 - b2) in Mitsuba's order, fmadd(a0, b0, fmadd(a1, b1,
// a2 b2)) (Mesh::interpolate_attribute; a face attribute's three corners are equal), times the
// scale. No triangle (validation refuses the material on other shapes): 0.
fn eval_mesh_attribute_texture(at: u32, ctx: TextureEvalContext) -> vec3f {
    if (ctx.triangle == INVALID) {
        return vec3f(0.0);
    }
    let slots = u32(bsdf_data[at + 3u]);
    let base = (ctx.triangle * slots + u32(bsdf_data[at + 1u])) * 3u;
    let b0 = 1.0 - ctx.bary.x - ctx.bary.y;
    let v = mesh_attributes[base].xyz * b0 + (mesh_attributes[base + 1u].xyz * ctx.bary.x + mesh_attributes[base + 2u].xyz * ctx.bary.y);
    return v * bsdf_data[at + 2u];
}

// A checkerboard at uv mapped by to_uv (a scale, or where `affine` two rows of a 2D affine map).
fn eval_checkerboard_texture(at: u32, uv: vec2f, affine: bool) -> vec3f {
    var scaled = uv * vec2f(bsdf_data[at + 7u], bsdf_data[at + 8u]);
    if (affine) {
        scaled = vec2f(
            bsdf_data[at + 7u] * uv.x + bsdf_data[at + 8u] * uv.y + bsdf_data[at + 9u],
            bsdf_data[at + 10u] * uv.x + bsdf_data[at + 11u] * uv.y + bsdf_data[at + 12u],
        );
    }
    let above = (scaled - floor(scaled)) > vec2f(0.5);
    let first = 1u + select(3u, 0u, above.x == above.y);
    return vec3f(bsdf_data[at + first], bsdf_data[at + first + 1u], bsdf_data[at + first + 2u]);
}

// Texel index i of n folded into [0, n) by the wrap mode (Dr.Jit's: repeat tiles, mirror
// reflects every other tile, clamp extends the edge).
fn bitmap_wrap(i: i32, n: i32, mode: u32) -> i32 {
    if (mode == 2u) {
        return clamp(i, 0, n - 1);
    }
    let period = select(n, 2 * n, mode == 1u);
    let p = ((i % period) + period) % period;
    return select(p, period - 1 - p, p >= n);
}

// Texel (x, y) (wrapped) of the bitmap at `at`, as linear RGB.
fn bitmap_texel(at: u32, x: i32, y: i32) -> vec3f {
    let w = i32(bsdf_data[at + 1u]);
    let h = i32(bsdf_data[at + 2u]);
    let mode = u32(bsdf_data[at + 4u]);
    let index = u32(bitmap_wrap(y, h, mode) * w + bitmap_wrap(x, w, mode));
    if (bsdf_data[at + 5u] == 0.0) {
        let t = at + BITMAP_HEADER + 3u * index;
        return vec3f(bsdf_data[t], bsdf_data[t + 1u], bsdf_data[t + 2u]);
    }
    // Bytes: each code through the record's decode table.
    let table = at + BITMAP_HEADER;
    let codes = u32(bsdf_data[table + 256u + index]);
    return vec3f(bsdf_data[table + (codes & 255u)], bsdf_data[table + ((codes >> 8u) & 255u)], bsdf_data[table + (codes >> 16u)]);
}

// The bitmap at `at`'s uv after its to_uv.
fn bitmap_uv(at: u32, uv_in: vec2f) -> vec2f {
    return vec2f(bsdf_data[at + 6u] * uv_in.x + bsdf_data[at + 7u] * uv_in.y + bsdf_data[at + 8u],
                 bsdf_data[at + 9u] * uv_in.x + bsdf_data[at + 10u] * uv_in.y + bsdf_data[at + 11u]);
}

// The cell of a bilinear lookup at uv of an image of `size` texels: texel centres at integers
// after subtracting 1/2; the lower-left texel and the fractions towards the next ones.
struct BilinearCell {
    x0: i32,
    y0: i32,
    f: vec2f,
}

fn bilinear_cell(uv: vec2f, size: vec2f) -> BilinearCell {
    let p = uv * size - vec2f(0.5);
    let base = floor(p);
    return BilinearCell(i32(base.x), i32(base.y), p - base);
}

fn eval_bitmap_texture(at: u32, uv_in: vec2f) -> vec3f {
    // to_uv, then the image's pixel coordinates.
    let uv = bitmap_uv(at, uv_in);
    let size = vec2f(bsdf_data[at + 1u], bsdf_data[at + 2u]);
    if (bsdf_data[at + 3u] == 0.0) {
        let p = floor(uv * size);
        return bitmap_texel(at, i32(p.x), i32(p.y));
    }
    let c = bilinear_cell(uv, size);
    let f = c.f;
    let t00 = bitmap_texel(at, c.x0, c.y0);
    let t10 = bitmap_texel(at, c.x0 + 1, c.y0);
    let t01 = bitmap_texel(at, c.x0, c.y0 + 1);
    let t11 = bitmap_texel(at, c.x0 + 1, c.y0 + 1);
    let top = t00 + f.x * (t10 - t00);
    let bottom = t01 + f.x * (t11 - t01);
    return top + f.y * (bottom - top);
}

// The gradient in uv of the bitmap at `at` as Mitsuba's Bitmap::eval_1_grad gives it (host twin:
// Bitmap::eval_1_grad): zero for nearest filtering; for bilinear, the partials of the
// interpolant of the four texels' luminances in pixel coordinates,
//   df/dx = (1 - fy)(f10 - f00) + fy (f11 - f01),  df/dy = (1 - fx)(f01 - f00) + fx (f11 - f10),
// through to_uv by its transpose and times the resolution, (m00 df/dx + m10 df/dy) w and
// (m01 df/dx + m11 df/dy) h, in Mitsuba's order.
fn bitmap_gradient(at: u32, uv_in: vec2f) -> vec2f {
    if (bsdf_data[at + 3u] == 0.0) {
        return vec2f(0.0);
    }
    let size = vec2f(bsdf_data[at + 1u], bsdf_data[at + 2u]);
    let c = bilinear_cell(bitmap_uv(at, uv_in), size);
    let f = c.f;
    let f00 = texture_value_1(bitmap_texel(at, c.x0, c.y0));
    let f10 = texture_value_1(bitmap_texel(at, c.x0 + 1, c.y0));
    let f01 = texture_value_1(bitmap_texel(at, c.x0, c.y0 + 1));
    let f11 = texture_value_1(bitmap_texel(at, c.x0 + 1, c.y0 + 1));
    // to_uv's linear part, for the transpose.
    let m00 = bsdf_data[at + 6u];
    let m01 = bsdf_data[at + 7u];
    let m10 = bsdf_data[at + 9u];
    let m11 = bsdf_data[at + 10u];
    let dx = (1.0 - f.y) * (f10 - f00) + f.y * (f11 - f01);
    let dy = (1.0 - f.x) * (f01 - f00) + f.x * (f11 - f10);
    return vec2f((m00 * dx + m10 * dy) * size.x, (m01 * dx + m11 * dy) * size.y);
}

// The gradient in uv of the texture whose record starts at `at` (a bump map's heights: a bitmap,
// the only texture with Mitsuba's eval_1_grad; the host refuses the others).
fn texture_gradient(at: u32, uv: vec2f) -> vec2f {
    return bitmap_gradient(at, uv);
}

// Cell i (x fastest, already wrapped) of a grid's cells starting at `cells`, as RGB (one
// channel: grey).
fn volume_cell(cells: u32, i: i32, channels: u32) -> vec3f {
    let t = cells + u32(i) * channels;
    if (channels == 1u) {
        return vec3f(bsdf_data[t]);
    }
    return vec3f(bsdf_data[t], bsdf_data[t + 1u], bsdf_data[t + 2u]);
}

// A grid volume at world position p: p into the grid's unit cube, then Dr.Jit's texture lookup
// in 3D (cell centres at integers after subtracting 1/2; trilinear along x, then y, then z).
// The header is read once and each axis's two indices wrapped once: on lavapipe every lookup
// site runs whole wherever it is reached (masked), a load per lane each.
fn eval_volume_texture(at: u32, p: vec3f) -> vec3f {
    let m = at + 7u;
    let q = vec3f(bsdf_data[m] * p.x + bsdf_data[m + 1u] * p.y + bsdf_data[m + 2u] * p.z + bsdf_data[m + 3u],
                  bsdf_data[m + 4u] * p.x + bsdf_data[m + 5u] * p.y + bsdf_data[m + 6u] * p.z + bsdf_data[m + 7u],
                  bsdf_data[m + 8u] * p.x + bsdf_data[m + 9u] * p.y + bsdf_data[m + 10u] * p.z + bsdf_data[m + 11u]);
    let size = vec3f(bsdf_data[at + 1u], bsdf_data[at + 2u], bsdf_data[at + 3u]);
    let n = vec3i(size);
    let channels = u32(bsdf_data[at + 4u]);
    let mode = u32(bsdf_data[at + 6u]);
    let cells = at + VOLUME_HEADER;
    if (bsdf_data[at + 5u] == 0.0) {
        let c = floor(q * size);
        let x = bitmap_wrap(i32(c.x), n.x, mode);
        let y = bitmap_wrap(i32(c.y), n.y, mode);
        let z = bitmap_wrap(i32(c.z), n.z, mode);
        return volume_cell(cells, (z * n.y + y) * n.x + x, channels);
    }
    let pos = q * size - vec3f(0.5);
    let base = floor(pos);
    let f = pos - base;
    let b = vec3i(base);
    let x0 = bitmap_wrap(b.x, n.x, mode);
    let x1 = bitmap_wrap(b.x + 1, n.x, mode);
    let y0 = bitmap_wrap(b.y, n.y, mode);
    let y1 = bitmap_wrap(b.y + 1, n.y, mode);
    let z0 = bitmap_wrap(b.z, n.z, mode);
    let z1 = bitmap_wrap(b.z + 1, n.z, mode);
    // Rows (y, z) of the two planes, each row's first cell.
    let r00 = (z0 * n.y + y0) * n.x;
    let r10 = (z0 * n.y + y1) * n.x;
    let r01 = (z1 * n.y + y0) * n.x;
    let r11 = (z1 * n.y + y1) * n.x;
    let plane0 = mix_exact(mix_exact(volume_cell(cells, r00 + x0, channels), volume_cell(cells, r00 + x1, channels), f.x),
                           mix_exact(volume_cell(cells, r10 + x0, channels), volume_cell(cells, r10 + x1, channels), f.x), f.y);
    let plane1 = mix_exact(mix_exact(volume_cell(cells, r01 + x0, channels), volume_cell(cells, r01 + x1, channels), f.x),
                           mix_exact(volume_cell(cells, r11 + x0, channels), volume_cell(cells, r11 + x1, channels), f.x), f.y);
    return mix_exact(plane0, plane1, f.z);
}

// a + t (b - a), written out (the host twin's order; WGSL's mix may round otherwise).
fn mix_exact(a: vec3f, b: vec3f, t: f32) -> vec3f {
    return a + t * (b - a);
}

// The kinds of texture some material uses (bit k: kind k; SceneFeatures::texture_kinds): the
// others' lookups are compiled out (lavapipe runs both sides of every branch: a grid lookup
// compiled into every textured scene cost those a quarter of their speed).
override TEXTURE_KINDS: u32 = 63u;

fn uses_texture_kind(kind: f32) -> bool {
    return (TEXTURE_KINDS & (1u << u32(kind))) != 0u;
}

// The texture whose record starts at `at`, where the context says.
fn eval_texture(at: u32, ctx: TextureEvalContext) -> vec3f {
    let kind = bsdf_data[at];
    let uv = ctx.uv;
    if (uses_texture_kind(TEXTURE_BITMAP) && kind == TEXTURE_BITMAP) {
        return eval_bitmap_texture(at, uv);
    }
    if (uses_texture_kind(TEXTURE_VOLUME) && kind == TEXTURE_VOLUME) {
        return eval_volume_texture(at, ctx.p);
    }
    if (uses_texture_kind(TEXTURE_MESH_ATTRIBUTE) && kind == TEXTURE_MESH_ATTRIBUTE) {
        return eval_mesh_attribute_texture(at, ctx);
    }
    if (uses_texture_kind(TEXTURE_RAW_CONSTANT) && kind == TEXTURE_RAW_CONSTANT) {
        return vec3f(bsdf_data[at + 1u], bsdf_data[at + 2u], bsdf_data[at + 3u]);
    }
    if (uses_texture_kind(TEXTURE_CHECKERBOARD_AFFINE) && kind == TEXTURE_CHECKERBOARD_AFFINE) {
        return eval_checkerboard_texture(at, uv, true);
    }
    if (uses_texture_kind(TEXTURE_CHECKERBOARD)) {
        return eval_checkerboard_texture(at, uv, false);
    }
    return vec3f(0.0);
}

// A texture's value as Mitsuba's eval_1 reads it (a scalar parameter): its luminance. The host
// packs a checkerboard read so grey (`Texture::scalar`), whose luminance is itself. Host twin:
// `Texture::eval_1`.
fn texture_value_1(c: vec3f) -> f32 {
    return dot(LUMINANCE, c);
}

// A scalar slot's value where the context says (a roughness): itself, or, where negative, the
// value of the texture whose record it references, -(start + 1).
fn scalar_texture_slot(v: f32, ctx: TextureEvalContext) -> f32 {
    if (v >= 0.0) {
        return v;
    }
    return texture_value_1(eval_texture(u32(-v - 1.0), ctx));
}

// A colour slot's value where the context says: itself, or its texture's value.
fn texture_slot(slot: vec3f, ctx: TextureEvalContext) -> vec3f {
    if (slot.x >= 0.0) {
        return slot;
    }
    return eval_texture(u32(-slot.x - 1.0), ctx);
}
