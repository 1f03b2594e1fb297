//! Changes to a loaded scene's render settings that every front-end offers (the CLI's
//! `--width`, `--height`, `--size`, `--max-depth`, `--rr-depth`; Python's `load_scene` and
//! `Scene.with_` keywords), checked in one place before any GPU work. A new size with another
//! aspect ratio changes what the camera sees; `apply` says how (`Reframing`), for the
//! front-end to tell once.

use std::fmt;

use super::{Fov, Projection, Scene};

/// Render settings to replace; `None` keeps the scene's.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Overrides {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
    /// `Some(None)`: Russian roulette off; `Some(Some(k))`: from scattering vertex `k` (>= 1).
    pub rr_depth: Option<Option<u32>>,
    /// Default samples per pixel of the scene (`render.spp`).
    pub spp: Option<u64>,
}

/// An override whose value is impossible; `field` is the setting's name in the scene file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{field} must be {requirement}")]
pub struct OverrideError {
    pub field: &'static str,
    pub requirement: &'static str,
}

impl Overrides {
    /// Checks every value, then applies them all (or none). Returns how the framing changes
    /// where the new size has another aspect ratio than the scene's.
    pub fn apply(&self, scene: &mut Scene) -> Result<Option<Reframing>, OverrideError> {
        let at_least_one = |field: &'static str, value: Option<u64>| match value {
            Some(0) => Err(OverrideError { field, requirement: "at least 1" }),
            _ => Ok(()),
        };
        at_least_one("width", self.width.map(u64::from))?;
        at_least_one("height", self.height.map(u64::from))?;
        at_least_one("max_depth", self.max_depth.map(u64::from))?;
        at_least_one("spp", self.spp)?;
        if self.rr_depth == Some(Some(0)) {
            return Err(OverrideError { field: "rr_depth", requirement: "at least 1 (the first scattering vertex is 1), or off" });
        }
        let r = &mut scene.render;
        let from = (r.width, r.height);
        r.width = self.width.unwrap_or(r.width);
        r.height = self.height.unwrap_or(r.height);
        r.max_depth = self.max_depth.unwrap_or(r.max_depth);
        r.rr_depth = self.rr_depth.unwrap_or(r.rr_depth);
        r.spp = self.spp.or(r.spp);
        Ok(Reframing::of(from, (r.width, r.height), scene.camera.projection))
    }
}

/// A new image size whose aspect ratio is not the scene's (to a pixel's rounding): the camera
/// keeps the field of view its `fov_axis` names (Mitsuba's rule, applied at the new size), or an
/// orthographic camera its width, so the other extent changes and the image shows more or less
/// of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reframing {
    pub from: (u32, u32),
    pub to: (u32, u32),
    pub projection: Projection,
}

impl Reframing {
    /// The change from `from` to `to`, or `None` where `to` is `from`'s aspect ratio rounded to
    /// whole pixels (`--quick`'s 128x72 for 1920x1080 keeps the framing).
    pub fn of(from: (u32, u32), to: (u32, u32), projection: Projection) -> Option<Reframing> {
        let (fw, fh) = (from.0 as f64, from.1 as f64);
        let (tw, th) = (to.0 as f64, to.1 as f64);
        let same = (tw * fh / fw - th).abs() <= 0.5 || (th * fw / fh - tw).abs() <= 0.5;
        (!same).then_some(Reframing { from, to, projection })
    }

    /// What the rule keeps, in words.
    fn kept(&self) -> String {
        let fov = match self.projection {
            Projection::Perspective(fov) => fov,
            Projection::Orthographic { .. } => return "the orthographic view's width".into(),
        };
        let resolved = fov.resolve(self.to.0, self.to.1);
        let side = if matches!(resolved, Fov::X(_)) { "horizontal" } else { "vertical" };
        match fov {
            Fov::X(_) => "the horizontal field of view (fov_x)".into(),
            Fov::Y(_) => "the vertical field of view (fov_y)".into(),
            Fov::Smaller(_) => format!("the shorter side's field of view (fov_axis \"smaller\", now the {side} one)"),
            Fov::Larger(_) => format!("the longer side's field of view (fov_axis \"larger\", now the {side} one)"),
            Fov::Diagonal(_) => "the diagonal field of view (fov_axis \"diagonal\")".into(),
        }
    }
}

impl fmt::Display for Reframing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Angles of a perspective camera's view, in degrees; extents of an orthographic one's.
        let (extents, unit, digits) = match self.projection {
            Projection::Perspective(fov) => ((fov.angles(self.from.0, self.from.1), fov.angles(self.to.0, self.to.1)), "°", 1),
            Projection::Orthographic { .. } => {
                let full = |(w, h): (u32, u32)| {
                    let (hw, hh) = self.projection.half_extents(w, h);
                    (2.0 * hw, 2.0 * hh)
                };
                ((full(self.from), full(self.to)), " scene units", 3)
            }
        };
        let ((h0, v0), (h1, v1)) = extents;
        // Changes too small to print at the precision shown are no change.
        let tol = if digits == 1 { 0.05 } else { 5e-4 };
        let change = |a: f64, b: f64, where_: &str| {
            if (a - b).abs() < tol {
                None
            } else {
                Some(format!("{} is seen {where_}", if b > a { "more" } else { "less" }))
            }
        };
        let changes: Vec<String> =
            [change(h0, h1, "left and right"), change(v0, v1, "above and below")].into_iter().flatten().collect();
        write!(
            f,
            "{}x{} has another aspect ratio than the scene's {}x{}, so the framing changes: the camera keeps {}, \
             and sees {h1:.digits$}{unit} x {v1:.digits$}{unit} instead of {h0:.digits$}{unit} x {v0:.digits$}{unit}",
            self.to.0,
            self.to.1,
            self.from.0,
            self.from.1,
            self.kept()
        )?;
        if !changes.is_empty() {
            write!(f, " ({})", changes.join(", "))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_scene(fov: &str) -> Scene {
        let text = format!(
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\n{fov}\n\
             [render]\nwidth = 256\nheight = 256\nmax_depth = 2\n\
             [materials.grey]\ndiffuse = 0.5\n\
             [[planes]]\npoint = [0, -2, 0]\nnormal = [0, 1, 0]\nmaterial = \"grey\"\n"
        );
        Scene::parse(&text, "test.toml").unwrap()
    }

    fn resized(fov: &str, width: u32, height: u32) -> (Scene, Option<Reframing>) {
        let mut s = square_scene(fov);
        let r = Overrides { width: Some(width), height: Some(height), ..Overrides::default() }.apply(&mut s).unwrap();
        (s, r)
    }

    #[test]
    fn a_size_of_the_same_aspect_ratio_keeps_the_framing() {
        assert_eq!(resized("fov_x = 40", 128, 128).1, None);
        assert_eq!(resized("fov_x = 40", 1, 1).1, None);
        // A 1920x1080 scene at 128x72 (exact) and at 100x56 (56.25 rounded) keeps its framing.
        assert_eq!(Reframing::of((1920, 1080), (128, 72), Projection::Perspective(Fov::X(40.0))), None);
        assert_eq!(Reframing::of((1920, 1080), (100, 56), Projection::Perspective(Fov::X(40.0))), None);
        assert!(Reframing::of((1920, 1080), (100, 50), Projection::Perspective(Fov::X(40.0))).is_some());
    }

    #[test]
    fn another_aspect_ratio_keeps_the_angle_the_fov_axis_names() {
        // fov_x: the horizontal 40 degrees stay; the vertical narrows.
        let (s, r) = resized("fov_x = 40", 128, 64);
        let r = r.expect("a reframing");
        let (h, v) = s.camera.fov().unwrap().angles(128, 64);
        assert!((h - 40.0).abs() < 1e-9 && v < 40.0, "{h} {v}");
        let text = r.to_string();
        assert!(text.contains("128x64 has another aspect ratio than the scene's 256x256"), "{text}");
        assert!(text.contains("the horizontal field of view (fov_x)") && text.contains("less is seen above and below"), "{text}");
        assert!(!text.contains("left and right"), "{text}");
        // fov_y: the vertical stays; the horizontal widens.
        let text = resized("fov_y = 40", 128, 64).1.unwrap().to_string();
        assert!(text.contains("(fov_y)") && text.contains("more is seen left and right") && !text.contains("above"), "{text}");
        // smaller: on a wide image the shorter side is the vertical one, which keeps the angle
        // (on the square original it was the horizontal one, by Mitsuba's rule).
        let (s, r) = resized("fov_smaller = 40", 128, 64);
        let (_, v) = s.camera.fov().unwrap().angles(128, 64);
        assert!((v - 40.0).abs() < 1e-9, "{v}");
        assert!(r.unwrap().to_string().contains("now the vertical one"));
        let (s, _) = resized("fov_larger = 40", 64, 128);
        assert!((s.camera.fov().unwrap().angles(64, 128).1 - 40.0).abs() < 1e-9);
        // diagonal: the diagonal's angle stays, both sides change.
        let (s, r) = resized("fov_diagonal = 60", 200, 100);
        let (hw, hh) = s.camera.fov().unwrap().half_extents(200, 100);
        assert!(((hw * hw + hh * hh).sqrt() - 30f64.to_radians().tan()).abs() < 1e-12);
        let text = r.unwrap().to_string();
        assert!(text.contains("more is seen left and right") && text.contains("less is seen above and below"), "{text}");
    }
}
