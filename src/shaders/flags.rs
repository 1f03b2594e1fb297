//! Bit flags the host packs and the kernels test, defined once here and generated into the
//! WGSL (`generated`).

/// Material flag: emits.
pub const MATERIAL_EMISSIVE: u32 = 1;
/// Material flag: the BSDF is one-sided (black seen from behind).
pub const MATERIAL_ONE_SIDED: u32 = 2;

/// Material flag: the surface bounds a medium (`Material::is_medium_boundary`); its interior's
/// and exterior's indices are the flags' bits from `MEDIUM_INTERIOR_SHIFT` and
/// `MEDIUM_EXTERIOR_SHIFT` on, 8 each, `NO_MEDIUM` for none.
pub const MATERIAL_MEDIUM_BOUNDARY: u32 = 4;
pub const MEDIUM_INTERIOR_SHIFT: u32 = 16;
pub const MEDIUM_EXTERIOR_SHIFT: u32 = 24;
/// No medium (vacuum), in a material's flags and for the camera.
pub const NO_MEDIUM: u32 = 255;
/// Floats per medium record at the start of the BSDF data (`media::Medium::pack`).
pub const MEDIUM_RECORD_FLOATS: u32 = crate::scene::media::MEDIUM_RECORD_FLOATS as u32;

/// The flags of a material bounding the media `interior` and `exterior` (`None`: vacuum):
/// `MATERIAL_MEDIUM_BOUNDARY` and the indices, 0 where it bounds none.
pub fn medium_flags(interior: Option<usize>, exterior: Option<usize>) -> u32 {
    if interior.is_none() && exterior.is_none() {
        return 0;
    }
    let index = |m: Option<usize>| m.map_or(NO_MEDIUM, |i| i as u32);
    MATERIAL_MEDIUM_BOUNDARY | index(interior) << MEDIUM_INTERIOR_SHIFT | index(exterior) << MEDIUM_EXTERIOR_SHIFT
}

/// `Material.back` of a material without a back BSDF (Mitsuba's `twosided` with one BSDF).
pub const NO_BACK: u32 = u32::MAX;

/// `Material.blend` of a material without a blend (Mitsuba's `blendbsdf`).
pub const NO_BLEND: u32 = u32::MAX;

/// `Material.normal_map` of a material without a normal map.
pub const NO_NORMAL_MAP: u32 = u32::MAX;

/// `Material.bump_map` of a material without a bump map.
pub const NO_BUMP_MAP: u32 = u32::MAX;

/// `Material.emission_texture` of a material whose emission is one colour.
pub const NO_EMISSION_TEXTURE: u32 = u32::MAX;

/// `DeltaLight.texture` of a delta light that projects no texture.
pub const NO_LIGHT_TEXTURE: u32 = u32::MAX;

/// Triangle flag: emits on both sides.
pub const TRIANGLE_TWO_SIDED: u32 = 1;
/// Triangle flag: has vertex normals (`GpuTriangleNormals` at the same index).
pub const TRIANGLE_HAS_NORMALS: u32 = 2;

/// Triangle flag: has texture coordinates (`GpuTriangleUvs` at the same index).
pub const TRIANGLE_HAS_UVS: u32 = 4;

/// Technique fault: a researcher's technique returned a non-finite or negative number, or a
/// direction that is not a unit vector, or a point off its light (`shaders/technique.wgsl`).
pub const TECHNIQUE_FAULT_VALUE: u32 = 1;
/// Technique fault: a call ran its loops past `TECHNIQUE_MAX_ITERATIONS` and was stopped.
pub const TECHNIQUE_FAULT_LOOP: u32 = 2;

/// The WGSL declarations of every flag.
pub fn wgsl() -> String {
    [
        ("MATERIAL_EMISSIVE", MATERIAL_EMISSIVE),
        ("MATERIAL_ONE_SIDED", MATERIAL_ONE_SIDED),
        ("MATERIAL_MEDIUM_BOUNDARY", MATERIAL_MEDIUM_BOUNDARY),
        ("MEDIUM_INTERIOR_SHIFT", MEDIUM_INTERIOR_SHIFT),
        ("MEDIUM_EXTERIOR_SHIFT", MEDIUM_EXTERIOR_SHIFT),
        ("NO_MEDIUM", NO_MEDIUM),
        ("MEDIUM_RECORD_FLOATS", MEDIUM_RECORD_FLOATS),
        ("NO_BACK", NO_BACK),
        ("NO_BLEND", NO_BLEND),
        ("NO_NORMAL_MAP", NO_NORMAL_MAP),
        ("NO_BUMP_MAP", NO_BUMP_MAP),
        ("NO_EMISSION_TEXTURE", NO_EMISSION_TEXTURE),
        ("NO_LIGHT_TEXTURE", NO_LIGHT_TEXTURE),
        ("TRIANGLE_TWO_SIDED", TRIANGLE_TWO_SIDED),
        ("TRIANGLE_HAS_NORMALS", TRIANGLE_HAS_NORMALS),
        ("TRIANGLE_HAS_UVS", TRIANGLE_HAS_UVS),
        ("TECHNIQUE_FAULT_VALUE", TECHNIQUE_FAULT_VALUE),
        ("TECHNIQUE_FAULT_LOOP", TECHNIQUE_FAULT_LOOP),
    ]
    .iter()
    .map(|(name, value)| format!("const {name}: u32 = {value}u;\n"))
    .collect()
}
