//! The camera: where it is, how it projects the scene onto the image (a perspective field of
//! view or an orthographic width), and its thin lens.

use glam::DVec3;

/// The camera: its frame (`position`, looking at `look_at`, `up` towards the image's top), its
/// projection, and, for a perspective camera, an optional thin lens.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    pub projection: Projection,
    /// A thin lens (Mitsuba's `thinlens`): rays leave from a disk of this radius about
    /// `position`, across the image plane, and meet again on the plane at `focus_distance` along
    /// the view direction, so only that plane is sharp. 0: a pinhole, in focus everywhere.
    pub aperture_radius: f64,
    pub focus_distance: f64,
}

impl Camera {
    /// The field of view of a perspective camera; `None` for an orthographic one.
    pub fn fov(&self) -> Option<Fov> {
        match self.projection {
            Projection::Perspective(fov) => Some(fov),
            Projection::Orthographic { .. } => None,
        }
    }

    /// The corners of a box about every point a camera ray leaves at `width` x `height`: the
    /// pinhole alone, the square about a thin lens's disk, or an orthographic camera's rectangle
    /// (what the scene's culling must see from wherever a path begins).
    pub fn ray_origin_corners(&self, width: u32, height: u32) -> Vec<DVec3> {
        let forward = (self.look_at - self.position).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let (half_right, half_up) = match self.projection {
            Projection::Orthographic { .. } => self.projection.half_extents(width, height),
            Projection::Perspective(_) if self.aperture_radius > 0.0 => (self.aperture_radius, self.aperture_radius),
            Projection::Perspective(_) => return vec![self.position],
        };
        [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
            .into_iter()
            .map(|(a, b)| self.position + a * half_right * right + b * half_up * up)
            .collect()
    }
}

/// How the camera maps the image onto rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Rays from `position` (or from a point of the thin lens) through the image plane, framed by
    /// a field of view.
    Perspective(Fov),
    /// Parallel rays along the view direction, one from each point of a rectangle about
    /// `position`, `width` scene units across (Mitsuba's `orthographic`, whose rectangle is its
    /// `to_world`'s x scale times 2 across); its height follows from the image's aspect ratio, so
    /// a new image size keeps the width, as Mitsuba's rule keeps it.
    Orthographic { width: f64 },
}

impl Projection {
    /// Half-extents (horizontal, vertical) of the image at `width` x `height`: of the image plane
    /// at distance 1 for a perspective camera, of the rectangle the rays leave for an
    /// orthographic one (in scene units).
    pub fn half_extents(self, width: u32, height: u32) -> (f64, f64) {
        match self {
            Projection::Perspective(fov) => fov.half_extents(width, height),
            Projection::Orthographic { width: across } => {
                let half = across / 2.0;
                (half, half * height.max(1) as f64 / width.max(1) as f64)
            }
        }
    }
}

/// Field of view in degrees along one image axis, or by one of Mitsuba's other `fov_axis`
/// rules; the other angle follows from the image's aspect ratio. The rule is kept, not resolved
/// at load, so that a new image size frames the scene as Mitsuba would frame it at that size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fov {
    X(f64),
    Y(f64),
    /// Along the shorter side (`fov_axis="smaller"`; the horizontal one on a square image).
    Smaller(f64),
    /// Along the longer side (`fov_axis="larger"`; the horizontal one on a square image).
    Larger(f64),
    /// Along the image diagonal (`fov_axis="diagonal"`).
    Diagonal(f64),
}

impl Fov {
    /// The same field of view at a `width` x `height` image, as an angle along x or along y.
    pub fn resolve(self, width: u32, height: u32) -> Fov {
        let (w, h) = (width.max(1) as f64, height.max(1) as f64);
        match self {
            Fov::X(_) | Fov::Y(_) => self,
            Fov::Smaller(deg) => if w <= h { Fov::X(deg) } else { Fov::Y(deg) },
            Fov::Larger(deg) => if w >= h { Fov::X(deg) } else { Fov::Y(deg) },
            // tan(fov_x / 2) = tan(fov_d / 2) w / sqrt(w^2 + h^2).
            Fov::Diagonal(deg) => {
                let half = (deg.to_radians() / 2.0).tan();
                Fov::X(2.0 * (half * w / (w * w + h * h).sqrt()).atan().to_degrees())
            }
        }
    }

    /// Half-extents (horizontal, vertical) of the image plane at distance 1, at `width` x `height`.
    pub fn half_extents(self, width: u32, height: u32) -> (f64, f64) {
        let (w, h) = (width as f64, height as f64);
        match self.resolve(width, height) {
            Fov::X(deg) => {
                let hw = (deg.to_radians() / 2.0).tan();
                (hw, hw * h / w)
            }
            Fov::Y(deg) => {
                let hh = (deg.to_radians() / 2.0).tan();
                (hh * w / h, hh)
            }
            _ => unreachable!("resolve gives an angle along x or y"),
        }
    }

    /// The full angles (horizontal, vertical) in degrees at `width` x `height`.
    pub fn angles(self, width: u32, height: u32) -> (f64, f64) {
        let (hw, hh) = self.half_extents(width, height);
        (2.0 * hw.atan().to_degrees(), 2.0 * hh.atan().to_degrees())
    }

    /// The angle as written, in degrees.
    pub fn degrees(self) -> f64 {
        match self {
            Fov::X(d) | Fov::Y(d) | Fov::Smaller(d) | Fov::Larger(d) | Fov::Diagonal(d) => d,
        }
    }

    /// The scene-file key that gives this field of view (`fov_x`, ..., `fov_diagonal`).
    pub fn key(self) -> &'static str {
        match self {
            Fov::X(_) => "fov_x",
            Fov::Y(_) => "fov_y",
            Fov::Smaller(_) => "fov_smaller",
            Fov::Larger(_) => "fov_larger",
            Fov::Diagonal(_) => "fov_diagonal",
        }
    }
}

