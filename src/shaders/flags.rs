//! Bit flags the host packs and the kernels test, defined once here and generated into the
//! WGSL (`generated`).

/// Material flag: emits.
pub const MATERIAL_EMISSIVE: u32 = 1;
/// Material flag: the BSDF is one-sided (black seen from behind).
pub const MATERIAL_ONE_SIDED: u32 = 2;

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
