// light_table.wgsl — the scene's lights and how next event estimation picks among them.
//
// Each kind's lights (EMITTER_KIND_*) are one range of the table, the kinds in the registry's
// order (emitter.wgsl), so light l's kind is its range's; light_entry(l).object names its object
// where the kind needs one. NUM_LIGHTS and one NUM_<KIND>_LIGHTS per kind are
// generated after this file. LIGHT_SELECT (values generated from
// `method::LightSelect`):
//   all:     every light gets its own shadow ray at every vertex (selection probability 1);
//   uniform: one light per vertex, each with probability 1 / NUM_LIGHTS;
//   power:   one light per vertex with probability proportional to its emitted power, drawn
//            from Walker's alias table (as pbrt-v4's PowerLightSampler): slot i = floor(u N)
//            keeps light i if the rest of u is below threshold_i, else takes its alias.

override LIGHT_SELECT: u32 = LIGHT_SELECT_ALL;

struct LightEntry {
    // The kind's object: a triangle's index; unused by spheres (sphere light l is sphere l)
    // and the environment.
    object: u32,
    // Probability of this light under power selection.
    power_prob: f32,
    // Alias table slot of index l: the alias and the threshold below which l keeps it.
    alias_index: u32,
    threshold: f32,
}

// The table, one texel per light (`GpuLight`'s bytes): a light is read at an index that differs
// per lane (the selected one), which lavapipe serves from a texel table as one 16-byte load per
// lane, where a storage buffer read is a loop over the lanes with two branches per component.
@group(0) @binding(BINDING_LIGHTS) var light_texels: texture_storage_2d<rgba32uint, read>;

// Entry l of the light table.
fn light_entry(l: u32) -> LightEntry {
    let t = textureLoad(light_texels, texel_coords(l));
    return LightEntry(t.x, bitcast<f32>(t.y), t.z, bitcast<f32>(t.w));
}

// Probability that the pipeline's selection picks light l.
fn light_select_prob(l: u32) -> f32 {
    switch (LIGHT_SELECT) {
        case LIGHT_SELECT_UNIFORM: {
            return 1.0 / f32(max(NUM_LIGHTS, 1u));
        }
        case LIGHT_SELECT_POWER: {
            return light_entry(l).power_prob;
        }
        default: {
            return 1.0;
        }
    }
}

struct SelectedLight {
    index: u32,
    prob: f32,
}

// One light for u in [0, 1) (uniform or power selection).
fn select_light(u: f32) -> SelectedLight {
    let scaled = u * f32(NUM_LIGHTS);
    let slot = min(u32(scaled), max(NUM_LIGHTS, 1u) - 1u);
    if (LIGHT_SELECT == LIGHT_SELECT_UNIFORM) {
        return SelectedLight(slot, 1.0 / f32(max(NUM_LIGHTS, 1u)));
    }
    let entry = light_entry(slot);
    let l = select(entry.alias_index, slot, scaled - f32(slot) < entry.threshold);
    return SelectedLight(l, light_entry(l).power_prob);
}
