//! From TOML text to a validated `Scene`: every error names the file, the line and the field,
//! and all errors of a file are reported together.

use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;
use std::path::Path;

use glam::{DAffine3, DVec3};
use toml::Spanned;

use crate::display::{DisplayTransform, Transfer};

use super::checker::Checker;
use super::diagnostic::SourceMap;
use super::media::{grid_bounds, Field, Medium, MediumKind, Phase, MAX_MEDIA};
use super::mesh::{self, shapes, Mesh, MeshData, Shading};
use super::emitters::{DirectionalLight, PointLight, ProjectorLight, SpotLight, SpotTexture, BEAM_WIDTH_OF_CUTOFF, DEFAULT_CUTOFF_ANGLE};
use super::textures::Texture;
use super::raw::{RawColor, RawColorOrTexture, RawEnvironmentMap, RawMaterial, RawRotations, RawScale, RawScene, RawTransform};
use super::quadrics::{self, Quadric, QuadricData, QuadricKind, MAX_QUADRICS};
use super::transform::Transform;
use super::{
    Camera, Diagnostic, Fov, Material, Projection, Opacity, Plane, RenderSettings, Scene, SceneError, Severity, Sphere, MAX_DELTA_LIGHTS,
    MAX_MATERIALS, MAX_PLANES, MAX_SPHERES,
};

/// The field-of-view keys given (`fov_x`, `fov_y`, `fov_smaller`, `fov_larger`,
/// `fov_diagonal`, in that order: a camera's or a projector's), each with its rule.
fn given_fovs(keys: [&Option<Spanned<f64>>; 5]) -> Vec<(&'static str, &Spanned<f64>, fn(f64) -> Fov)> {
    const RULES: [(&str, fn(f64) -> Fov); 5] = [("fov_x", Fov::X), ("fov_y", Fov::Y), ("fov_smaller", Fov::Smaller), ("fov_larger", Fov::Larger), ("fov_diagonal", Fov::Diagonal)];
    RULES.into_iter().zip(keys).filter_map(|((key, make), v)| v.as_ref().map(|v| (key, v, make))).collect()
}

/// A field of view in degrees, strictly between 0 and 180.
fn checked_fov(ck: &mut Checker, fov: &Spanned<f64>, field: &str) -> f64 {
    let v = ck.number(fov, field);
    if !(v > 0.0 && v < 180.0) && fov.get_ref().is_finite() {
        ck.error(fov.span(), field, format!("field of view must be strictly between 0 and 180 degrees (got {v})"));
    }
    v
}

/// A unit direction from `value`, refusing the zero vector.
fn unit_direction(ck: &mut Checker, value: &Spanned<[f64; 3]>, field: &str) -> DVec3 {
    let v = ck.vector(value, field);
    let length = v.length();
    if length > 0.0 && length.is_finite() {
        return v / length;
    }
    if v.is_finite() {
        ck.error(value.span(), field, "must be a non-zero direction");
    }
    DVec3::Z
}

/// `[[point_lights]]`, `[[spot_lights]]` and `[[directional_lights]]`: positions and directions
/// finite (directions non-zero), intensities finite and >= 0, a spot's angles in degrees with
/// 0 < beam_width <= cutoff_angle <= 180 (Mitsuba's defaults 20 and 3/4 of the cutoff), at most
/// `MAX_DELTA_LIGHTS` of them together.
fn check_delta_lights(ck: &mut Checker, raw: &RawScene) -> (Vec<PointLight>, Vec<SpotLight>, Vec<DirectionalLight>, Vec<ProjectorLight>) {
    let mut points = Vec::new();
    for (i, l) in raw.point_lights.iter().enumerate() {
        let l = l.get_ref();
        let position = ck.vector(&l.position, &format!("point_lights[{i}].position"));
        let intensity = ck.color(Some(&l.intensity), &format!("point_lights[{i}].intensity"));
        points.push(PointLight { position, intensity });
    }
    let mut spots = Vec::new();
    for (i, l) in raw.spot_lights.iter().enumerate() {
        let l = l.get_ref();
        let position = ck.vector(&l.position, &format!("spot_lights[{i}].position"));
        let direction = unit_direction(ck, &l.direction, &format!("spot_lights[{i}].direction"));
        let intensity = ck.color(Some(&l.intensity), &format!("spot_lights[{i}].intensity"));
        let angle = |ck: &mut Checker, v: &Option<Spanned<f64>>, name: &str, default: f64| match v {
            None => default,
            Some(v) => {
                let field = format!("spot_lights[{i}].{name}");
                let a = ck.number(v, &field);
                if !(a > 0.0 && a <= 180.0) && v.get_ref().is_finite() {
                    ck.error(v.span(), &field, format!("`{name}` must be an angle in (0, 180] degrees (got {a})"));
                }
                a
            }
        };
        let cutoff_angle = angle(ck, &l.cutoff_angle, "cutoff_angle", DEFAULT_CUTOFF_ANGLE);
        let beam_width = angle(ck, &l.beam_width, "beam_width", cutoff_angle * BEAM_WIDTH_OF_CUTOFF);
        if beam_width > cutoff_angle {
            let span = l.beam_width.as_ref().map_or(l.position.span(), Spanned::span);
            ck.error(span, &format!("spot_lights[{i}].beam_width"), format!("`beam_width` ({beam_width}) must not exceed `cutoff_angle` ({cutoff_angle})"));
        }
        let texture = match (&l.texture, &l.up) {
            (None, None) => None,
            (None, Some(up)) => {
                ck.warn(up.span(), &format!("spot_lights[{i}].up"), "`up` has no effect without a `texture`: the spot's falloff is the same about its axis");
                None
            }
            (Some(t), up) => {
                let field = format!("spot_lights[{i}].texture");
                let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
                let mut errors = Vec::new();
                let texture = match t.get_ref() {
                    toml::Value::Table(table) => Texture::from_toml(table, t.span(), &base, &mut errors),
                    v => {
                        errors.push((t.span(), format!("`texture` must be a texture table, e.g. {{ texture = \"bitmap\", filename = \"pattern.png\" }} (got {v})")));
                        None
                    }
                };
                for (span, message) in errors {
                    ck.error(span, &field, message);
                }
                let texture = refuse_light_mesh_attribute(ck, texture, t.span(), &field);
                let up = match up {
                    Some(up) => {
                        let u = unit_direction(ck, up, &format!("spot_lights[{i}].up"));
                        if u.cross(direction).length() < 1e-9 && u.length() > 0.0 {
                            ck.error(up.span(), &format!("spot_lights[{i}].up"), "`up` must not be parallel to the direction");
                        }
                        u
                    }
                    None => {
                        ck.error(t.span(), &format!("spot_lights[{i}].up"), "a spot light's `texture` needs `up`, the direction its v runs along (the light frame's y axis)");
                        DVec3::Y
                    }
                };
                // The frame's y axis, made orthogonal to the direction.
                let (_, y) = super::emitters::light_frame(direction, up);
                texture.map(|texture| SpotTexture { texture, up: y })
            }
        };
        spots.push(SpotLight { position, direction, intensity, cutoff_angle, beam_width, texture });
    }
    let mut directionals = Vec::new();
    for (i, l) in raw.directional_lights.iter().enumerate() {
        let l = l.get_ref();
        let direction = unit_direction(ck, &l.direction, &format!("directional_lights[{i}].direction"));
        let irradiance = ck.color(Some(&l.irradiance), &format!("directional_lights[{i}].irradiance"));
        directionals.push(DirectionalLight { direction, irradiance });
    }
    let mut projectors = Vec::new();
    for (i, l) in raw.projector_lights.iter().enumerate() {
        let whole = l.span();
        let l = l.get_ref();
        let field = |name: &str| format!("projector_lights[{i}].{name}");
        let position = ck.vector(&l.position, &field("position"));
        let direction = unit_direction(ck, &l.direction, &field("direction"));
        let up = unit_direction(ck, &l.up, &field("up"));
        if up.cross(direction).length() < 1e-9 && up.length() > 0.0 && direction.length() > 0.0 {
            ck.error(l.up.span(), &field("up"), "`up` must not be parallel to the direction");
        }
        let (_, up) = super::emitters::light_frame(direction, up);
        let given = given_fovs([&l.fov_x, &l.fov_y, &l.fov_smaller, &l.fov_larger, &l.fov_diagonal]);
        let fov = match given.as_slice() {
            [(key, v, make)] => make(checked_fov(ck, v, &field(key))),
            [] => {
                ck.error(whole.clone(), &format!("projector_lights[{i}]"), "missing field of view: give exactly one of fov_x, fov_y, fov_smaller, fov_larger, fov_diagonal");
                Fov::X(90.0)
            }
            [(first, ..), (second, v, _), ..] => {
                ck.error(v.span(), &field(second), format!("give exactly one field of view, not both {first} and {second}"));
                Fov::X(90.0)
            }
        };
        // The irradiance: a colour (a rawconstant texture, one value) or a texture table.
        let irradiance = match l.irradiance.get_ref() {
            toml::Value::Table(table) => {
                let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
                let mut errors = Vec::new();
                let t = Texture::from_toml(table, l.irradiance.span(), &base, &mut errors);
                for (span, message) in errors {
                    ck.error(span, &field("irradiance"), message);
                }
                refuse_light_mesh_attribute(ck, t, l.irradiance.span(), &field("irradiance")).unwrap_or(Texture::RawConstant { value: DVec3::ZERO })
            }
            _ => match toml::Value::try_into::<RawColor>(l.irradiance.get_ref().clone()) {
                Ok(c) => Texture::RawConstant { value: ck.color(Some(&Spanned::new(l.irradiance.span(), c)), &field("irradiance")) },
                Err(_) => {
                    ck.error(l.irradiance.span(), &field("irradiance"), "`irradiance` must be a colour >= 0 (a number or [r, g, b]) or a texture table");
                    Texture::RawConstant { value: DVec3::ZERO }
                }
            },
        };
        let scale = match &l.scale {
            None => 1.0,
            Some(v) => {
                let x = ck.number(v, &field("scale"));
                if x < 0.0 {
                    ck.error(v.span(), &field("scale"), format!("`scale` must be >= 0 (got {x})"));
                }
                x
            }
        };
        projectors.push(ProjectorLight { position, direction, up, fov, irradiance, scale });
    }
    let total = points.len() + spots.len() + directionals.len() + projectors.len();
    if total > MAX_DELTA_LIGHTS {
        let span = raw
            .point_lights
            .iter()
            .map(Spanned::span)
            .chain(raw.spot_lights.iter().map(Spanned::span))
            .chain(raw.directional_lights.iter().map(Spanned::span))
            .chain(raw.projector_lights.iter().map(Spanned::span))
            .nth(MAX_DELTA_LIGHTS)
            .unwrap_or(0..0);
        ck.error(span, "point_lights", format!("the scene has {total} point, spot, directional and projector lights, more than the {MAX_DELTA_LIGHTS} the kernel holds"));
    }
    (points, spots, directionals, projectors)
}

/// Largest accepted width, height or max_depth: beyond this the GPU buffers cannot be sized.
const MAX_IMAGE_SIDE: i64 = 65_536;
const MAX_DEPTH_LIMIT: i64 = 1024;

pub(super) fn parse_and_validate(text: &str, file: &Path) -> Result<Scene, SceneError> {
    let raw: RawScene = match toml::from_str(text) {
        Ok(raw) => raw,
        Err(e) => {
            let span = e.span().unwrap_or(0..0);
            let field = field_path_at(text, span.start);
            let d = SourceMap::single(file, text).diagnostic(Severity::Error, span.start, field, e.message().trim().to_string());
            return Err(SceneError::Invalid(vec![d]));
        }
    };
    validate(&raw, file, SourceMap::single(file, text), Vec::new())
}

/// Validates a raw scene (from TOML, or translated from Mitsuba XML) whose spans point into
/// `sources`; `diagnostics` are findings of the reader (reported with the validator's).
pub(super) fn validate(raw: &RawScene, file: &Path, sources: SourceMap, diagnostics: Vec<Diagnostic>) -> Result<Scene, SceneError> {
    let mut ck = Checker { file, sources, diagnostics };

    let camera = check_camera(&mut ck, raw);
    let render = check_render(&mut ck, raw);
    let (media, medium_names) = check_media(&mut ck, raw);
    let (mut materials, names) = check_materials(&mut ck, raw);
    let camera_medium = resolve_media(&mut ck, raw, &mut materials, &medium_names);
    let display = check_display(&mut ck, raw);

    let mut used = BTreeSet::new();
    let mut resolve = |ck: &mut Checker, name: &Spanned<String>, field: &str| -> usize {
        match names.get(name.get_ref()) {
            Some(&i) => {
                used.insert(i);
                i
            }
            None => {
                let known: Vec<&str> = names.keys().map(String::as_str).collect();
                ck.error(
                    name.span(),
                    field,
                    format!("unknown material \"{}\" (defined: {})", name.get_ref(), known.join(", ")),
                );
                0
            }
        }
    };

    let mut spheres = Vec::new();
    for (i, s) in raw.spheres.iter().enumerate() {
        let s = s.get_ref();
        let center = ck.vector(&s.center, &format!("spheres[{i}].center"));
        let field = format!("spheres[{i}].radius");
        let radius = ck.number(&s.radius, &field);
        if radius <= 0.0 && s.radius.get_ref().is_finite() {
            ck.error(s.radius.span(), &field, format!("radius must be > 0 (got {radius})"));
        }
        let material = resolve(&mut ck, &s.material, &format!("spheres[{i}].material"));
        refuse_mesh_only_material(&mut ck, &materials, material, &s.material, &format!("spheres[{i}].material"), "sphere");
        let axes = match &s.axes {
            None => Sphere::WORLD_AXES,
            Some(axes) => sphere_axes(&mut ck, axes, &format!("spheres[{i}].axes")),
        };
        spheres.push(Sphere { center, radius, material, axes });
    }

    let mut planes = Vec::new();
    for (i, p) in raw.planes.iter().enumerate() {
        let p = p.get_ref();
        let point = ck.vector(&p.point, &format!("planes[{i}].point"));
        let field = format!("planes[{i}].normal");
        let normal = ck.vector(&p.normal, &field);
        let length = normal.length();
        if length == 0.0 || !length.is_finite() {
            ck.error(p.normal.span(), &field, "normal must be a non-zero vector");
        }
        let field = format!("planes[{i}].material");
        let material = resolve(&mut ck, &p.material, &field);
        refuse_mesh_only_material(&mut ck, &materials, material, &p.material, &field, "plane");
        if materials.get(material).is_some_and(Material::is_emissive) {
            ck.error(
                p.material.span(),
                &field,
                format!(
                    "material \"{}\" emits light, but planes are infinite and cannot be sampled as lights; \
                     use a sphere for an emitter",
                    p.material.get_ref()
                ),
            );
        }
        planes.push(Plane { point, normal: if length > 0.0 { normal / length } else { DVec3::Z }, material });
    }

    let meshes = check_meshes(&mut ck, raw, &materials, &mut |ck, name, field| resolve(ck, name, field));
    let quadrics = check_quadrics(&mut ck, raw, &materials, &mut |ck, name, field| resolve(ck, name, field));

    // Capacities of the kernel's uniform buffers.
    if let Some(extra) = raw.spheres.get(MAX_SPHERES) {
        ck.error(extra.span(), format!("spheres[{MAX_SPHERES}]"), too_many(raw.spheres.len(), MAX_SPHERES, "spheres"));
    }
    if let Some(extra) = raw.planes.get(MAX_PLANES) {
        ck.error(extra.span(), format!("planes[{MAX_PLANES}]"), too_many(raw.planes.len(), MAX_PLANES, "planes"));
    }
    if let Some((name, extra)) = raw.materials.iter().nth(MAX_MATERIALS) {
        ck.error(extra.span(), format!("materials.{name}"), too_many(raw.materials.len(), MAX_MATERIALS, "materials"));
    }

    // A material used on the back of a used one, or blended into one, is used.
    let backs: Vec<usize> = materials
        .iter()
        .enumerate()
        .filter(|(i, _)| used.contains(i))
        .flat_map(|(_, m)| m.back.into_iter().chain(m.blend.as_ref().map(|b| b.material)))
        .collect();
    for (name, &i) in &names {
        if !used.contains(&i) && !backs.contains(&i) {
            ck.warn(raw.materials[name].span(), format!("materials.{name}"), "material is defined but never used");
        }
    }
    let environment_map = raw.environment_map.as_ref().and_then(|e| check_environment_map(&mut ck, e));
    let techniques = raw.techniques.as_ref().map(|t| check_techniques(&mut ck, t.get_ref())).unwrap_or_default();
    if environment_map.is_some() && render.environment.max_element() > 0.0 {
        ck.error(raw.render.span(), "render.environment", "give either a constant environment or an environment map, not both (Mitsuba has one infinite emitter)");
    }
    let (point_lights, spot_lights, directional_lights, projector_lights) = check_delta_lights(&mut ck, raw);
    let any_emitter = spheres.iter().map(|s| s.material).chain(meshes.iter().map(|m| m.material)).chain(quadrics.iter().map(|q| q.material))
        .any(|m| materials.get(m).is_some_and(Material::is_emissive))
        || point_lights.iter().any(|l| l.intensity.max_element() > 0.0)
        || spot_lights.iter().any(|l| l.intensity.max_element() > 0.0)
        || directional_lights.iter().any(|l| l.irradiance.max_element() > 0.0)
        || projector_lights.iter().any(|l| l.scale > 0.0 && l.irradiance.mean().max_element() > 0.0);
    if !any_emitter && render.environment.max_element() <= 0.0 && environment_map.is_none() {
        ck.warn(raw.render.span(), "render.environment", "the scene has no emitter and a black environment: the image will be black");
    }

    if ck.diagnostics.iter().any(|d| d.severity == Severity::Error) {
        let mut diagnostics = ck.diagnostics;
        diagnostics.sort_by_key(|d| (d.severity != Severity::Error, d.line, d.column));
        return Err(SceneError::Invalid(diagnostics));
    }
    Ok(Scene {
        path: file.to_path_buf(),
        camera,
        render,
        materials,
        spheres,
        planes,
        meshes,
        quadrics,
        environment_map,
        point_lights,
        spot_lights,
        directional_lights,
        projector_lights,
        display,
        warnings: ck.diagnostics,
        techniques,
        translation: Default::default(),
        media,
        camera_medium,
    })
}

/// `[media.<name>]`: each medium's coefficients checked (σ_t finite and >= 0, albedo in
/// [0, 1], a known phase function, HG's g in (-1, 1)), in name order.
fn check_media(ck: &mut Checker, raw: &RawScene) -> (Vec<Medium>, BTreeMap<String, usize>) {
    let mut media = Vec::new();
    let mut names = BTreeMap::new();
    if let Some((name, extra)) = raw.media.iter().nth(MAX_MEDIA) {
        ck.error(extra.span(), format!("media.{name}"), too_many(raw.media.len(), MAX_MEDIA, "media"));
    }
    for (name, m) in &raw.media {
        let r = m.get_ref();
        let heterogeneous = match r.kind.as_ref().map(|k| (k.get_ref().as_str(), k.span())) {
            None | Some(("homogeneous", _)) => false,
            Some(("heterogeneous", _)) => true,
            Some((other, span)) => {
                ck.error(span, format!("media.{name}.type"), format!("unknown medium type \"{other}\" (pathlab has homogeneous, heterogeneous)"));
                false
            }
        };
        let sigma_t_field = format!("media.{name}.sigma_t");
        let sigma_t = check_medium_field(ck, &r.sigma_t, &sigma_t_field);
        if let (false, Field::Grid(_)) = (heterogeneous, &sigma_t) {
            ck.error(r.sigma_t.span(), &sigma_t_field, "a homogeneous medium's sigma_t is one value everywhere: give type = \"heterogeneous\" for a grid");
        }
        let scale = r.scale.as_ref().map_or(1.0, |s| {
            let v = ck.number(s, &format!("media.{name}.scale"));
            if v < 0.0 {
                ck.error(s.span(), format!("media.{name}.scale"), format!("`scale` must be >= 0 (got {v})"));
            }
            v
        });
        let albedo_field = format!("media.{name}.albedo");
        // Mitsuba's default albedo (homogeneous.cpp, heterogeneous.cpp: volume("albedo", 0.75f)).
        let albedo = r.albedo.as_ref().map_or(Field::Constant(DVec3::splat(0.75)), |a| check_medium_field(ck, a, &albedo_field));
        let albedo_max = match &albedo {
            Field::Constant(c) => c.max_element(),
            grid => grid.max(),
        };
        if albedo_max > 1.0 {
            let span = r.albedo.as_ref().map_or(m.span(), |a| a.span());
            ck.error(span, albedo_field, format!("an albedo is a fraction of the extinction that scatters: each channel must be in [0, 1] (its largest value is {albedo_max})"));
        }
        let kind = match (heterogeneous, &sigma_t, r.bounds.as_ref()) {
            (false, _, None) => MediumKind::Homogeneous,
            (false, _, Some(b)) => {
                ck.error(b.span(), format!("media.{name}.bounds"), "`bounds` is the box a heterogeneous medium's constant sigma_t fills: a homogeneous medium fills all space");
                MediumKind::Homogeneous
            }
            (true, Field::Grid(g), None) => MediumKind::Heterogeneous { bounds: grid_bounds(g) },
            (true, Field::Grid(_), Some(b)) => {
                ck.error(b.span(), format!("media.{name}.bounds"), "a grid's box is its to_world's unit cube: give `bounds` only with a constant sigma_t");
                MediumKind::Homogeneous
            }
            (true, Field::Constant(_), b) => {
                // Mitsuba's constvolume fills its to_world's unit cube, by default [0, 1]^3.
                let [lo, hi] = b.map_or([[0.0; 3], [1.0; 3]], |b| *b.get_ref());
                let (lo, hi) = (DVec3::from_array(lo), DVec3::from_array(hi));
                if let Some(b) = b.filter(|_| !(lo.is_finite() && hi.is_finite() && lo.cmplt(hi).all())) {
                    ck.error(b.span(), format!("media.{name}.bounds"), format!("`bounds` must be [[min], [max]] with min < max, finite (got {lo} and {hi})"));
                }
                MediumKind::Heterogeneous { bounds: [lo, hi] }
            }
        };
        let g = r.g.as_ref().map(|g| (ck.number(g, &format!("media.{name}.g")), g.span()));
        let phase = match r.phase.as_ref().map(|p| (p.get_ref().as_str(), p.span())) {
            None | Some(("isotropic", _)) => {
                if let Some((_, span)) = g {
                    ck.error(span, format!("media.{name}.g"), "`g` is the mean cosine of the `hg` phase function: give phase = \"hg\" with it");
                }
                Phase::Isotropic
            }
            Some(("hg", _)) => {
                let g = g.map_or(0.8, |(g, span)| {
                    if !(g > -1.0 && g < 1.0) {
                        ck.error(span, format!("media.{name}.g"), format!("`g` must lie in (-1, 1) (got {g})"));
                    }
                    g
                });
                Phase::HenyeyGreenstein { g }
            }
            Some((other, span)) => {
                ck.error(span, format!("media.{name}.phase"), format!("unknown phase function \"{other}\" (pathlab has isotropic, hg)"));
                Phase::Isotropic
            }
        };
        names.insert(name.clone(), media.len());
        media.push(Medium { name: name.clone(), kind, sigma_t, scale, albedo, phase });
    }
    (media, names)
}

/// A medium's `sigma_t` or `albedo`: a colour (each channel >= 0), or a volume texture table
/// (a grid, looked up in space); any other texture is refused.
fn check_medium_field(ck: &mut Checker, value: &Spanned<RawColorOrTexture>, field: &str) -> Field {
    match value.get_ref() {
        RawColorOrTexture::Color(c) => Field::Constant(ck.color(Some(&Spanned::new(value.span(), *c)), field)),
        RawColorOrTexture::Texture(table) => {
            let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
            let mut errors = Vec::new();
            let texture = Texture::from_toml(table, value.span(), &base, &mut errors);
            for (span, message) in errors {
                ck.error(span, field, message);
            }
            match texture {
                Some(Texture::Volume(g)) => Field::Grid(g),
                Some(t) => {
                    ck.error(value.span(), field, format!("a medium's coefficient is looked up in space: give a volume texture, not a {}", t.name()));
                    Field::Constant(DVec3::ZERO)
                }
                None => Field::Constant(DVec3::ZERO),
            }
        }
    }
}

/// Resolves the media that materials bound (`interior`, `exterior`) and the camera's, by name;
/// warns of media nothing uses.
fn resolve_media(ck: &mut Checker, raw: &RawScene, materials: &mut [Material], names: &BTreeMap<String, usize>) -> Option<usize> {
    let mut used = BTreeSet::new();
    let mut lookup = |ck: &mut Checker, name: &Spanned<String>, field: String| -> Option<usize> {
        match names.get(name.get_ref()) {
            Some(&i) => {
                used.insert(i);
                Some(i)
            }
            None => {
                let known: Vec<&str> = names.keys().map(String::as_str).collect();
                let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
                ck.error(name.span(), field, format!("no medium \"{}\" (media: {known})", name.get_ref()));
                None
            }
        }
    };
    for (i, (name, m)) in raw.materials.iter().enumerate() {
        let r = m.get_ref();
        let interior = r.interior.as_ref().and_then(|n| lookup(ck, n, format!("materials.{name}.interior")));
        let exterior = r.exterior.as_ref().and_then(|n| lookup(ck, n, format!("materials.{name}.exterior")));
        if let Some(material) = materials.get_mut(i) {
            material.interior = interior;
            material.exterior = exterior;
        }
    }
    let camera = raw.camera.get_ref().medium.as_ref().and_then(|n| lookup(ck, n, "camera.medium".to_string()));
    for (name, m) in &raw.media {
        if !used.contains(&names[name]) {
            ck.warn(m.span(), format!("media.{name}"), "medium is defined but no material bounds it and the camera is not in it");
        }
    }
    camera
}

/// `[techniques]`: each file read (relative to the scene's folder), named by a valid stem, valid
/// WGSL is checked later (`shaders::validate_technique`, which needs the kernels); two of one
/// name are refused.
fn check_techniques(ck: &mut Checker, raw: &super::raw::RawTechniques) -> Vec<super::Technique> {
    let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut out: Vec<super::Technique> = Vec::new();
    for (kind, files) in [(crate::method::TechniqueKind::Bsdf, &raw.bsdf), (crate::method::TechniqueKind::Light, &raw.light)] {
        let field = format!("techniques.{kind}");
        for f in files {
            match super::Technique::load(kind, base.join(f.get_ref())) {
                Ok(t) if out.iter().any(|o| o.name == t.name) => {
                    ck.error(f.span(), &field, format!("two techniques are named `{}`: a method names a technique by its file's stem", t.name))
                }
                Ok(t) => out.push(t),
                Err(e) => ck.error(f.span(), &field, e.to_string()),
            }
        }
    }
    out
}

/// `[environment_map]`: its image read (relative to the scene's folder), its scale finite and
/// non-negative, its transform a rotation.
fn check_environment_map(ck: &mut Checker, e: &Spanned<RawEnvironmentMap>) -> Option<super::EnvironmentMap> {
    let raw = e.get_ref();
    let scale = match &raw.scale {
        Some(s) => {
            let v = ck.number(s, "environment_map.scale");
            if v < 0.0 {
                ck.error(s.span(), "environment_map.scale", format!("scale must be >= 0 (got {v})"));
            }
            v
        }
        None => 1.0,
    };
    let transform = check_transform(ck, raw.transform.as_ref(), "environment_map.transform");
    let m = glam::DMat3::from_mat4(transform.matrix);
    // Orthonormal to 1e-4 (matrices printed to 6 digits); a translation moves no direction at
    // infinity and is without effect, as in Mitsuba.
    let orthonormal = (m.transpose() * m - glam::DMat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() <= 1e-4);
    if !orthonormal {
        let span = raw.transform.as_ref().map_or(e.span(), |t| t.span());
        ck.error(span, "environment_map.transform", "an environment map's transform must be a rotation (directions at infinity are not scaled or sheared)");
    }
    let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
    let file = base.join(raw.filename.get_ref());
    if !file.exists() {
        ck.error(raw.filename.span(), "environment_map.filename", format!("image file \"{}\" not found (searched {}/)", raw.filename.get_ref(), base.display()));
        return None;
    }
    let image = match super::image_file::read_image(&file, false) {
        Ok(image) => image,
        Err(message) => {
            ck.error(raw.filename.span(), "environment_map.filename", format!("image file {}: {message}", file.display()));
            return None;
        }
    };
    if let super::image_file::Texels::Float(t) = &image.texels
        && let Some(i) = t.iter().position(|p| p.iter().any(|c| *c < 0.0))
    {
        ck.error(raw.filename.span(), "environment_map.filename", format!("image file {}: pixel ({}, {}) is negative: {:?}", file.display(), i as u32 % image.width, i as u32 / image.width, t[i]));
        return None;
    }
    // Orthonormalised (Gram-Schmidt on the columns, keeping a mirror a mirror), the rows of R.
    let x = m.x_axis.normalize();
    let y = (m.y_axis - x * x.dot(m.y_axis)).normalize();
    let z = (m.z_axis - x * x.dot(m.z_axis) - y * y.dot(m.z_axis)).normalize();
    let r = glam::DMat3::from_cols(x, y, z);
    let rows = [r.row(0).to_array(), r.row(1).to_array(), r.row(2).to_array()];
    Some(super::EnvironmentMap { file, content_hash: image.content_hash(), image: std::sync::Arc::new(image), scale, to_world: rows })
}

/// A transform table: a `matrix` alone, or translate/rotate/scale (see `scene::transform`).
/// A sphere's object axes: three rows, each a unit vector and orthogonal to the others to
/// within 1e-4 (six printed digits), made exactly orthonormal by Gram-Schmidt.
fn sphere_axes(ck: &mut Checker, axes: &Spanned<[[f64; 3]; 3]>, field: &str) -> [DVec3; 3] {
    let rows = axes.get_ref().map(|r| ck.vector(&Spanned::new(axes.span(), r), field));
    const TOLERANCE: f64 = 1e-4;
    let unit = rows.iter().all(|r| (r.length() - 1.0).abs() <= TOLERANCE);
    let orthogonal = [(0, 1), (1, 2), (0, 2)].iter().all(|&(a, b)| rows[a].dot(rows[b]).abs() <= TOLERANCE);
    if !(unit && orthogonal) {
        ck.error(axes.span(), field, format!("the axes must be orthonormal rows to within {TOLERANCE} (got {rows:?})"));
        return Sphere::WORLD_AXES;
    }
    let x = rows[0].normalize();
    let y = (rows[1] - x * x.dot(rows[1])).normalize();
    let z = rows[2] - x * x.dot(rows[2]) - y * y.dot(rows[2]);
    [x, y, z.normalize()]
}

fn check_transform(ck: &mut Checker, t: Option<&Spanned<RawTransform>>, field: &str) -> Transform {
    let Some(t) = t else { return Transform::default() };
    let span = t.span();
    let raw = t.get_ref();
    let result = match &raw.matrix {
        Some(m) if raw.translate.is_some() || raw.rotate.is_some() || raw.scale.is_some() => {
            Err((m.span(), "matrix", super::transform::TransformError::MatrixAndParts))
        }
        Some(m) => Transform::from_rows(*m.get_ref()).map_err(|e| (m.span(), "matrix", e)),
        None => {
            let translate = raw.translate.as_ref().map_or(DVec3::ZERO, |v| DVec3::from_array(*v.get_ref()));
            let scale = match raw.scale.as_ref().map(|s| *s.get_ref()) {
                None => DVec3::ONE,
                Some(RawScale::Uniform(k)) => DVec3::splat(k),
                Some(RawScale::PerAxis(v)) => DVec3::from_array(v),
            };
            let rotations: Vec<(DVec3, f64)> = match raw.rotate.as_ref().map(|r| r.get_ref().clone()) {
                None => Vec::new(),
                Some(RawRotations::One(r)) => vec![(DVec3::from_array(r.axis), r.angle)],
                Some(RawRotations::Many(rs)) => rs.iter().map(|r| (DVec3::from_array(r.axis), r.angle)).collect(),
            };
            // Name the part at fault where one is.
            Transform::from_parts(translate, &rotations, scale).map_err(|e| {
                use super::transform::TransformError as E;
                match (&e, &raw.translate, &raw.rotate, &raw.scale) {
                    (E::ZeroAxis, _, Some(r), _) => (r.span(), "rotate", e),
                    (E::Singular(_), _, _, Some(s)) => (s.span(), "scale", e),
                    (E::NotFinite(_), Some(t), _, _) if !t.get_ref().iter().all(|v| v.is_finite()) => (t.span(), "translate", e),
                    (E::NotFinite(_), _, _, Some(s)) => (s.span(), "scale", e),
                    (E::NotFinite(_), _, Some(r), _) => (r.span(), "rotate", e),
                    _ => (span.clone(), "", e),
                }
            })
        }
    };
    match result {
        Ok(t) => t,
        Err((span, part, e)) => {
            let name = if part.is_empty() { field.to_string() } else { format!("{field}.{part}") };
            ck.error(span, name, format!("transform {e}"));
            Transform::default()
        }
    }
}

/// `[[disks]]`, `[[cylinders]]`, `[[linear_curves]]`, `[[bspline_curves]]` and `[[sdf_grids]]`
/// (`quadrics`), in that order: transforms invertible; a
/// cylinder's radius > 0, its ends apart and its `to_world` not a mirror (its normals would turn
/// inwards); either may emit (on its normals' side, or both with `two_sided_emission`), a
/// cylinder only if not sheared or scaled unevenly across its axis. Mitsuba warns of a cylinder scaled unevenly across its axis or sheared, and
/// so does pathlab (its intersection is exact either way).
fn check_quadrics(ck: &mut Checker, raw: &RawScene, materials: &[Material], resolve: &mut Resolve) -> Vec<Quadric> {
    let mut quadrics = Vec::new();
    let flag = |f: &Option<Spanned<bool>>| f.as_ref().is_some_and(|f| *f.get_ref());
    for (i, s) in raw.disks.iter().enumerate() {
        let table = format!("disks[{i}]");
        let s = s.get_ref();
        let material = resolve(ck, &s.material, &format!("{table}.material"));
        refuse_mesh_only_material(ck, materials, material, &s.material, &format!("{table}.material"), "disk");
        let to_world = check_transform(ck, s.transform.as_ref(), &format!("{table}.transform"));
        quadrics.push(Quadric {
            kind: QuadricKind::Disk,
            to_world: DAffine3::from_mat4(to_world.matrix),
            flip_normals: flag(&s.flip_normals),
            material,
            two_sided_emission: flag(&s.two_sided_emission),
            data: QuadricData::Unit,
        });
    }
    for (i, c) in raw.cylinders.iter().enumerate() {
        let table = format!("cylinders[{i}]");
        let span = c.span();
        let c = c.get_ref();
        let material = resolve(ck, &c.material, &format!("{table}.material"));
        refuse_mesh_only_material(ck, materials, material, &c.material, &format!("{table}.material"), "cylinder");
        let transform = check_transform(ck, c.transform.as_ref(), &format!("{table}.transform"));
        let p0 = c.p0.as_ref().map_or(DVec3::ZERO, |p| ck.vector(p, &format!("{table}.p0")));
        let p1 = c.p1.as_ref().map_or(DVec3::Z, |p| ck.vector(p, &format!("{table}.p1")));
        let radius = match &c.radius {
            None => 1.0,
            Some(r) => {
                let field = format!("{table}.radius");
                let v = ck.number(r, &field);
                if !(v > 0.0) && r.get_ref().is_finite() {
                    ck.error(r.span(), &field, format!("radius must be > 0 (got {v})"));
                    continue;
                }
                v
            }
        };
        if (p1 - p0).length() == 0.0 {
            ck.error(c.p1.as_ref().map_or(span.clone(), Spanned::span), format!("{table}.p1"), "p0 and p1 must differ: the cylinder has no length");
            continue;
        }
        let to_world = quadrics::cylinder_to_world(DAffine3::from_mat4(transform.matrix), p0, p1, radius);
        let l = to_world.matrix3;
        let at = c.transform.as_ref().map_or(span.clone(), Spanned::span);
        if l.determinant() < 0.0 {
            ck.error(at, format!("{table}.transform"), "the cylinder's to_world mirrors it (negative determinant), which pathlab does not support");
            continue;
        }
        let (x, y, z) = (l.x_axis, l.y_axis, l.z_axis);
        let uneven = (x.length() - y.length()).abs() > 1e-6 * x.length()
            || x.dot(y).abs() > 1e-6 * x.length_squared()
            || x.dot(z).abs() > 1e-6 * x.length() * z.length()
            || y.dot(z).abs() > 1e-6 * y.length() * z.length();
        if uneven {
            ck.warn(at.clone(), format!("{table}.transform"), "the cylinder's to_world shears it or scales it unevenly across its axis (Mitsuba warns likewise); it is intersected exactly");
        }
        if uneven && materials.get(material).is_some_and(Material::is_emissive) {
            ck.error(at.clone(), format!("{table}.transform"), format!("material \"{}\" emits light: an emissive cylinder must not be sheared or scaled unevenly across its axis (its area, and so its sampling density, would be Mitsuba's approximation)", c.material.get_ref()));
        }
        quadrics.push(Quadric { kind: QuadricKind::Cylinder, to_world, flip_normals: flag(&c.flip_normals), material, two_sided_emission: flag(&c.two_sided_emission), data: QuadricData::Unit });
    }
    let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
    let curves = raw.linear_curves.iter().map(|c| (c, 2)).chain(raw.bspline_curves.iter().map(|c| (c, 4)));
    for (i, (c, min_points)) in curves.enumerate() {
        let linear = min_points == 2;
        let i = if linear { i } else { i - raw.linear_curves.len() };
        let table = if linear { format!("linear_curves[{i}]") } else { format!("bspline_curves[{i}]") };
        let c = c.get_ref();
        let material = resolve(ck, &c.material, &format!("{table}.material"));
        refuse_mesh_only_material(ck, materials, material, &c.material, &format!("{table}.material"), if linear { "linear curve" } else { "B-spline curve" });
        if materials.get(material).is_some_and(Material::is_emissive) {
            ck.error(c.material.span(), format!("{table}.material"), format!("material \"{}\" emits light: a curve cannot be a light (Mitsuba cannot sample points of its curves either)", c.material.get_ref()));
            continue;
        }
        if !linear && materials.get(material).is_some_and(|m| m.normal_map.is_some() || m.bump_map.is_some()) {
            ck.error(c.material.span(), format!("{table}.material"), format!("material \"{}\" has a normal or bump map, which pathlab does not support on a B-spline curve (its dp/dv is not computed)", c.material.get_ref()));
            continue;
        }
        let transform = check_transform(ck, c.transform.as_ref(), &format!("{table}.transform"));
        let file = base.join(c.file.get_ref());
        let curves = std::fs::read_to_string(&file).map_err(|e| (0, format!("cannot read curve file {}: {e}", file.display()))).and_then(|text| quadrics::read_curves(&text, min_points));
        let curves = match curves {
            Ok(curves) => curves,
            Err((line, message)) => {
                // The diagnostic points into the curve file, and names the scene's field.
                let (scene_file, scene_line, _) = ck.sources.locate(c.file.span().start);
                ck.diagnostics.push(Diagnostic {
                    severity: Severity::Error,
                    file: file.clone(),
                    line,
                    column: 1,
                    field: format!("{table}.file"),
                    message: format!("{message} (curve file of {}:{scene_line})", scene_file.display()),
                });
                continue;
            }
        };
        let to_world = DAffine3::from_mat4(transform.matrix);
        let beyond_f32 = |p: &DVec3| !p.is_finite() || p.abs().max_element() > f32::MAX as f64;
        let curve = |kind, data| Quadric { kind, to_world: DAffine3::IDENTITY, flip_normals: false, material, two_sided_emission: false, data };
        if !linear {
            let segments = quadrics::bspline_segments(&curves, &to_world);
            if let Some(s) = segments.iter().find(|s| s.p.iter().any(beyond_f32)) {
                ck.error(c.transform.as_ref().map_or(c.file.span(), Spanned::span), format!("{table}.transform"), format!("moves segment {} of {} beyond 32-bit floats", s.index, file.display()));
                continue;
            }
            quadrics.extend(segments.into_iter().map(|s| curve(QuadricKind::BsplineSegment, QuadricData::Bspline(s))));
            continue;
        }
        let segments = quadrics::segments(&curves, &to_world);
        if let Some(k) = segments.iter().position(|s| beyond_f32(&s.p0) || beyond_f32(&s.p1)) {
            ck.error(c.transform.as_ref().map_or(c.file.span(), Spanned::span), format!("{table}.transform"), format!("moves segment {k} of {} beyond 32-bit floats", file.display()));
            continue;
        }
        // A segment whose end spheres contain one another has no side (Embree's round cone
        // needs |p1 - p0| > |r1 - r0|).
        if let Some(s) = segments.iter().find(|s| (s.p1 - s.p0).length() <= (s.r1 - s.r0).abs()) {
            ck.error(c.file.span(), format!("{table}.file"), format!("segment {} of {} has one end sphere inside the other (length {} against radii {} and {}): it has no side", s.index, file.display(), (s.p1 - s.p0).length(), s.r0, s.r1));
            continue;
        }
        quadrics.extend(segments.into_iter().map(|s| curve(QuadricKind::CurveSegment, QuadricData::Curve(s))));
    }
    let mut grids_read: Vec<(std::path::PathBuf, bool, std::sync::Arc<quadrics::SdfGrid>)> = Vec::new();
    for (i, g) in raw.sdf_grids.iter().enumerate() {
        let table = format!("sdf_grids[{i}]");
        let g = g.get_ref();
        let material = resolve(ck, &g.material, &format!("{table}.material"));
        refuse_mesh_only_material(ck, materials, material, &g.material, &format!("{table}.material"), "signed distance grid");
        if let Some(m) = materials.get(material) {
            if m.is_emissive() {
                ck.error(g.material.span(), format!("{table}.material"), format!("material \"{}\" emits light: a signed distance grid cannot be a light (Mitsuba cannot sample points of its surface either)", g.material.get_ref()));
                continue;
            }
            if m.normal_map.is_some() || m.bump_map.is_some() {
                ck.error(g.material.span(), format!("{table}.material"), format!("material \"{}\" has a normal or bump map, which needs a uv parametrisation: a signed distance grid has none (Mitsuba's uv is 0 there)", g.material.get_ref()));
                continue;
            }
        }
        let smooth = match g.normals.as_ref().map(|n| n.get_ref().as_str()) {
            None | Some("smooth") => true,
            Some("analytic") => false,
            Some(other) => {
                let at = g.normals.as_ref().map_or(g.file.span(), Spanned::span);
                ck.error(at, format!("{table}.normals"), format!("normals \"{other}\" is not one of smooth, analytic"));
                continue;
            }
        };
        let transform = check_transform(ck, g.transform.as_ref(), &format!("{table}.transform"));
        let file = base.join(g.file.get_ref());
        // A file read once, however many shapes (an instanced group's copies) place it.
        if let Some((_, _, grid)) = grids_read.iter().find(|(f, s, _)| *f == file && *s == smooth) {
            quadrics.push(Quadric { kind: QuadricKind::SdfGrid, to_world: DAffine3::from_mat4(transform.matrix), flip_normals: false, material, two_sided_emission: false, data: QuadricData::Grid(grid.clone()) });
            continue;
        }
        let grid = crate::scene::vol_file::read_vol(&file).and_then(|vol| {
            if vol.channels != 1 {
                return Err(format!("{} channels (a signed distance grid has 1)", vol.channels));
            }
            quadrics::SdfGrid::new(file.clone(), vol.res, vol.data, smooth)
        });
        match grid {
            Ok(grid) => {
                let grid = std::sync::Arc::new(grid);
                grids_read.push((file, smooth, grid.clone()));
                quadrics.push(Quadric { kind: QuadricKind::SdfGrid, to_world: DAffine3::from_mat4(transform.matrix), flip_normals: false, material, two_sided_emission: false, data: QuadricData::Grid(grid) });
            }
            Err(e) => ck.error(g.file.span(), format!("{table}.file"), format!("signed distance grid {}: {e}", file.display())),
        }
    }
    if quadrics.len() > MAX_QUADRICS {
        let extra = raw.disks.iter().map(Spanned::span).chain(raw.cylinders.iter().map(Spanned::span)).chain(raw.linear_curves.iter().map(Spanned::span)).chain(raw.bspline_curves.iter().map(Spanned::span)).chain(raw.sdf_grids.iter().map(Spanned::span)).last().unwrap_or(0..0);
        ck.error(extra, "disks", too_many(quadrics.len(), MAX_QUADRICS, "disks, cylinders, curve segments and signed distance grids"));
    }
    quadrics
}

type Resolve<'r> = dyn FnMut(&mut Checker, &Spanned<String>, &str) -> usize + 'r;

/// `[[meshes]]` (OBJ, PLY or Mitsuba serialized files, relative to the scene file), `[[rectangles]]` and `[[cubes]]`:
/// read, checked, placed in the world. Errors in a mesh file name that file and its line.
fn check_meshes(ck: &mut Checker, raw: &RawScene, materials: &[Material], resolve: &mut Resolve) -> Vec<Mesh> {
    let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut meshes = Vec::new();
    let mut add = |ck: &mut Checker, table: String, source: String, data: MeshData, transform: Transform, shading: Shading,
                   flip_normals: bool, two_sided_emission: bool, material: usize, span: Range<usize>| {
        let (mut placed, placement) = mesh::place(&data, &transform, shading);
        if flip_normals {
            placed.flip_normals();
        }
        if let Some(i) = placed.positions.iter().position(|p| !p.is_finite() || p.abs().max_element() > f32::MAX as f64) {
            ck.error(span.clone(), format!("{table}.transform"), format!("moves vertex {i} of {source} beyond 32-bit floats"));
            return;
        }
        if placement.degenerate > 0 {
            ck.warn(span.clone(), &table, format!("{} of {} triangles of {source} have zero area and are dropped", placement.degenerate, data.triangles.len()));
        }
        let mesh = Mesh {
            source,
            material,
            two_sided_emission,
            positions: placed.positions,
            normals: placed.normals,
            uvs: placed.uvs,
            triangles: placed.triangles,
            attributes: placed.attributes,
        };
        // Every attribute its material's textures read, with channels the reading can use.
        for (name, scalar) in mesh_attribute_reads(materials, material) {
            let named = |a: &crate::scene::mesh::MeshAttribute| format!("{} ({} channel{})", a.name, a.channels, if a.channels == 1 { "" } else { "s" });
            let problem = match mesh.attribute(&name) {
                None => Some(format!(
                    "has no attribute \"{name}\" (it has {}), which its material's mesh_attribute texture reads",
                    if mesh.attributes.is_empty() { "none".to_string() } else { mesh.attributes.iter().map(named).collect::<Vec<_>>().join(", ") }
                )),
                Some(a) if a.channels != 1 && a.channels != 3 => {
                    Some(format!("has the attribute {}, where a texture reads 1 or 3 (Mitsuba evaluates other counts as 0)", named(a)))
                }
                Some(a) if scalar && a.channels != 1 => Some(format!(
                    "has the attribute {}, which its material reads as one number (a weight or an opacity, Mitsuba's eval_1, which gives 0 for 3 channels): give a one-channel attribute",
                    named(a)
                )),
                // An emission's values (times its scale, >= 0) must be >= 0 (a radiance).
                Some(a) if emission_reads(materials, material, &name) && a.values.iter().any(|v| *v < 0.0) => {
                    Some(format!("has the attribute {} with a negative value, which its material emits (a radiance is >= 0)", named(a)))
                }
                Some(_) => None,
            };
            if let Some(problem) = problem {
                ck.error(span.clone(), format!("{table}.material"), format!("{} {problem}", mesh.source));
            }
        }
        let emissive = materials.get(material).is_some_and(Material::is_emissive);
        if emissive && !(mesh.area() > 0.0) {
            ck.error(span, format!("{table}.material"), format!("{} is emissive but its total area is zero: it cannot be sampled as a light", mesh.source));
            return;
        }
        if !mesh.triangles.is_empty() {
            meshes.push(mesh);
        }
    };
    for (i, m) in raw.meshes.iter().enumerate() {
        let span = m.span();
        let m = m.get_ref();
        let table = format!("meshes[{i}]");
        let material = resolve(ck, &m.material, &format!("{table}.material"));
        let transform = check_transform(ck, m.transform.as_ref(), &format!("{table}.transform"));
        let file = base.join(m.file.get_ref());
        let serialized = mesh::is_serialized(&file);
        let shape_index = match &m.shape_index {
            Some(k) if !serialized => {
                ck.error(k.span(), format!("{table}.shape_index"), "shape_index applies to Mitsuba serialized files (.serialized) only");
                0
            }
            Some(k) => ck.integer(k, &format!("{table}.shape_index"), 0, u32::MAX as i64) as u32,
            None => 0,
        };
        let mut data = match mesh::read_mesh_shape(&file, shape_index) {
            Ok(d) => d,
            Err(e) => {
                // The diagnostic points into the mesh file where it can, and names the scene's field.
                let (scene_file, scene_line, _) = ck.sources.locate(m.file.span().start);
                ck.diagnostics.push(Diagnostic {
                    severity: Severity::Error,
                    file: e.path.clone(),
                    line: e.line.unwrap_or(0),
                    column: 1,
                    field: format!("{table}.file"),
                    message: format!("{} (mesh of {}:{scene_line})", e.message, scene_file.display()),
                });
                continue;
            }
        };
        for (line, note) in &data.notes {
            ck.diagnostics.push(Diagnostic {
                severity: Severity::Warning,
                file: file.clone(),
                line: line.unwrap_or(0),
                column: 1,
                field: format!("{table}.file"),
                message: note.clone(),
            });
        }
        // Mitsuba's rule: smooth unless `face_normals`, with normals recomputed where the file has none.
        let shading = if m.face_normals.as_ref().is_some_and(|f| *f.get_ref()) { Shading::Faceted } else { Shading::Smooth };
        let two_sided = m.two_sided_emission.as_ref().is_some_and(|f| *f.get_ref());
        let flip = m.flip_normals.as_ref().is_some_and(|f| *f.get_ref());
        // Mitsuba's default: v becomes 1 - v (images start at their bottom row in OBJ and PLY);
        // its serialized shape has no such flip.
        if m.flip_tex_coords.as_ref().map_or(!serialized, |f| *f.get_ref()) {
            data.flip_tex_coords();
        }
        add(ck, table, file.display().to_string(), data, transform, shading, flip, two_sided, material, span);
    }
    for (kind, list, make) in [("rectangles", &raw.rectangles, shapes::rectangle as fn() -> MeshData), ("cubes", &raw.cubes, shapes::cube)] {
        for (i, s) in list.iter().enumerate() {
            let span = s.span();
            let s = s.get_ref();
            let table = format!("{kind}[{i}]");
            let material = resolve(ck, &s.material, &format!("{table}.material"));
            let transform = check_transform(ck, s.transform.as_ref(), &format!("{table}.transform"));
            let two_sided = s.two_sided_emission.as_ref().is_some_and(|f| *f.get_ref());
            let flip = s.flip_normals.as_ref().is_some_and(|f| *f.get_ref());
            add(ck, table.clone(), table, make(), transform, Shading::Faceted, flip, two_sided, material, span);
        }
    }
    meshes
}

/// `[display]`: `transfer = "srgb"` (default) or `"gamma"` with `gamma = G > 0`; `exposure` in
/// stops (default 0).
fn check_display(ck: &mut Checker, raw: &RawScene) -> DisplayTransform {
    let Some(d) = &raw.display else { return DisplayTransform::default() };
    let d = d.get_ref();
    let exposure = d.exposure.as_ref().map_or(0.0, |e| ck.number(e, "display.exposure")) as f32;
    let gamma = d.gamma.as_ref().map(|g| {
        let v = ck.number(g, "display.gamma");
        if !(v > 0.0) && g.get_ref().is_finite() {
            ck.error(g.span(), "display.gamma", format!("gamma must be > 0 (got {v})"));
        }
        v
    });
    let transfer = match d.transfer.as_ref().map(|t| (t.get_ref().as_str(), t.span())) {
        None | Some(("srgb", _)) => {
            if let (Some(g), Some(_)) = (&d.gamma, gamma) {
                ck.error(g.span(), "display.gamma", "gamma applies only with transfer = \"gamma\"");
            }
            Transfer::Srgb
        }
        Some(("gamma", span)) => match gamma {
            Some(g) if g > 0.0 => Transfer::Gamma(g as f32),
            Some(_) => Transfer::Srgb,
            None => {
                ck.error(span, "display.gamma", "transfer = \"gamma\" needs gamma = G (e.g. 2.2; the study used 1.6)");
                Transfer::Srgb
            }
        },
        Some((other, span)) => {
            ck.error(span, "display.transfer", format!("unknown transfer \"{other}\" (known: \"srgb\", \"gamma\")"));
            Transfer::Srgb
        }
    };
    DisplayTransform { transfer, exposure }
}

fn check_camera(ck: &mut Checker, raw: &RawScene) -> Camera {
    let c = raw.camera.get_ref();
    let position = ck.vector(&c.position, "camera.position");
    let look_at = ck.vector(&c.look_at, "camera.look_at");
    let up = ck.vector(&c.up, "camera.up");
    let forward = look_at - position;
    if forward.length() == 0.0 {
        ck.error(c.look_at.span(), "camera.look_at", "look_at must differ from position");
    } else if forward.normalize().cross(up).length() < 1e-9 {
        ck.error(c.up.span(), "camera.up", "up must be non-zero and not parallel to the view direction");
    }
    // Exactly one of the keys gives the field of view.
    let given = given_fovs([&c.fov_x, &c.fov_y, &c.fov_smaller, &c.fov_larger, &c.fov_diagonal]);
    // An orthographic camera: a width instead of a field of view.
    let projection = match (&c.orthographic_width, given.as_slice()) {
        (Some(w), []) => {
            let v = ck.number(w, "camera.orthographic_width");
            if !(v > 0.0) && w.get_ref().is_finite() {
                ck.error(w.span(), "camera.orthographic_width", format!("orthographic_width must be > 0 (got {v})"));
            }
            Projection::Orthographic { width: v }
        }
        (Some(_), [(key, v, _), ..]) => {
            ck.error(v.span(), &format!("camera.{key}"), format!("give either a field of view or orthographic_width, not both ({key} and orthographic_width)"));
            Projection::Orthographic { width: 1.0 }
        }
        (None, [(key, v, make)]) => Projection::Perspective(make(checked_fov(ck, v, &format!("camera.{key}")))),
        (None, []) => {
            ck.error(raw.camera.span(), "camera", "missing field of view: give exactly one of fov_x and fov_y (or fov_smaller, fov_larger, fov_diagonal, or orthographic_width)");
            Projection::Perspective(Fov::X(90.0))
        }
        (None, [(first, ..), (second, v, _), ..]) => {
            ck.error(v.span(), &format!("camera.{second}"), format!("give exactly one field of view, not both {first} and {second}"));
            Projection::Perspective(Fov::Y(90.0))
        }
    };
    // A thin lens: an aperture radius >= 0 (0: a pinhole) and a focus distance > 0 (default the
    // distance to look_at), which a pinhole does not use (said, not ignored).
    let aperture_radius = match &c.aperture_radius {
        None => 0.0,
        Some(a) => {
            let v = ck.number(a, "camera.aperture_radius");
            if v < 0.0 {
                ck.error(a.span(), "camera.aperture_radius", format!("aperture_radius must be >= 0 (got {v}; 0 is a pinhole)"));
            }
            if v > 0.0 && matches!(projection, Projection::Orthographic { .. }) {
                ck.error(a.span(), "camera.aperture_radius", "an orthographic camera has no lens: give aperture_radius with a field of view");
            }
            v.max(0.0)
        }
    };
    let focus_distance = match &c.focus_distance {
        None => forward.length(),
        Some(f) => {
            let v = ck.number(f, "camera.focus_distance");
            if !(v > 0.0) && f.get_ref().is_finite() {
                ck.error(f.span(), "camera.focus_distance", format!("focus_distance must be > 0 (got {v})"));
            }
            if aperture_radius == 0.0 {
                ck.warn(f.span(), "camera.focus_distance", "focus_distance has no effect without an aperture_radius: a pinhole is in focus everywhere");
            }
            v
        }
    };
    Camera { position, look_at, up, projection, aperture_radius, focus_distance }
}

fn check_render(ck: &mut Checker, raw: &RawScene) -> RenderSettings {
    let r = raw.render.get_ref();
    let rr_depth = r.rr_depth.as_ref().map(|d| ck.integer(d, "render.rr_depth", 1, MAX_DEPTH_LIMIT) as u32);
    let max_depth = if *r.max_depth.get_ref() == -1 {
        if rr_depth.is_none() {
            ck.error(r.max_depth.span(), "render.max_depth", "max_depth = -1 (unbounded) needs Russian roulette: give rr_depth too (Mitsuba's default is 5)");
        }
        super::UNBOUNDED_DEPTH
    } else {
        ck.integer(&r.max_depth, "render.max_depth", 1, MAX_DEPTH_LIMIT) as u32
    };
    RenderSettings {
        width: ck.integer(&r.width, "render.width", 1, MAX_IMAGE_SIDE) as u32,
        height: ck.integer(&r.height, "render.height", 1, MAX_IMAGE_SIDE) as u32,
        max_depth,
        rr_depth,
        environment: ck.color(r.environment.as_ref(), "render.environment"),
        spp: r.spp.as_ref().map(|spp| ck.integer(spp, "render.spp", 1, u32::MAX as i64)),
        hide_emitters: r.hide_emitters.as_ref().is_some_and(|h| *h.get_ref()),
    }
}

/// A material's `emission`: a colour, or a texture (its mean, and the texture), looked up at
/// the uv parametrisation of the emitting surface; a grid volume, looked up in space, is not
/// supported as an emission.
fn check_emission(ck: &mut Checker, name: &str, m: &RawMaterial) -> (DVec3, Option<Texture>) {
    let field = format!("materials.{name}.emission");
    let Some(e) = m.emission.as_ref() else { return (DVec3::ZERO, None) };
    match e.get_ref() {
        RawColorOrTexture::Color(c) => (ck.color(Some(&Spanned::new(e.span(), *c)), &field), None),
        RawColorOrTexture::Texture(table) => {
            let base = ck.file.parent().map(Path::to_path_buf).unwrap_or_default();
            let mut errors = Vec::new();
            let texture = Texture::from_toml(table, e.span(), &base, &mut errors);
            for (span, message) in errors {
                ck.error(span, &field, message);
            }
            match texture {
                Some(Texture::Volume(_)) => {
                    ck.error(e.span(), &field, "a volume texture as an emission is not supported (an emission texture is looked up at the surface's uv parametrisation: give a bitmap, a checkerboard or a rawconstant)");
                    (DVec3::ZERO, None)
                }
                Some(Texture::MeshAttribute { scale, .. }) if scale < 0.0 => {
                    ck.error(e.span(), &field, format!("`scale` of a mesh_attribute emission must be >= 0 (got {scale})"));
                    (DVec3::ZERO, None)
                }
                Some(t) if t.mean().min_element() < 0.0 => {
                    ck.error(e.span(), &field, format!("an emission texture must be >= 0 everywhere (its mean is {:?})", t.mean().to_array()));
                    (DVec3::ZERO, None)
                }
                Some(t) => (t.mean(), Some(t)),
                None => (DVec3::ZERO, None),
            }
        }
    }
}

/// A light's texture, refused where it is a mesh attribute: a light's texture is looked up in
/// its own frame, where no mesh is hit.
fn refuse_light_mesh_attribute(ck: &mut Checker, texture: Option<Texture>, span: Range<usize>, field: &str) -> Option<Texture> {
    match texture {
        Some(Texture::MeshAttribute { .. }) => {
            ck.error(span, field, "a mesh_attribute cannot texture a light: it is looked up on the mesh a ray hits, and a light's texture in the light's own frame");
            None
        }
        t => t,
    }
}

/// Refuses a material with a textured emission, or one that reads a mesh attribute, on a shape
/// other than a triangle mesh: the kernel looks an emission texture up on triangles alone, and
/// only meshes have attributes.
fn refuse_mesh_only_material(ck: &mut Checker, materials: &[Material], material: usize, name: &Spanned<String>, field: &str, shape: &str) {
    if materials.get(material).is_some_and(|m| m.emission_texture.is_some()) {
        ck.error(name.span(), field, format!("material \"{}\" has a textured emission, which pathlab supports on triangle meshes (meshes, rectangles, cubes) alone, not on a {shape}", name.get_ref()));
    }
    if let Some((attribute, _)) = mesh_attribute_reads(materials, material).first() {
        ck.error(name.span(), field, format!("material \"{}\" reads the mesh attribute \"{attribute}\" (a mesh_attribute texture), which only a triangle mesh has, not a {shape}", name.get_ref()));
    }
}

/// Whether material i's emission is the mesh attribute `name`.
fn emission_reads(materials: &[Material], i: usize, name: &str) -> bool {
    materials.get(i).and_then(|m| m.emission_texture.as_ref()).and_then(Texture::mesh_attribute) == Some(name)
}

/// The mesh attributes that material i's textures read (its own, its back material's and its
/// blend partner's), each with whether it is read as a scalar (Mitsuba's `eval_1`).
fn mesh_attribute_reads(materials: &[Material], i: usize) -> Vec<(String, bool)> {
    let mut reads = Vec::new();
    let mut visit = vec![i];
    let mut seen = BTreeSet::new();
    while let Some(k) = visit.pop() {
        let Some(m) = materials.get(k).filter(|_| seen.insert(k)) else { continue };
        for t in m.textures() {
            if let Texture::MeshAttribute { name, scalar, .. } = t {
                reads.push((name.clone(), *scalar));
            }
        }
        visit.extend(m.back);
        visit.extend(m.blend.as_ref().map(|b| b.material));
    }
    reads
}

fn check_materials(ck: &mut Checker, raw: &RawScene) -> (Vec<Material>, BTreeMap<String, usize>) {
    let mut materials = Vec::new();
    let mut names = BTreeMap::new();
    for (name, m) in &raw.materials {
        let span = m.span();
        let m: &RawMaterial = m.get_ref();
        let (emission, emission_texture) = check_emission(ck, name, m);
        let mut two_sided = m.two_sided.as_ref().is_none_or(|t| *t.get_ref());
        let bsdf = super::bsdfs::read(ck, name, span, m.bsdf.as_ref(), &m.params);
        if bsdf.both_sides() {
            if let Some(t) = m.two_sided.as_ref().filter(|t| !*t.get_ref()) {
                let kind = bsdf.kind().toml_name();
                let why = if bsdf.kind().both_sides() { "by its nature" } else { "where it transmits" };
                ck.error(t.span(), format!("materials.{name}.two_sided"), format!("a {kind} scatters on both sides {why}: two_sided = false does not apply"));
            }
            two_sided = true;
        }
        let opacity = m.opacity.as_ref().and_then(|o| {
            let base = ck.file.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
            match Opacity::from_toml(o.get_ref(), o.span(), &base) {
                Ok(opacity) => opacity,
                Err(errors) => {
                    for (span, message) in errors {
                        ck.error(span, format!("materials.{name}.opacity"), message);
                    }
                    None
                }
            }
        });
        let normal_map = m.normal_map.as_ref().and_then(|n| {
            let base = ck.file.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
            let field = format!("materials.{name}.normal_map");
            if bsdf.transmits() || bsdf.both_sides() {
                ck.error(n.span(), field, format!("a normal map around a {}, which transmits, is not supported (normal-map a BSDF that reflects)", bsdf.kind().toml_name()));
                return None;
            }
            match super::bsdfs::NormalMap::from_toml(n.get_ref(), n.span(), &base) {
                Ok(map) => Some(map),
                Err(errors) => {
                    for (span, message) in errors {
                        ck.error(span, field.clone(), message);
                    }
                    None
                }
            }
        });
        let bump_map = m.bump_map.as_ref().and_then(|b| {
            let base = ck.file.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
            let field = format!("materials.{name}.bump_map");
            if bsdf.transmits() || bsdf.both_sides() {
                ck.error(b.span(), field, format!("a bump map around a {}, which transmits, is not supported (bump-map a BSDF that reflects)", bsdf.kind().toml_name()));
                return None;
            }
            if m.normal_map.is_some() {
                ck.error(b.span(), field, "a material takes a normal map or a bump map, not both");
                return None;
            }
            match super::bsdfs::BumpMap::from_toml(b.get_ref(), b.span(), &base) {
                Ok(map) => Some(map),
                Err(errors) => {
                    for (span, message) in errors {
                        ck.error(span, field.clone(), message);
                    }
                    None
                }
            }
        });
        names.insert(name.clone(), materials.len());
        materials.push(Material { name: name.clone(), emission, emission_texture, two_sided, bsdf, opacity, normal_map, bump_map, back: None, blend: None, interior: None, exterior: None });
    }
    // Backs, once every material has its index: a back's own BSDF is what scatters, so it must
    // be a plain one-BSDF material that only reflects (Mitsuba's twosided nests no
    // transmission), and the front two-sided.
    for (name, m) in &raw.materials {
        let Some(back) = m.get_ref().back.as_ref() else { continue };
        let field = format!("materials.{name}.back");
        let Some(&b) = names.get(back.get_ref()) else {
            let known: Vec<&str> = names.keys().map(String::as_str).collect();
            ck.error(back.span(), field, format!("no material \"{}\" (materials: {})", back.get_ref(), known.join(", ")));
            continue;
        };
        let i = names[name];
        let bm = &materials[b];
        let problem = if b == i {
            Some("a material cannot be its own back".to_string())
        } else if bm.bsdf.transmits() {
            Some(format!("the back \"{}\" is a {}, which transmits: Mitsuba's twosided nests only BSDFs that reflect", bm.name, bm.bsdf_kind().toml_name()))
        } else if raw.materials.get(back.get_ref()).is_some_and(|r| r.get_ref().back.is_some() || r.get_ref().blend.is_some()) || bm.opacity.is_some() || bm.normal_map.is_some() || bm.bump_map.is_some() || bm.is_emissive() {
            Some(format!("the back \"{}\" must be a plain material: no back, blend, opacity, normal map, bump map or emission of its own", bm.name))
        } else if !materials[i].two_sided {
            Some("a material with a back is two-sided: two_sided = false does not apply".to_string())
        } else if materials[i].bsdf.transmits() {
            Some(format!("a {} transmits: Mitsuba's twosided nests only BSDFs that reflect", materials[i].bsdf_kind().toml_name()))
        } else {
            None
        };
        match problem {
            Some(p) => ck.error(back.span(), field, p),
            None => materials[i].back = Some(b),
        }
    }
    // Blends, likewise: the other material's BSDF is picked in place of this one's at some
    // vertices, so it must be a plain one-BSDF material, and this one may add a mask (which
    // wraps the blend) but no back, normal map or bump map (whose frames the blend does not
    // pass on).
    for (name, m) in &raw.materials {
        let raw_m = m.get_ref();
        let field = format!("materials.{name}.blend");
        let (blend, weight) = match (&raw_m.blend, &raw_m.blend_weight) {
            (None, None) => continue,
            (Some(b), Some(w)) => (b, w),
            (Some(b), None) => {
                ck.error(b.span(), field, "a blend needs its `blend_weight` (the other BSDF's weight in [0, 1], as Mitsuba's blendbsdf requires its `weight`)");
                continue;
            }
            (None, Some(w)) => {
                ck.error(w.span(), format!("materials.{name}.blend_weight"), "`blend_weight` without `blend` (the material whose BSDF it weighs)");
                continue;
            }
        };
        let base = ck.file.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
        let weight = match Opacity::weight_from_toml(weight.get_ref(), weight.span(), &base, "blend_weight") {
            Ok(w) => w,
            Err(errors) => {
                for (span, message) in errors {
                    ck.error(span, format!("materials.{name}.blend_weight"), message);
                }
                continue;
            }
        };
        let Some(&b) = names.get(blend.get_ref()) else {
            let known: Vec<&str> = names.keys().map(String::as_str).collect();
            ck.error(blend.span(), field, format!("no material \"{}\" (materials: {})", blend.get_ref(), known.join(", ")));
            continue;
        };
        let i = names[name];
        let bm = &materials[b];
        let other_raw = raw.materials.get(blend.get_ref()).map(|r| r.get_ref());
        let problem = if b == i {
            Some("a material cannot blend with itself".to_string())
        } else if other_raw.is_some_and(|r| r.back.is_some() || r.blend.is_some()) || bm.opacity.is_some() || bm.normal_map.is_some() || bm.bump_map.is_some() || bm.is_emissive() {
            Some(format!("the blended \"{}\" must be a plain material: no back, blend, opacity, normal map, bump map or emission of its own", bm.name))
        } else if raw_m.back.is_some() || materials[i].normal_map.is_some() || materials[i].bump_map.is_some() {
            Some("a blend with a back, a normal map or a bump map is not supported (blend plain BSDFs; a mask may wrap the blend)".to_string())
        } else {
            None
        };
        match problem {
            Some(p) => ck.error(blend.span(), field, p),
            None => materials[i].blend = Some(super::bsdfs::Blend { material: b, weight }),
        }
    }
    (materials, names)
}

fn too_many(count: usize, max: usize, what: &str) -> String {
    format!(
        "the scene has {count} {what}, more than the {max} the kernel supports \
         (every ray is tested against every object: there is no acceleration structure)"
    )
}

/// Dotted path of the TOML field at byte `offset` (e.g. `spheres[1].radius`), recovered from the
/// table headers above it: used for errors reported by the TOML parser itself.
fn field_path_at(text: &str, offset: usize) -> String {
    let mut table = String::new();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut pos = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim();
        let line_end = pos + line.len();
        if let Some(name) = trimmed.strip_prefix("[[").and_then(|s| s.split("]]").next()) {
            let name = name.trim().to_string();
            let n = counts.entry(name.clone()).or_insert(0);
            table = format!("{name}[{n}]");
            *n += 1;
        } else if let Some(name) = trimmed.strip_prefix('[').and_then(|s| s.split(']').next()) {
            table = name.trim().to_string();
        }
        if offset < line_end || line_end == text.len() {
            let key = trimmed
                .split_once('=')
                .map(|(k, _)| k.trim())
                .filter(|k| !k.is_empty() && !k.starts_with('[') && !k.starts_with('#'));
            return match (key, table.is_empty()) {
                (Some(k), false) => format!("{table}.{k}"),
                (Some(k), true) => k.to_string(),
                (None, _) => table,
            };
        }
        pos = line_end;
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn field_path_of_array_of_tables() {
        let text = "[camera]\nfov_x = 1\n[[spheres]]\nradius = 1\n[[spheres]]\nradius = -1\n";
        let offset = text.rfind("-1").unwrap();
        assert_eq!(field_path_at(text, offset), "spheres[1].radius");
        assert_eq!(field_path_at(text, text.find("fov_x").unwrap()), "camera.fov_x");
    }

    #[test]
    fn more_objects_than_the_kernel_holds_are_refused_at_the_first_extra_one() {
        let mut text = String::from(
            "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nup = [0, 1, 0]\nfov_x = 60\n\
             [render]\nwidth = 4\nheight = 4\nmax_depth = 1\n[materials.m]\nemission = 1\n",
        );
        for i in 0..=MAX_SPHERES {
            text.push_str(&format!("[[spheres]]\ncenter = [{i}, 0, -10]\nradius = 0.1\nmaterial = \"m\"\n"));
        }
        let Err(SceneError::Invalid(diagnostics)) = parse_and_validate(&text, Path::new("many.toml")) else {
            panic!("accepted {} spheres", MAX_SPHERES + 1);
        };
        let d = &diagnostics[0];
        assert_eq!(d.field, format!("spheres[{MAX_SPHERES}]"));
        assert_eq!(d.line, 12 + 4 * MAX_SPHERES);
        assert!(d.message.contains("more than the 1024"), "{}", d.message);
    }
}
