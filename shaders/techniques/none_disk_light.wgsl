// techniques/none_disk_light.wgsl — stands in for the disk functions of a `light` technique
// where none is loaded or the loaded one does not sample disk lights (LIGHT_TECHNIQUE_DISKS is
// then false, and these are never called).

fn sample_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, u: vec2f) -> vec3f {
    return light.center;
}

fn pdf_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, p: vec3f) -> f32 {
    return 0.0;
}
