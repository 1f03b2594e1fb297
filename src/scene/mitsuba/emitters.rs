//! Mitsuba's delta emitters, `point`, `spot` and `directional`, read into `[[point_lights]]`,
//! `[[spot_lights]]` and `[[directional_lights]]` (`scene::emitters::{point, spot,
//! directional}`), with their parameters, defaults and frames as Mitsuba 3.9.1 reads them
//! (`src/emitters/point.cpp`, `spot.cpp`, `directional.cpp`).

use glam::{DMat3, DVec3};

use super::super::raw::{RawColor, RawDirectionalLight, RawPointLight, RawSpotLight};
use super::super::diagnostic::Findings;
use super::super::spectrum::SpectrumRole;
use super::xml::{compose, Object};
use super::{spanned, Props, Translator};
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

    /// `<emitter type="spot">`: `to_world` (its translation the position, its +z the axis; a
    /// rotation with a uniform scale, as `lookat` gives), `intensity`, `cutoff_angle` and
    /// `beam_width` in degrees. A projected `texture` is refused.
    pub(super) fn spot_emitter(&mut self, o: &Object) -> Option<Spanned<RawSpotLight>> {
        let mut p = Props::of(o);
        let frame = self.frame(&mut p);
        let intensity = self.delta_emission(&mut p, "intensity", o);
        let cutoff = self.get::<f64>(&mut p, "cutoff_angle").map(|(v, prop)| spanned(prop.value_at, v));
        let beam = self.get::<f64>(&mut p, "beam_width").map(|(v, prop)| spanned(prop.value_at, v));
        self.finish(p, "to_world, intensity, cutoff_angle, beam_width");
        for c in &o.children {
            let what = if c.name.as_deref() == Some("texture") { "a projected `texture`".to_string() } else { super::describe(&c.tag, &c.plugin) };
            self.error(c.at, c.name.as_deref().unwrap_or(""), format!("{what} of a spot emitter is not supported"));
        }
        let (linear, position) = match frame {
            None => (DMat3::IDENTITY, DVec3::ZERO),
            Some((linear, t, at)) => {
                if !is_similarity(linear) {
                    self.error(at, "to_world", "the `to_world` of a spot emitter must be a rotation with a uniform scale (its falloff is measured in angles about its axis)".to_string());
                    return None;
                }
                (linear, t)
            }
        };
        let direction = (linear * DVec3::Z).normalize();
        Some(spanned(
            o.at,
            RawSpotLight {
                position: spanned(o.at, position.to_array()),
                direction: spanned(o.at, direction.to_array()),
                intensity,
                cutoff_angle: cutoff,
                beam_width: beam,
            },
        ))
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
