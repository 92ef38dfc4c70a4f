//! Parallel-yarn contact (docs/MODEL.md, "Parallel-yarn contact").
//!
//! Two consecutive contacts on one yarn are two other yarns crossing it.
//! They cannot come closer along it than a yarn diameter `D`, unless they can
//! pass each other. The penalty on their Eulerian coordinates is
//!
//! ```text
//! Vp = kp/2 (D - (u2 - u1))^2   for u2 - u1 < D,   0 otherwise
//! ```
//!
//! which is C1 at `u2 - u1 = D` (value and force vanish there); the Hessian
//! steps from `kp` to 0, which Newton tolerates.
//!
//! [`parallel_enabled`] decides whether the pair gets the penalty (docs/MODEL.md,
//! "Parallel-yarn contact"): never for external contacts (another fabric may pass), and not
//! when the two crossing yarns lie on opposite sides of this yarn unless one
//! of them bends around it. "Bends around" is tested with the bending
//! vector, the average of the unit directions from the contact node to the
//! crossing yarn's two neighbours: a yarn draped over this one has both
//! segments heading toward this yarn's side, so the bending vector points
//! along the contact normal (dot product above [`BEND_THRESHOLD`]). Two
//! straight yarns on opposite sides slide past each other freely.

use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};

/// The bend-vector threshold (0.25, from *Robust Eulerian-on-Lagrangian Rods*).
pub const BEND_THRESHOLD: f64 = 0.25;

/// Parallel-contact penalty on `[u1, u2]` (N = 2), `u1` the earlier contact.
#[derive(Clone, Copy, Debug)]
pub struct ParallelContact {
    /// Penalty stiffness (N/m).
    pub kp: f64,
    /// Minimal Eulerian separation, the yarn diameter (m).
    pub diameter: f64,
}

impl ParallelContact {
    pub fn new(kp: f64, diameter: f64) -> Self {
        ParallelContact { kp, diameter }
    }

    fn overlap(&self, q: &SVector<f64, 2>) -> f64 {
        (self.diameter - (q[1] - q[0])).max(0.0)
    }
}

impl Stencil<2> for ParallelContact {
    fn value(&self, q: &SVector<f64, 2>) -> f64 {
        0.5 * self.kp * self.overlap(q).powi(2)
    }
    fn gradient(&self, q: &SVector<f64, 2>) -> SVector<f64, 2> {
        let f = self.kp * self.overlap(q);
        SVector::<f64, 2>::new(f, -f)
    }
    fn hessian(&self, q: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        let k = if self.overlap(q) > 0.0 { self.kp } else { 0.0 };
        SMatrix::<f64, 2, 2>::new(k, -k, -k, k)
    }
}

/// One crossing yarn at a contact on the yarn being tested.
#[derive(Clone, Copy, Debug)]
pub struct CrossingSide {
    /// The contact is with an external object or another fabric.
    pub external: bool,
    /// Unit contact normal, from the crossing yarn toward this yarn's axis
    /// (i.e. which side the crossing yarn lies on, negated).
    pub normal: Vector3<f64>,
    /// Bending vector of the crossing yarn at the contact: the mean of the
    /// unit directions from the contact node to its two neighbours.
    pub bend: Vector3<f64>,
}

impl CrossingSide {
    /// Builds the bending vector from the crossing yarn's nodes.
    pub fn from_nodes(
        external: bool,
        normal: Vector3<f64>,
        contact: &Vector3<f64>,
        prev: &Vector3<f64>,
        next: &Vector3<f64>,
    ) -> Self {
        let dir = |p: &Vector3<f64>| (p - contact).try_normalize(0.0).unwrap_or_else(Vector3::zeros);
        CrossingSide {
            external,
            normal,
            bend: (dir(prev) + dir(next)) * 0.5,
        }
    }

    /// The yarn wraps around this one rather than passing straight by.
    pub fn bends_around(&self) -> bool {
        self.bend.dot(&self.normal) > BEND_THRESHOLD
    }
}

/// Whether two consecutive contacts on a yarn repel each other (docs/MODEL.md, "Parallel-yarn contact").
pub fn parallel_enabled(first: &CrossingSide, second: &CrossingSide) -> bool {
    if first.external || second.external {
        return false;
    }
    let opposite_sides = first.normal.dot(&second.normal) < 0.0;
    !opposite_sides || first.bends_around() || second.bends_around()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;

    #[test]
    fn penalty_by_hand_and_c1_at_diameter() {
        let p = ParallelContact::new(10.0, 1.0);
        // Separation 0.4: overlap 0.6, V = 5 * 0.36.
        let q = SVector::<f64, 2>::new(1.0, 1.4);
        assert!((p.value(&q) - 1.8).abs() < 1e-14);
        assert!((p.gradient(&q) - SVector::<f64, 2>::new(6.0, -6.0)).norm() < 1e-13);
        check_derivatives(&p, &q, 1e-6, 1e-8);
        let apart = SVector::<f64, 2>::new(0.0, 1.5);
        assert_eq!(p.value(&apart), 0.0);
        // Just inside the diameter the force is tiny: C1 at D.
        let touching = SVector::<f64, 2>::new(0.0, 1.0 - 1e-9);
        assert!(p.gradient(&touching).norm() < 1e-7);
        // Crossed contacts (u2 < u1) are pushed back apart, still finite.
        let crossed = SVector::<f64, 2>::new(0.5, 0.0);
        assert!(p.gradient(&crossed)[0] > 0.0);
    }

    /// A crossing yarn above (+z) or below this yarn, straight or draped.
    fn side(above: bool, draped: bool) -> CrossingSide {
        let s = if above { 1.0 } else { -1.0 };
        let contact = Vector3::new(0.0, 0.0, 0.0);
        // Draped: neighbours drop toward this yarn's side (-s z).
        let drop = if draped { -s } else { 0.0 };
        let prev = Vector3::new(0.0, -1.0, drop);
        let next = Vector3::new(0.0, 1.0, drop);
        CrossingSide::from_nodes(false, Vector3::new(0.0, 0.0, -s), &contact, &prev, &next)
    }

    #[test]
    fn enable_rules() {
        // Same side: they collide.
        assert!(parallel_enabled(&side(true, false), &side(true, false)));
        // Opposite sides, both straight: they pass.
        assert!(!parallel_enabled(&side(true, false), &side(false, false)));
        // Opposite sides, one wraps around this yarn: it blocks the other.
        assert!(side(false, true).bends_around());
        assert!(parallel_enabled(&side(true, false), &side(false, true)));
        // External contacts never repel.
        let mut ext = side(true, false);
        ext.external = true;
        assert!(!parallel_enabled(&ext, &side(true, false)));
        // A slight sag (bend . n = 0.1 < 0.25) is not a wrap.
        let mut slight = side(false, false);
        slight.bend = Vector3::new(0.0, 0.0, 0.1);
        assert!(!slight.bends_around());
    }
}
