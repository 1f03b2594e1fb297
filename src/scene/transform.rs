//! Object-to-world transforms of meshes and built-in shapes.
//!
//! Written as `scale`, `rotate` and `translate`, applied in that order (x' = T R S x, as
//! Mitsuba's `T.translate(..) @ T.rotate(..) @ T.scale(..)`); a list of rotations applies in
//! the order written, as consecutive `<rotate>` elements of a Mitsuba XML `<transform>` do.
//! Or a 4x4 `matrix`, row-major as Mitsuba's `<matrix value="...">`, whose last row must be
//! 0 0 0 1 (affine).

use glam::{DMat3, DMat4, DVec3};

/// An affine, invertible map from object to world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    pub matrix: DMat4,
}

impl Default for Transform {
    fn default() -> Self {
        Transform { matrix: DMat4::IDENTITY }
    }
}

/// Why a transform is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransformError {
    #[error("must be finite (got {0})")]
    NotFinite(f64),
    #[error("the rotation axis must be a non-zero vector")]
    ZeroAxis,
    #[error("the last row of the matrix must be 0 0 0 1 (only affine transforms are supported)")]
    NotAffine,
    #[error("give either `matrix` or translate/rotate/scale, not both")]
    MatrixAndParts,
    #[error("the transform is singular (determinant {0:e}): it flattens the shape")]
    Singular(f64),
}

fn finite(values: &[f64]) -> Result<(), TransformError> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(&v) => Err(TransformError::NotFinite(v)),
        None => Ok(()),
    }
}

impl Transform {
    /// T R_k .. R_1 S from the parts (rotations in the order written), checked.
    pub fn from_parts(translate: DVec3, rotations: &[(DVec3, f64)], scale: DVec3) -> Result<Transform, TransformError> {
        finite(&translate.to_array())?;
        finite(&scale.to_array())?;
        let mut m = DMat4::from_scale(scale);
        for &(axis, degrees) in rotations {
            finite(&axis.to_array())?;
            finite(&[degrees])?;
            let length = axis.length();
            if !(length > 0.0) || !length.is_finite() {
                return Err(TransformError::ZeroAxis);
            }
            m = DMat4::from_axis_angle(axis / length, degrees.to_radians()) * m;
        }
        Transform { matrix: DMat4::from_translation(translate) * m }.checked()
    }

    /// From a row-major 4x4 matrix, checked.
    pub fn from_rows(rows: [[f64; 4]; 4]) -> Result<Transform, TransformError> {
        for row in &rows {
            finite(row)?;
        }
        if rows[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(TransformError::NotAffine);
        }
        Transform { matrix: DMat4::from_cols_array_2d(&rows).transpose() }.checked()
    }

    /// Refuses a singular linear part: relative to the lengths of its columns, so that a tiny
    /// but well-shaped scale passes and a projection onto a plane does not.
    fn checked(self) -> Result<Transform, TransformError> {
        let l = self.linear();
        let det = l.determinant();
        let scale = l.x_axis.length() * l.y_axis.length() * l.z_axis.length();
        if !(det.abs() > 1e-12 * scale) || !det.is_finite() {
            return Err(TransformError::Singular(det));
        }
        Ok(self)
    }

    fn linear(&self) -> DMat3 {
        DMat3::from_mat4(self.matrix)
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.matrix.transform_point3(p)
    }

    /// A normal maps by the inverse transpose of the linear part (then renormalised).
    pub fn normal(&self, n: DVec3) -> DVec3 {
        (self.linear().inverse().transpose() * n).normalize_or_zero()
    }

    /// True when the transform mirrors (negative determinant): triangle windings are then
    /// reversed so that each face keeps the side its transformed normal points to.
    pub fn swaps_handedness(&self) -> bool {
        self.linear().determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_then_rotate_then_translate() {
        // Mitsuba's Cornell box light: translate(0, 0.99, 0.01) rotate(x, 90) scale(0.23, 0.19, 0.19).
        let t = Transform::from_parts(DVec3::new(0.0, 0.99, 0.01), &[(DVec3::X, 90.0)], DVec3::new(0.23, 0.19, 0.19)).unwrap();
        let p = t.point(DVec3::new(1.0, 1.0, 0.0));
        assert!((p - DVec3::new(0.23, 0.99, 0.01 + 0.19)).length() < 1e-12, "{p}");
        // The rectangle's +z normal turns to face down.
        assert!((t.normal(DVec3::Z) - DVec3::NEG_Y).length() < 1e-12);
        let rows = [[2.0, 0.0, 0.0, 1.0], [0.0, 3.0, 0.0, 2.0], [0.0, 0.0, 4.0, 3.0], [0.0, 0.0, 0.0, 1.0]];
        let m = Transform::from_rows(rows).unwrap();
        assert_eq!(m.point(DVec3::ONE), DVec3::new(3.0, 5.0, 7.0));
    }

    #[test]
    fn singular_projective_and_non_finite_transforms_are_refused() {
        assert!(matches!(Transform::from_parts(DVec3::ZERO, &[], DVec3::new(1.0, 0.0, 1.0)), Err(TransformError::Singular(_))));
        assert!(Transform::from_parts(DVec3::ZERO, &[], DVec3::splat(1e-9)).is_ok(), "tiny but invertible");
        assert_eq!(Transform::from_parts(DVec3::ZERO, &[(DVec3::ZERO, 5.0)], DVec3::ONE), Err(TransformError::ZeroAxis));
        assert!(matches!(Transform::from_parts(DVec3::new(f64::NAN, 0.0, 0.0), &[], DVec3::ONE), Err(TransformError::NotFinite(_))));
        let mut rows = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 1.0, 1.0]];
        assert_eq!(Transform::from_rows(rows), Err(TransformError::NotAffine));
        rows[3] = [0.0, 0.0, 0.0, 1.0];
        rows[2] = [1.0, 0.0, 0.0, 0.0];
        assert!(matches!(Transform::from_rows(rows), Err(TransformError::Singular(_))));
        assert!(Transform::from_parts(DVec3::ZERO, &[], DVec3::new(-1.0, 1.0, 1.0)).unwrap().swaps_handedness());
    }
}
