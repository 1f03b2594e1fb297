//! Mitsuba's delta emitters, `point`, `spot`, `directional` and `projector`, read into
//! `[[point_lights]]`, `[[spot_lights]]`, `[[directional_lights]]` and `[[projector_lights]]`
//! (`scene::emitters::{point, spot, directional, projector}`), with their parameters, defaults
//! and frames as Mitsuba 3.9.1 reads them (`src/emitters/point.cpp`, `spot.cpp`,
//! `directional.cpp`, `projector.cpp`).

use glam::{DMat3, DVec3};

use super::super::raw::{RawColor, RawDirectionalLight, RawPointLight, RawProjectorLight, RawSpotLight};
use super::super::diagnostic::Findings;
use super::super::spectrum::SpectrumRole;
use super::xml::{compose, Object};
use super::{spanned, PluginReader, Props, Translator};
use crate::scene::bsdfs::PluginProps as _;
use toml::Spanned;

/// Mitsuba's default intensity (and irradiance): 1.
const DEFAULT_EMISSION: [f64; 3] = [1.0; 3];

impl Translator<'_> {
    /// The emission of a delta emitter (`intensity` or `irradiance`, Mitsuba's emissive
    /// texture: an `<rgb>`, a `<float>` or a `<spectrum>` read as an emission), default 1.
    fn delta_emission(&mut self, p: &mut Props, name: &str, o: &Object) -> Spanned<RawColor> {
        let c = self.color(p, name, SpectrumRole::Emission);
        spanned(c.map_or(o.at, |c| c.1), RawColor(c.map_or(DEFAULT_EMISSION, |c| c.0)))
    }

    /// A `to_world` as (linear part, translation), where given.
    fn frame(&mut self, p: &mut Props) -> Option<(DMat3, DVec3, usize)> {
        let (ops, at) = self.transform(p, "to_world")?;
        let m = compose(&ops);
        Some((DMat3::from_mat4(m), m.w_axis.truncate(), at))
    }

    /// `<emitter type="point">`: `position` or the translation of `to_world` (not both, as
    /// Mitsuba), `intensity`.
    pub(super) fn point_emitter(&mut self, o: &Object) -> Option<Spanned<RawPointLight>> {
        let mut p = Props::of(o);
        let position = self.point(&mut p, "position");
        let frame = self.frame(&mut p);
        let intensity = self.delta_emission(&mut p, "intensity", o);
        self.finish(p, "position, to_world, intensity");
        let position = match (position, frame) {
            (Some(_), Some((_, _, at))) => {
                self.error(at, "to_world", "give either `position` or `to_world` of a point emitter, not both (as Mitsuba)".to_string());
                return None;
            }
            (Some(x), None) => x,
            (None, Some((_, t, _))) => t,
            (None, None) => DVec3::ZERO,
        };
        Some(spanned(o.at, RawPointLight { position: spanned(o.at, position.to_array()), intensity }))
    }

    /// `<emitter type="spot">`: `to_world` (its translation the position, its +z the axis, its
    /// +y the projected texture's up; a rotation with a uniform scale, as `lookat` gives),
    /// `intensity`, `cutoff_angle` and `beam_width` in degrees, and a projected `texture`
    /// (Mitsuba requires one that varies: a bitmap or a checkerboard).
    pub(super) fn spot_emitter(&mut self, o: &Object) -> Option<Spanned<RawSpotLight>> {
        let mut p = Props::of(o);
        let frame = self.frame(&mut p);
        let intensity = self.delta_emission(&mut p, "intensity", o);
        let cutoff = self.get::<f64>(&mut p, "cutoff_angle").map(|(v, prop)| spanned(prop.value_at, v));
        let beam = self.get::<f64>(&mut p, "beam_width").map(|(v, prop)| spanned(prop.value_at, v));
        let texture = self.emitter_texture(o, p, "texture", "to_world, intensity, cutoff_angle, beam_width, texture");
        // Mitsuba's spot refuses a texture that does not vary ("must be spatially varying").
        let texture = match texture {
            Some(t) if t.get_ref().get("texture").and_then(toml::Value::as_str) == Some("rawconstant") => {
                self.error(t.span().start, "texture", "the `texture` of a spot emitter must vary over it (Mitsuba: \"must be spatially varying (e.g. bitmap type)\"); give a bitmap or a checkerboard".to_string());
                None
            }
            t => t,
        };
        let (linear, position) = self.similarity_frame(frame, "a spot emitter", "its falloff is measured in angles about its axis")?;
        let direction = (linear * DVec3::Z).normalize();
        let up = texture.as_ref().map(|_| spanned(o.at, (linear * DVec3::Y).normalize().to_array()));
        Some(spanned(
            o.at,
            RawSpotLight {
                position: spanned(o.at, position.to_array()),
                direction: spanned(o.at, direction.to_array()),
                intensity,
                cutoff_angle: cutoff,
                beam_width: beam,
                texture,
                up,
            },
        ))
    }

    /// `<emitter type="projector">`: `to_world` (its translation the pinhole, its +z the axis,
    /// its +y the image's up; a rotation with a uniform scale s, which scales the irradiance by
    /// s as Mitsuba's formula does: see below), the field of
    /// view as a perspective sensor's (`fov`, `fov_axis` or `focal_length`, default 50mm),
    /// resolved at the irradiance image's aspect ratio, `irradiance` (a texture, or a colour:
    /// Mitsuba's default 1) and `scale` (default 1).
    pub(super) fn projector_emitter(&mut self, o: &Object) -> Option<Spanned<RawProjectorLight>> {
        let mut p = Props::of(o);
        let frame = self.frame(&mut p);
        let fov = self.field_of_view(o, &mut p);
        let scale = self.get::<f64>(&mut p, "scale").map(|(v, prop)| spanned(prop.value_at, v));
        let colour = self.color(&mut p, "irradiance", SpectrumRole::Emission);
        let texture = self.emitter_texture(o, p, "irradiance", "to_world, fov, fov_axis, focal_length, irradiance, scale");
        let irradiance = match (texture, colour) {
            (Some(t), _) => t,
            (None, Some((c, at))) => spanned(at, super::super::bsdfs::color_value(c)),
            (None, None) => spanned(o.at, super::super::bsdfs::color_value(DEFAULT_EMISSION)),
        };
        let (linear, position) = self.similarity_frame(frame, "a projector", "its image is projected in angles about its axis")?;
        // Mitsuba divides by the depth in the local frame squared (z / s)^2 and by
        // -dot(n, d) with n = to_world (0, 0, 1) left unnormalised (s cos(theta)): s in all.
        let s = linear.x_axis.length();
        let scale = match scale {
            Some(v) => Some(spanned(v.span().start, *v.get_ref() * s)),
            None => (s != 1.0).then(|| spanned(o.at, s)),
        };
        let (fov, at) = fov?;
        let given = |key: &str| (fov.key() == key).then(|| spanned(at, fov.degrees()));
        Some(spanned(
            o.at,
            RawProjectorLight {
                position: spanned(o.at, position.to_array()),
                direction: spanned(o.at, (linear * DVec3::Z).normalize().to_array()),
                up: spanned(o.at, (linear * DVec3::Y).normalize().to_array()),
                fov_x: given("fov_x"),
                fov_y: given("fov_y"),
                fov_smaller: given("fov_smaller"),
                fov_larger: given("fov_larger"),
                fov_diagonal: given("fov_diagonal"),
                irradiance,
                scale,
            },
        ))
    }

    /// An emitter's nested texture `name` (a spot's projected `texture`, a projector's
    /// `irradiance`, an area emitter's `radiance`), read as a BSDF's textures are, as its TOML
    /// value; `reads` lists what the emitter reads; any other child is refused.
    pub(super) fn emitter_texture(&mut self, o: &Object, p: Props, name: &str, reads: &str) -> Option<Spanned<toml::Value>> {
        let nested = o.children.iter().position(|c| c.tag == "texture" && c.name.as_deref() == Some(name));
        let mut reader = PluginReader { t: self, p: Some(p), o, taken: Vec::new() };
        let value = match nested {
            Some(_) => reader.color_or_texture(name),
            None => None,
        };
        reader.finish(reads);
        for (i, c) in o.children.iter().enumerate() {
            if Some(i) != nested {
                self.error(c.at, c.name.as_deref().unwrap_or(""), format!("{} inside an <emitter type=\"{}\"> is not supported", super::describe(&c.tag, &c.plugin), o.plugin));
            }
        }
        let at = nested.map_or(o.at, |i| o.children[i].at);
        value.map(|v| spanned(at, v))
    }

    /// A delta emitter's `to_world` as (linear part, translation), refused (naming `what`, and
    /// `why` it must be) unless a rotation with a uniform scale; the identity where not given.
    fn similarity_frame(&mut self, frame: Option<(DMat3, DVec3, usize)>, what: &str, why: &str) -> Option<(DMat3, DVec3)> {
        match frame {
            None => Some((DMat3::IDENTITY, DVec3::ZERO)),
            Some((linear, t, _)) if is_similarity(linear) => Some((linear, t)),
            Some((_, _, at)) => {
                self.error(at, "to_world", format!("the `to_world` of {what} must be a rotation with a uniform scale ({why})"));
                None
            }
        }
    }

    /// `<emitter type="directional">`: `direction` (the way the light travels) or `to_world`
    /// (its +z; not both, as Mitsuba), `irradiance`.
    pub(super) fn directional_emitter(&mut self, o: &Object) -> Option<Spanned<RawDirectionalLight>> {
        let mut p = Props::of(o);
        let direction = self.point(&mut p, "direction");
        let frame = self.frame(&mut p);
        let irradiance = self.delta_emission(&mut p, "irradiance", o);
        self.finish(p, "direction, to_world, irradiance");
        let direction = match (direction, frame) {
            (Some(_), Some((_, _, at))) => {
                self.error(at, "to_world", "give either `direction` or `to_world` of a directional emitter, not both (as Mitsuba)".to_string());
                return None;
            }
            (Some(d), None) => d,
            (None, Some((linear, _, _))) => linear * DVec3::Z,
            (None, None) => DVec3::Z,
        };
        Some(spanned(o.at, RawDirectionalLight { direction: spanned(o.at, direction.to_array()), irradiance }))
    }
}

/// Whether `m` is a rotation times a uniform scale (columns orthogonal and of one length, to
/// 1e-4 as matrices printed to 6 digits are).
fn is_similarity(m: DMat3) -> bool {
    let cols = [m.x_axis, m.y_axis, m.z_axis];
    let s = cols[0].length();
    if !(s > 0.0 && s.is_finite()) || m.determinant() <= 0.0 {
        return false;
    }
    let tol = 1e-4 * s * s;
    cols.iter().all(|c| (c.length_squared() - s * s).abs() <= tol)
        && (cols[0].dot(cols[1]).abs() <= tol && cols[0].dot(cols[2]).abs() <= tol && cols[1].dot(cols[2]).abs() <= tol)
}
