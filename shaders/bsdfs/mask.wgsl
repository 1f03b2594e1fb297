// mask.wgsl — Mitsuba's mask (src/bsdfs/mask.cpp; host: src/scene/bsdfs/mask.rs): an opacity
// around any material's BSDF. With probability `opacity` a ray meeting the surface scatters off
// the nested BSDF (f and pdf times the opacity: bsdf.wgsl's eval_pdf_bsdf); otherwise it passes
// straight through, a null interaction: a delta lobe of mass 1 - opacity in the direction -wo,
// weight 1. The integrator continues such a ray from the surface's other side, from either side
// of a one-sided material, as a vertex of the path (Mitsuba's depth counts it). Shadow rays do
// not see through masks (Mitsuba's ray_test): what reaches a point through one arrives along
// the null interactions, with MIS weight 1 (a delta).

// Some material is masked (SceneFeatures::has_masks): without, all of it compiles out.
override HAS_MASKS: bool = false;

// Whether the BSDF's sampling takes the null interaction: exactly when u_lobe is at least the
// opacity (the nested BSDF draws with u_lobe / opacity otherwise).
fn bsdf_passes_through(b: Bsdf, u_lobe: f32) -> bool {
    return HAS_MASKS && u_lobe >= b.opacity;
}

// The null interaction: on along -wo, weight (1 - opacity) / (1 - opacity) = 1, a delta whose
// probability 1 - opacity is the sample's pdf (Mitsuba's bs.pdf; MIS ignores it, being a delta).
fn sample_null_bsdf(b: Bsdf, wo: vec3f) -> BsdfSample {
    return BsdfSample(-wo, 1.0 - b.opacity, vec3f(1.0), true, 1.0);
}

// A texture's value as an opacity (Mitsuba's eval_1, texture.wgsl's texture_value_1), clipped
// to [0, 1]. Host twin: `Opacity::eval`.
fn mask_opacity_of_texel(c: vec3f) -> f32 {
    return clamp(texture_value_1(c), 0.0, 1.0);
}
