//! The scene's identity: a SHA-256 of a documented canonical encoding of everything that
//! determines its image, so that checkpoints, split-render parts and the study's cache, which
//! travel between machines and pathlab versions, are matched to the scene they were made of.
//!
//! The encoding (version 1) is UTF-8 text, one `key=value` line per field, in this order:
//!
//! ```text
//! pathlab-scene-hash=1
//! camera.position=X,Y,Z        camera.look_at=…   camera.up=…   camera.fov_x=F (or camera.fov_y=F,
//!   or, for an orthographic camera, camera.orthographic_width=W)
//! render.width=W  render.height=H  render.max_depth=D  render.environment=R,G,B
//! materials=N, then per material i: material.i.diffuse=… .specular=… .glossiness=… .emission=…
//!   (.emission.texture=… where its emission is a texture)
//!   (then .two_sided=0 where one-sided, its kind's own lines, .opacity=… where masked, .back=INDEX, .blend=INDEX WEIGHT
//!   where its back has another BSDF)
//! spheres=N, then sphere.i.center=… .radius=… .material=INDEX
//! planes=N, then plane.i.point=… .normal=… .material=INDEX
//! ```
//!
//! and, only when the scene has triangle meshes (so that every scene without them keeps its
//! hash):
//!
//! ```text
//! meshes=N, then mesh.i.material=INDEX .two_sided=0|1 (its emission) .triangles=T .data=SHA256
//! ```
//!
//! and after a mesh's `.data`, where the mesh has texture coordinates and some material reads
//! uvs (a texture) or is anisotropic (its tangent from them), `mesh.i.uvs=SHA256`; then for each
//! attribute of it that a `mesh_attribute` texture reads, `mesh.i.attribute.NAME=SHA256` (its
//! channel count and values).
//!
//! `render.hide_emitters=true` after `render.environment` only where the scene hides emitters;
//! and, only where the camera has a thin lens (aperture_radius > 0),
//! `camera.thin_lens=APERTURE_RADIUS FOCUS_DISTANCE`; and, only where the scene has delta
//! lights, for each kind that has any:
//!
//! ```text
//! point_lights=N, then point_light.i.position=… .intensity=…
//! spot_lights=N, then spot_light.i.position=… .direction=… .intensity=… .cutoff_angle=… .beam_width=…
//!   (then .up=… .texture=… where it projects a texture)
//! directional_lights=N, then directional_light.i.direction=… .irradiance=…
//! projector_lights=N, then projector_light.i.position=… .direction=… .up=… .half_extents=TX,TY
//!   (tan of the half field of view at the image's aspect) .irradiance=… .scale=…
//! ```
//!
//! and, only where the scene has disks, cylinders, curves or signed distance grids:
//!
//! ```text
//! quadrics=N, then quadric.i.kind=disk|cylinder|curve segment|B-spline segment|sdf grid .to_world=12 reals (the
//!   affine map's columns) .flip_normals=0|1 .material=INDEX .two_sided=0|1 (its emission),
//!   then for a curve segment .curve=P0,R0,P1,R1,INDEX,COUNT, for a B-spline segment
//!   .bspline=P0,R0,P1,R1,P2,R2,P3,R3,INDEX,COUNT, for a grid
//!   .grid=NXxNYxNZ,VALUES,smooth|analytic (VALUES the hex SHA-256 of its f32 values)
//! ```
//!
//! where `data` is the hex SHA-256 of the world-space mesh as little-endian bytes: every
//! position (3 f64), then every normal (3 f64, none for face normals), then every triangle
//! (3 u32).
//!
//! Every real number is written as the 16 hex digits of its IEEE-754 binary64 bit pattern
//! (`f64::to_bits`), integers in decimal. Left out, because they do not change the image: the
//! file's path, comments and formatting, material names, the default sample count and the
//! `[display]` table. Object order is kept (light order fixes which sample dimensions each
//! light uses). The hash is the first 16 hex digits of the SHA-256 of that text.

use std::fmt::Write as _;

use glam::DVec3;

use super::bsdfs::BsdfPlugin;
use super::{Bsdf, BsdfKind, Fov, Phong, Projection, Scene};

/// Version of the encoding, recorded beside the hash in accumulator files.
pub const SCENE_HASH_ENCODING: u32 = 1;

pub(crate) fn real(x: f64) -> String {
    format!("{:016x}", x.to_bits())
}

pub(crate) fn vec3(v: DVec3) -> String {
    format!("{},{},{}", real(v.x), real(v.y), real(v.z))
}

/// The canonical text of `scene` (see the module documentation).
pub fn canonical_encoding(scene: &Scene) -> String {
    let mut t = String::new();
    let mut line = |key: &str, value: String| {
        let _ = writeln!(t, "{key}={value}");
    };
    line("pathlab-scene-hash", SCENE_HASH_ENCODING.to_string());
    let c = &scene.camera;
    line("camera.position", vec3(c.position));
    line("camera.look_at", vec3(c.look_at));
    line("camera.up", vec3(c.up));
    // The field of view at the render's size: what the image depends on (a scene written with
    // `fov_axis` hashes as its resolved angle).
    match c.projection {
        Projection::Perspective(fov) => match fov.resolve(scene.render.width, scene.render.height) {
            Fov::Y(deg) => line("camera.fov_y", real(deg)),
            fov => line("camera.fov_x", real(fov.degrees())),
        },
        Projection::Orthographic { width } => line("camera.orthographic_width", real(width)),
    }
    let r = &scene.render;
    line("render.width", r.width.to_string());
    line("render.height", r.height.to_string());
    line("render.max_depth", r.max_depth.to_string());
    // Only scenes with roulette add a line, so that scenes written before keep their hash.
    if let Some(rr) = r.rr_depth {
        line("render.rr_depth", rr.to_string());
    }
    line("render.environment", vec3(r.environment));
    // Only scenes that hide emitters add a line, so that scenes written before keep their hash.
    if r.hide_emitters {
        line("render.hide_emitters", "true".to_string());
    }
    // Only scenes with a map add a line, so that scenes written before keep their hash.
    if let Some(m) = &scene.environment_map {
        let rows = m.to_world.iter().map(|r| vec3(glam::DVec3::from(*r))).collect::<Vec<_>>().join(" ");
        line("environment_map", format!("{} {} {}", m.content_hash, real(m.scale), rows));
    }
    line("materials", scene.materials.len().to_string());
    for (i, m) in scene.materials.iter().enumerate() {
        // Phong's three lines come before the emission, and every other kind's own lines after
        // it, behind Phong's three at zero: the order of the scenes written before the BSDF
        // registry, whose hashes stay.
        let phong = match &m.bsdf {
            Bsdf::Phong(p) => p,
            _ => &Phong::BLACK,
        };
        phong.hash_lines(&mut |key, value| line(&format!("material.{i}.{key}"), value));
        line(&format!("material.{i}.emission"), vec3(m.emission));
        // Only materials with an emission texture add a line.
        if let Some(t) = &m.emission_texture {
            line(&format!("material.{i}.emission.texture"), t.hash_value(vec3));
        }
        // Only one-sided materials add a line, so that scenes written before keep their hash.
        if !m.two_sided {
            line(&format!("material.{i}.two_sided"), "0".to_string());
        }
        if m.bsdf.kind() != BsdfKind::Phong {
            m.bsdf.hash_lines(&mut |key, value| line(&format!("material.{i}.{key}"), value));
        }
        // Only masked materials add a line.
        if let Some(o) = &m.opacity {
            line(&format!("material.{i}.opacity"), o.hash_value());
        }
        // Only normal-mapped materials add a line.
        if let Some(n) = &m.normal_map {
            line(&format!("material.{i}.normal_map"), n.hash_value());
        }
        // Only bump-mapped materials add a line.
        if let Some(b) = &m.bump_map {
            line(&format!("material.{i}.bump_map"), b.hash_value());
        }
        // Only materials with a back BSDF add a line: the back material's index.
        if let Some(b) = m.back {
            line(&format!("material.{i}.back"), b.to_string());
        }
        // Only blended materials add a line: the other material's index and the weight.
        if let Some(b) = &m.blend {
            line(&format!("material.{i}.blend"), format!("{} {}", b.material, b.weight.hash_value()));
        }
        // Only medium boundaries add lines: the media's indices (-1: none).
        if m.is_medium_boundary() {
            let index = |m: Option<usize>| m.map_or("-1".to_string(), |i| i.to_string());
            line(&format!("material.{i}.media"), format!("{} {}", index(m.interior), index(m.exterior)));
        }
    }
    // Only scenes with media add lines, so that scenes written before keep their hash.
    if !scene.media.is_empty() {
        line("media", scene.media.len().to_string());
        for (i, m) in scene.media.iter().enumerate() {
            m.hash_lines(&mut |key, value| line(&format!("medium.{i}.{key}"), value));
        }
        line("camera.medium", scene.camera_medium.map_or("-1".to_string(), |i| i.to_string()));
    }
    line("spheres", scene.spheres.len().to_string());
    for (i, s) in scene.spheres.iter().enumerate() {
        line(&format!("sphere.{i}.center"), vec3(s.center));
        line(&format!("sphere.{i}.radius"), real(s.radius));
        line(&format!("sphere.{i}.material"), s.material.to_string());
        // Only where they differ from the world's: scenes from before spheres had axes keep
        // their hash.
        if s.axes != crate::scene::Sphere::WORLD_AXES {
            line(&format!("sphere.{i}.axes"), s.axes.map(vec3).join(" "));
        }
    }
    line("planes", scene.planes.len().to_string());
    for (i, p) in scene.planes.iter().enumerate() {
        line(&format!("plane.{i}.point"), vec3(p.point));
        line(&format!("plane.{i}.normal"), vec3(p.normal));
        line(&format!("plane.{i}.material"), p.material.to_string());
    }
    if !scene.meshes.is_empty() {
        let attribute_names = scene.mesh_attribute_names();
        // Texture coordinates change the image where a texture reads them or an anisotropic
        // BSDF takes its tangent from them; only then are they hashed (every other scene keeps
        // its hash). Before 2026-12-05 they never were: two scenes differing only in a mesh's
        // uvs (or its `flip_tex_coords`) hashed alike, so a checkpoint of one resumed the other.
        let uvs_matter = scene.materials.iter().any(|m| m.reads_uv() || m.bsdf.is_anisotropic());
        line("meshes", scene.meshes.len().to_string());
        for (i, m) in scene.meshes.iter().enumerate() {
            line(&format!("mesh.{i}.material"), m.material.to_string());
            line(&format!("mesh.{i}.two_sided"), (m.two_sided_emission as u8).to_string());
            line(&format!("mesh.{i}.triangles"), m.triangles.len().to_string());
            line(&format!("mesh.{i}.data"), mesh_digest(m));
            if uvs_matter && !m.uvs.is_empty() {
                line(&format!("mesh.{i}.uvs"), uvs_digest(&m.uvs));
            }
            // The attributes that textures read, only where some does (every other scene keeps
            // its hash).
            for name in &attribute_names {
                if let Some(a) = m.attribute(name) {
                    line(&format!("mesh.{i}.attribute.{name}"), attribute_digest(a));
                }
            }
        }
    }
    // Only a thin lens adds a line, so that scenes written before keep their hash.
    if scene.camera.aperture_radius > 0.0 {
        line("camera.thin_lens", format!("{} {}", real(scene.camera.aperture_radius), real(scene.camera.focus_distance)));
    }
    // Only kinds a scene has add lines, so that scenes written before keep their hash.
    if !scene.point_lights.is_empty() {
        line("point_lights", scene.point_lights.len().to_string());
        for (i, l) in scene.point_lights.iter().enumerate() {
            line(&format!("point_light.{i}.position"), vec3(l.position));
            line(&format!("point_light.{i}.intensity"), vec3(l.intensity));
        }
    }
    if !scene.spot_lights.is_empty() {
        line("spot_lights", scene.spot_lights.len().to_string());
        for (i, l) in scene.spot_lights.iter().enumerate() {
            line(&format!("spot_light.{i}.position"), vec3(l.position));
            line(&format!("spot_light.{i}.direction"), vec3(l.direction));
            line(&format!("spot_light.{i}.intensity"), vec3(l.intensity));
            line(&format!("spot_light.{i}.cutoff_angle"), real(l.cutoff_angle));
            line(&format!("spot_light.{i}.beam_width"), real(l.beam_width));
            // Only a textured spot adds lines, so that scenes written before keep their hash.
            if let Some(t) = &l.texture {
                line(&format!("spot_light.{i}.up"), vec3(t.up));
                line(&format!("spot_light.{i}.texture"), t.texture.hash_value(vec3));
            }
        }
    }
    if !scene.directional_lights.is_empty() {
        line("directional_lights", scene.directional_lights.len().to_string());
        for (i, l) in scene.directional_lights.iter().enumerate() {
            line(&format!("directional_light.{i}.direction"), vec3(l.direction));
            line(&format!("directional_light.{i}.irradiance"), vec3(l.irradiance));
        }
    }
    // Only a scene with projectors adds lines, so that scenes written before keep their hash.
    if !scene.projector_lights.is_empty() {
        line("projector_lights", scene.projector_lights.len().to_string());
        for (i, l) in scene.projector_lights.iter().enumerate() {
            line(&format!("projector_light.{i}.position"), vec3(l.position));
            line(&format!("projector_light.{i}.direction"), vec3(l.direction));
            line(&format!("projector_light.{i}.up"), vec3(l.up));
            let (tx, ty) = l.half_extents();
            line(&format!("projector_light.{i}.half_extents"), format!("{},{}", real(tx), real(ty)));
            line(&format!("projector_light.{i}.irradiance"), l.irradiance.hash_value(vec3));
            line(&format!("projector_light.{i}.scale"), real(l.scale));
        }
    }
    // Only a scene with quadrics adds lines, so that scenes written before keep their hash.
    if !scene.quadrics.is_empty() {
        line("quadrics", scene.quadrics.len().to_string());
        for (i, q) in scene.quadrics.iter().enumerate() {
            line(&format!("quadric.{i}.kind"), q.kind.name().to_string());
            line(&format!("quadric.{i}.to_world"), q.to_world.to_cols_array().map(real).join(","));
            line(&format!("quadric.{i}.flip_normals"), (q.flip_normals as u8).to_string());
            line(&format!("quadric.{i}.material"), q.material.to_string());
            line(&format!("quadric.{i}.two_sided"), (q.two_sided_emission as u8).to_string());
            if let Some(c) = q.curve() {
                line(&format!("quadric.{i}.curve"), format!("{},{},{},{},{},{}", vec3(c.p0), real(c.r0), vec3(c.p1), real(c.r1), c.index, c.count));
            }
            if let Some(s) = q.bspline() {
                let points: Vec<String> = (0..4).map(|k| format!("{},{}", vec3(s.p[k]), real(s.r[k]))).collect();
                line(&format!("quadric.{i}.bspline"), format!("{},{},{}", points.join(","), s.index, s.count));
            }
            if let Some(g) = q.grid() {
                line(&format!("quadric.{i}.grid"), format!("{}x{}x{},{},{}", g.res[0], g.res[1], g.res[2], g.content_hash, if g.smooth { "smooth" } else { "analytic" }));
            }
        }
    }
    t
}

/// Hex SHA-256 of a mesh's world-space data (see the module documentation).
/// The SHA-256 of a mesh's texture coordinates.
fn uvs_digest(uvs: &[[f64; 2]]) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    for uv in uvs {
        for x in uv {
            h.update(x.to_le_bytes());
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// The SHA-256 of an attribute's channel count and values.
fn attribute_digest(a: &crate::scene::mesh::MeshAttribute) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    h.update((a.channels as u32).to_le_bytes());
    for x in &a.values {
        h.update(x.to_le_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

fn mesh_digest(m: &crate::scene::Mesh) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    for v in m.positions.iter().chain(&m.normals) {
        for x in v.to_array() {
            h.update(x.to_le_bytes());
        }
    }
    for t in &m.triangles {
        for i in t {
            h.update(i.to_le_bytes());
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// The first 16 hex digits of the SHA-256 of `canonical_encoding(scene)`.
pub fn content_hash(scene: &Scene) -> String {
    use sha2::{Digest, Sha256};
    let digest = Sha256::digest(canonical_encoding(scene).as_bytes());
    digest.iter().take(8).map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study() -> Scene {
        Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml")).expect("study scene")
    }

    /// Pinned: a change of this value means checkpoints, parts and cached study runs made by
    /// earlier versions no longer match their scene. Change the encoding only with a new
    /// `SCENE_HASH_ENCODING`.
    #[test]
    fn the_study_scene_hash_is_pinned() {
        assert_eq!(study().content_hash(), "d8327514cbc0ff01");
    }

    #[test]
    fn names_and_formatting_do_not_count_values_do() {
        let base = study();
        let mut renamed = base.clone();
        renamed.materials[0].name = "another name".into();
        renamed.render.spp = Some(12345);
        renamed.path = "elsewhere.toml".into();
        assert_eq!(renamed.content_hash(), base.content_hash());
        let mut moved = base.clone();
        moved.spheres[0].center.x = f64::from_bits(moved.spheres[0].center.x.to_bits() + 1);
        assert_ne!(moved.content_hash(), base.content_hash());
        let mut deeper = base.clone();
        deeper.render.max_depth += 1;
        assert_ne!(deeper.content_hash(), base.content_hash());
        assert!(canonical_encoding(&base).starts_with("pathlab-scene-hash=1\ncamera.position="));
    }
}
