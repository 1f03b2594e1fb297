//! Quadrics: Mitsuba 3's analytic `disk` and `cylinder` (pbrt-v4's "other quadrics"), exact
//! surfaces intersected in object space, one file per kind (`disk.rs`, `cylinder.rs`, and
//! `shaders/quadrics/<kind>.wgsl`). Each is a unit shape in its object space placed by an affine
//! `to_world`: the disk x^2 + y^2 <= 1 at z = 0, the open cylinder x^2 + y^2 = 1 for
//! 0 <= z <= 1 (no end caps). The host functions here are the reference the kernel's are tested
//! against, and give a light's area and power.
//!
//! The kernel tests every quadric per ray (`NUM_DISKS`, `NUM_CYLINDERS`, `NUM_CURVE_SEGMENTS`;
//! there is no acceleration structure for them), disks first, each kind's lights first.
//!
//! The segments of Mitsuba's `linearcurve` (`linear_curve.rs`) share the quadrics' records and
//! loops: each is a sphere swept along a segment, given by its ends and radii (`curve`), not an
//! affine image of a unit shape (its `to_world` is the identity), and so are the segments of
//! Mitsuba's `bsplinecurve` (`bspline_curve.rs`: `BsplineSegment`). So do Mitsuba's `sdfgrid`s
//! (`sdf_grid.rs`): a signed distance grid on the unit cube of the object space its `to_world`
//! places, its values in the BSDF data (`SdfGrid`).

mod bspline_curve;
mod cylinder;
mod disk;
mod linear_curve;
mod sdf_grid;

pub use bspline_curve::{bspline_segments, BsplineSegment, BSPLINE_NEWTON_STEPS, BSPLINE_PIECES, BSPLINE_V_SLACK};
pub use linear_curve::{angle_frame, read_curves, segments, CurveSegment};
pub use sdf_grid::{SdfGrid, REGULA_FALSI_STEPS};

use std::sync::Arc;

use glam::{DAffine3, DMat3, DVec3};

use crate::names::named_enum;

/// Most quadrics a scene may have (128 bytes each in a uniform buffer).
pub const MAX_QUADRICS: usize = 256;

named_enum! {
    /// The kind of a quadric.
    pub enum QuadricKind("quadric kind") {
        /// Mitsuba's `disk`: the unit disk at z = 0 in object space, its normal +z.
        Disk = "disk",
        /// Mitsuba's `cylinder`: the open unit cylinder from z = 0 to z = 1, normals outwards.
        Cylinder = "cylinder",
        /// One segment of Mitsuba's `linearcurve`: a sphere swept along it (`CurveSegment`).
        CurveSegment = "curve segment",
        /// One segment of Mitsuba's `bsplinecurve`: circles swept along a cubic B-spline
        /// (`BsplineSegment`).
        BsplineSegment = "B-spline segment",
        /// Mitsuba's `sdfgrid`: the zero set of a signed distance grid on the unit cube
        /// (`SdfGrid`).
        SdfGrid = "sdf grid",
    }
}

/// A disk or cylinder in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct Quadric {
    pub kind: QuadricKind,
    /// Object to world, affine and invertible (a cylinder's `p0`, `p1` and `radius` folded in,
    /// as Mitsuba does).
    pub to_world: DAffine3,
    /// Mitsuba's `flip_normals`: the normal (and the side an emitter emits on) turned around.
    pub flip_normals: bool,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// Emits on both sides (pathlab's `two_sided_emission`; Mitsuba's area emitters emit on the
    /// normal's side only).
    pub two_sided_emission: bool,
    /// What it holds beyond its kind's unit shape.
    pub data: QuadricData,
}

/// What a quadric holds beyond the unit shape of its kind.
#[derive(Debug, Clone, PartialEq)]
pub enum QuadricData {
    /// A disk or a cylinder: its `to_world` is all.
    Unit,
    /// A curve segment's ends and radii (`QuadricKind::CurveSegment`).
    Curve(CurveSegment),
    /// A B-spline segment's control points (`QuadricKind::BsplineSegment`).
    Bspline(BsplineSegment),
    /// An SDF grid's values (`QuadricKind::SdfGrid`), shared by the quadrics that place one file.
    Grid(Arc<SdfGrid>),
}

impl Quadric {
    /// World to object.
    pub fn to_object(&self) -> DAffine3 {
        self.to_world.inverse()
    }

    /// Surface area in world space.
    pub fn area(&self) -> f64 {
        match self.kind {
            QuadricKind::Disk => disk::area(self),
            QuadricKind::Cylinder => cylinder::area(self),
            // Never lights (as in Mitsuba, which cannot sample their positions).
            QuadricKind::CurveSegment | QuadricKind::BsplineSegment | QuadricKind::SdfGrid => 0.0,
        }
    }

    /// A curve segment's ends and radii.
    pub fn curve(&self) -> Option<&CurveSegment> {
        match &self.data {
            QuadricData::Curve(c) => Some(c),
            _ => None,
        }
    }

    /// A B-spline segment's control points.
    pub fn bspline(&self) -> Option<&BsplineSegment> {
        match &self.data {
            QuadricData::Bspline(s) => Some(s),
            _ => None,
        }
    }

    /// An SDF grid's values.
    pub fn grid(&self) -> Option<&Arc<SdfGrid>> {
        match &self.data {
            QuadricData::Grid(g) => Some(g),
            _ => None,
        }
    }

    fn segment(&self) -> &CurveSegment {
        self.curve().expect("a curve segment has its segment")
    }

    fn bspline_segment(&self) -> &BsplineSegment {
        self.bspline().expect("a B-spline segment has its control points")
    }

    /// An SDF grid's values (of a quadric of kind `SdfGrid`).
    pub fn sdf_grid(&self) -> &SdfGrid {
        self.grid().expect("an SDF grid has its values")
    }

    /// Nearest ray parameter t in (t_min, t_max) where the ray o + t d meets the surface.
    pub fn intersect(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let m = self.to_object();
        let (ol, dl) = (m.transform_point3(o), m.transform_vector3(d));
        match self.kind {
            QuadricKind::Disk => disk::intersect(ol, dl, t_min, t_max),
            QuadricKind::Cylinder => cylinder::intersect(ol, dl, t_min, t_max),
            QuadricKind::CurveSegment => self.segment().intersect(o, d, t_min, t_max),
            QuadricKind::BsplineSegment => self.bspline_segment().intersect(o, d, t_min, t_max).map(|(t, _)| t),
            QuadricKind::SdfGrid => self.sdf_grid().intersect(ol, dl, t_min, t_max),
        }
    }

    /// The unit surface normal at world point `p` of the surface (flip_normals applied).
    pub fn normal(&self, p: DVec3) -> DVec3 {
        let local = self.to_object().transform_point3(p);
        let n_object = match self.kind {
            QuadricKind::Disk => DVec3::Z,
            QuadricKind::Cylinder => DVec3::new(local.x, local.y, 0.0),
            QuadricKind::CurveSegment => return self.segment().normal(p),
            QuadricKind::BsplineSegment => {
                let s = self.bspline_segment();
                return s.normal_at(p, s.v_of(p));
            }
            QuadricKind::SdfGrid => self.sdf_grid().gradient(local),
        };
        let n = normal_to_world(&self.to_world, n_object);
        if self.flip_normals { -n } else { n }
    }

    /// The unit shading normal at world point `p` of the surface: an SDF grid's smooth normal
    /// where it has `normals = "smooth"` (0 where the blend of its cells' normals cancels),
    /// else the surface normal.
    pub fn shading_normal(&self, p: DVec3) -> DVec3 {
        match self.grid() {
            Some(g) if g.smooth => {
                let n = g.smooth_normal(self.to_object().transform_point3(p));
                let inverse_transpose: DMat3 = DMat3::from(self.to_world.matrix3).inverse().transpose();
                (inverse_transpose * n).normalize_or_zero()
            }
            _ => self.normal(p),
        }
    }

    /// Mitsuba's uv parametrisation at world point `p` of the surface.
    pub fn uv(&self, p: DVec3) -> [f64; 2] {
        let local = self.to_object().transform_point3(p);
        match self.kind {
            QuadricKind::Disk => disk::uv(local),
            QuadricKind::Cylinder => cylinder::uv(local),
            QuadricKind::CurveSegment => self.segment().uv(p),
            QuadricKind::BsplineSegment => {
                let s = self.bspline_segment();
                s.uv_at(p, s.v_of(p))
            }
            // No parametrisation (Mitsuba's uv 0).
            QuadricKind::SdfGrid => [0.0, 0.0],
        }
    }

    /// The corners of a box around it in world space: the image of its object space's
    /// [-1, 1]^2 x [0, 0] (a disk) or [0, 1] (a cylinder), or [0, 1]^3 (an SDF grid).
    pub fn box_corners(&self) -> [DVec3; 8] {
        if let Some(c) = self.curve() {
            return c.box_corners();
        }
        if let Some(s) = self.bspline() {
            return s.box_corners();
        }
        let top = if self.kind == QuadricKind::Disk { 0.0 } else { 1.0 };
        let low = if self.kind == QuadricKind::SdfGrid { 0.0 } else { -1.0 };
        std::array::from_fn(|c| {
            let corner = DVec3::new(if c & 1 == 0 { low } else { 1.0 }, if c & 2 == 0 { low } else { 1.0 }, if c & 4 == 0 { 0.0 } else { top });
            self.to_world.transform_point3(corner)
        })
    }

    /// The point of the surface that Mitsuba's `sample_position` gives for `u` in [0, 1)^2
    /// (uniform in area).
    pub fn sample_position(&self, u: [f64; 2]) -> DVec3 {
        let local = match self.kind {
            QuadricKind::Disk => disk::sample_local(u),
            QuadricKind::Cylinder => cylinder::sample_local(u),
            // Never lights: no position to sample.
            QuadricKind::CurveSegment => return self.segment().p0,
            QuadricKind::BsplineSegment => return self.bspline_segment().at(0.5).c,
            QuadricKind::SdfGrid => DVec3::splat(0.5),
        };
        self.to_world.transform_point3(local)
    }
}

/// A normal of object space in world space: the inverse transpose of the linear part, then
/// normalised (Mitsuba's `Transform * Normal3f`).
pub fn normal_to_world(to_world: &DAffine3, n: DVec3) -> DVec3 {
    let inverse_transpose: DMat3 = DMat3::from(to_world.matrix3).inverse().transpose();
    (inverse_transpose * n).normalize()
}

/// The smaller and larger roots of a t^2 + b t + c = 0 in the numerically stable form (Mitsuba's
/// `math::solve_quadratic`): q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2, roots q / a and c / q; the
/// linear case where a = 0. None where there is no real root.
pub fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let t = -c / b;
        return Some((t, t));
    }
    let discriminant = b * b - 4.0 * a * c;
    if discriminant < 0.0 {
        return None;
    }
    let q = -0.5 * (b + b.signum() * discriminant.sqrt());
    let (t0, t1) = (q / a, c / q);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// The frame Mitsuba's `coordinate_system` builds about a unit `n` (Duff et al. 2017): the
/// tangent s, the bitangent t; `(s, t, n)` is what `ScalarAffineTransform4f::to_frame` maps
/// x, y, z to.
pub fn coordinate_system(n: DVec3) -> (DVec3, DVec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    (s, t)
}

/// A cylinder's `to_world` from Mitsuba's `p0`, `p1`, `radius` and its own `to_world`:
/// to_world * translate(p0) * to_frame(frame about (p1 - p0) / |p1 - p0|) * scale(r, r, |p1 - p0|).
pub fn cylinder_to_world(to_world: DAffine3, p0: DVec3, p1: DVec3, radius: f64) -> DAffine3 {
    let d = p1 - p0;
    let length = d.length();
    let n = d / length;
    let (s, t) = coordinate_system(n);
    let frame = DAffine3::from_mat3(DMat3::from_cols(s, t, n));
    to_world * DAffine3::from_translation(p0) * frame * DAffine3::from_scale(DVec3::new(radius, radius, length))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quadric(kind: QuadricKind, to_world: DAffine3) -> Quadric {
        Quadric { kind, to_world, flip_normals: false, material: 0, two_sided_emission: false, data: QuadricData::Unit }
    }

    #[test]
    fn a_sheared_disk_has_the_area_of_its_ellipse_and_its_samples_lie_on_it() {
        let m = DAffine3::from_cols_array(&[1.5, 0.0, 0.0, 0.7, 2.5, 0.3, 0.1, 0.2, 1.0, 4.0, -1.0, 2.0]);
        let q = quadric(QuadricKind::Disk, m);
        let x = m.matrix3.x_axis;
        let y = m.matrix3.y_axis;
        assert!((q.area() - std::f64::consts::PI * x.cross(y).length()).abs() < 1e-12);
        for u in [[0.1, 0.2], [0.9, 0.4], [0.5, 0.5], [0.33, 0.99]] {
            let p = q.sample_position(u);
            let n = q.normal(p);
            // On the disk's plane, inside its rim.
            assert!((p - m.translation).dot(n).abs() < 1e-12);
            let local = q.to_object().transform_point3(p);
            assert!(local.x * local.x + local.y * local.y <= 1.0 + 1e-12);
        }
    }

    #[test]
    fn a_ray_meets_a_cylinder_on_its_near_side_and_from_inside_on_its_far_side() {
        let q = quadric(QuadricKind::Cylinder, cylinder_to_world(DAffine3::IDENTITY, DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, 1.0), 2.0));
        let t = q.intersect(DVec3::new(-5.0, 0.0, 0.0), DVec3::X, 0.0, f64::INFINITY).unwrap();
        assert!((t - 3.0).abs() < 1e-12);
        assert!((q.normal(DVec3::new(-2.0, 0.0, 0.0)) - DVec3::NEG_X).length() < 1e-12);
        let t = q.intersect(DVec3::ZERO, DVec3::X, 0.0, f64::INFINITY).unwrap();
        assert!((t - 2.0).abs() < 1e-12);
        // Past its end: no end caps.
        assert!(q.intersect(DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z, 0.0, f64::INFINITY).is_none());
        assert!((q.area() - 2.0 * std::f64::consts::PI * 2.0 * 2.0).abs() < 1e-12);
    }
}
