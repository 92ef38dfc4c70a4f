//! Rigid alignment of two point clouds with matched points (Kabsch).
//!
//! A free swatch has no preferred place or orientation: two relaxations
//! that differ only by a rigid motion are the same answer. Comparisons of
//! states (the error study, the reproducibility and solver-parity tests)
//! therefore measure distances after the best rigid fit of one cloud onto
//! the other, the rotation found from the SVD of the cross-covariance and
//! kept proper (no reflection).

use super::fabric::Vec3;
use nalgebra::Matrix3;

/// The rigid motion `x -> rotation * (x - from) + to` that best maps one
/// cloud onto another in the least-squares sense.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidFit {
    pub rotation: Matrix3<f64>,
    /// Centroid of the moving cloud.
    pub from: Vec3,
    /// Centroid of the target cloud.
    pub to: Vec3,
}

impl RigidFit {
    /// The best proper rigid fit of `moving` onto `target`, matched index
    /// by index; the identity for empty or mismatched clouds.
    pub fn of(moving: &[Vec3], target: &[Vec3]) -> Self {
        let (from, to) = (centroid(moving), centroid(target));
        let mut fit = RigidFit {
            rotation: Matrix3::identity(),
            from,
            to,
        };
        if moving.len() != target.len() || moving.is_empty() {
            return fit;
        }
        let cov = moving
            .iter()
            .zip(target)
            .fold(Matrix3::zeros(), |m, (p, q)| m + (p - from) * (q - to).transpose());
        let svd = cov.svd(true, true);
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            return fit;
        };
        let mut d = Matrix3::identity();
        d[(2, 2)] = (v_t.transpose() * u.transpose()).determinant().signum();
        let rotation = v_t.transpose() * d * u.transpose();
        if rotation.iter().all(|v| v.is_finite()) {
            fit.rotation = rotation;
        }
        fit
    }

    pub fn apply(&self, x: &Vec3) -> Vec3 {
        self.rotation * (x - self.from) + self.to
    }
}

fn centroid(x: &[Vec3]) -> Vec3 {
    x.iter().fold(Vec3::zeros(), |s, p| s + p) / x.len().max(1) as f64
}

/// RMS distance between matched points after the best rigid fit of `a`
/// onto `b`; `None` for empty or mismatched clouds.
pub fn aligned_rms(a: &[Vec3], b: &[Vec3]) -> Option<f64> {
    if a.len() != b.len() || a.is_empty() {
        return None;
    }
    let fit = RigidFit::of(a, b);
    let sq: f64 = a.iter().zip(b).map(|(p, q)| (fit.apply(p) - q).norm_squared()).sum();
    Some((sq / a.len() as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn cloud() -> Vec<Vec3> {
        (0..40)
            .map(|i| {
                let t = i as f64;
                Vec3::new((0.37 * t).sin(), (0.23 * t).cos() * 0.5, 0.01 * t * t)
            })
            .collect()
    }

    #[test]
    fn a_rigidly_moved_cloud_aligns_to_zero() {
        let a = cloud();
        let r = Rotation3::from_euler_angles(0.4, -1.1, 2.5);
        let b: Vec<Vec3> = a.iter().map(|p| r * p + Vec3::new(3.0, -2.0, 0.5)).collect();
        assert!(aligned_rms(&a, &b).unwrap() < 1e-12);
        let fit = RigidFit::of(&a, &b);
        assert!((fit.rotation - r.matrix()).norm() < 1e-12);
    }

    #[test]
    fn a_mirror_image_is_not_a_rigid_motion() {
        let a = cloud();
        let b: Vec<Vec3> = a.iter().map(|p| Vec3::new(-p.x, p.y, p.z)).collect();
        let rms = aligned_rms(&a, &b).unwrap();
        assert!(rms > 0.1, "{rms}");
        assert!(RigidFit::of(&a, &b).rotation.determinant() > 0.0);
    }

    #[test]
    fn a_deformation_survives_alignment() {
        let a = cloud();
        // Only the first point moves, by 1: the fit cannot absorb it all.
        let mut b = a.clone();
        b[0].x += 1.0;
        let rms = aligned_rms(&a, &b).unwrap();
        assert!(
            rms > 0.5 / (a.len() as f64).sqrt() && rms < 1.0 / (a.len() as f64).sqrt(),
            "{rms}"
        );
        assert_eq!(aligned_rms(&a, &b[1..]), None);
    }
}
