// light_table.wgsl — the scene's lights and how next event estimation picks among them.
//
// Light l is of kind light_table[l].kind (an EMITTER_KIND_*; each kind's lights are one range
// of the table, the kinds in the registry's order, emitter.wgsl), light_table[l].object naming
// its object where the kind needs one. NUM_LIGHTS and one NUM_<KIND>_LIGHTS per kind are
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
    // Its EMITTER_KIND_*.
    kind: u32,
}

@group(0) @binding(BINDING_LIGHTS) var<storage, read> light_table: array<LightEntry>;

// Probability that the pipeline's selection picks light l.
fn light_select_prob(l: u32) -> f32 {
    switch (LIGHT_SELECT) {
        case LIGHT_SELECT_UNIFORM: {
            return 1.0 / f32(max(NUM_LIGHTS, 1u));
        }
        case LIGHT_SELECT_POWER: {
            return light_table[l].power_prob;
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
    let entry = light_table[slot];
    let l = select(entry.alias_index, slot, scaled - f32(slot) < entry.threshold);
    return SelectedLight(l, light_table[l].power_prob);
}
