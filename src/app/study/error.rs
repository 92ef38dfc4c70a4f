//! The study's error measures: how far one relaxed state lies from the
//! reference state.
//!
//! EoL contact nodes slide along their yarns, so two relaxations of one
//! pattern do not put node `i` at the same material point: comparing node
//! indices would report sliding as error even where the yarn has not moved.
//! The distance is therefore taken between *material points*: each yarn is
//! sampled at fixed material coordinates `u` (chosen once, from the
//! reference), and each state's position at `u` is interpolated linearly
//! along that yarn's points sorted by `u` (EIL points at their
//! interpolated positions, `Fabric::point_position`). The RMS over all
//! samples, in yarn radii, is the shape error.
//!
//! Distances are taken after the best rigid fit of the run's samples onto
//! the reference's (`topology::align`): a free swatch may turn or drift
//! while it relaxes, and where it ends up in space is not part of its
//! shape.
//!
//! The shape of the swatch as a whole is measured by its extents along its
//! own frame (`StitchGrid::extents`: width along the courses, height along
//! the wales, depth across the fabric; the lab bounding box for fabrics
//! without a stitch grid), each as a signed percentage of the reference's
//! extent. The energy error is the signed relative difference of the total
//! potential energies.

use crate::topology::align::RigidFit;
use crate::topology::{Fabric, PointRef, StitchGrid, Vec3};

/// Material coordinates at which each yarn is sampled, yarn by yarn.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSamples {
    pub u: Vec<Vec<f64>>,
}

impl MaterialSamples {
    /// `per_segment` evenly spaced samples per point-to-point segment of
    /// each `reference` yarn, over the yarn's `u` range, both ends included.
    pub fn of(reference: &Fabric, per_segment: usize) -> Self {
        let per_segment = per_segment.max(1);
        let u = reference
            .yarns
            .iter()
            .map(|y| {
                let (Some(first), Some(last)) = (y.points.first(), y.points.last()) else {
                    return Vec::new();
                };
                let n = per_segment * y.points.len().saturating_sub(1).max(1);
                (0..=n)
                    .map(|k| first.u + (last.u - first.u) * k as f64 / n as f64)
                    .collect()
            })
            .collect();
        MaterialSamples { u }
    }

    pub fn len(&self) -> usize {
        self.u.iter().map(Vec::len).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Why two states cannot be compared.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CompareError {
    #[error("the states have {0} and {1} yarns")]
    YarnCount(usize, usize),
    #[error("yarn {0} has no points")]
    EmptyYarn(usize),
    #[error("no material samples to compare")]
    NoSamples,
}

/// One yarn's centre line as `(u, x)` pairs sorted by `u`.
fn centre_line(f: &Fabric, yarn: usize) -> Vec<(f64, Vec3)> {
    let mut pts: Vec<(f64, Vec3)> = (0..f.yarns[yarn].points.len())
        .map(|point| {
            (
                f.yarns[yarn].points[point].u,
                f.point_position(PointRef { yarn, point }),
            )
        })
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// Position at material coordinate `u`, linear between the neighbouring
/// points; clamped to the end points outside their range.
fn position_at(line: &[(f64, Vec3)], u: f64) -> Vec3 {
    let i = line.partition_point(|p| p.0 < u);
    if i == 0 {
        return line[0].1;
    }
    if i == line.len() {
        return line[i - 1].1;
    }
    let (a, b) = (line[i - 1], line[i]);
    if b.0 > a.0 {
        let s = (u - a.0) / (b.0 - a.0);
        a.1 * (1.0 - s) + b.1 * s
    } else {
        b.1
    }
}

/// RMS distance between `a` and `b` over the material samples, after the
/// best rigid fit of `a`'s samples onto `b`'s (a free swatch's place and
/// orientation are not part of its answer; `topology::align`), each
/// distance in units of its yarn's radius (`meta.yarns[spec].radius` of
/// `b`, the reference).
pub fn rms_radii(a: &Fabric, b: &Fabric, samples: &MaterialSamples) -> Result<f64, CompareError> {
    if a.yarns.len() != b.yarns.len() || samples.u.len() != b.yarns.len() {
        return Err(CompareError::YarnCount(a.yarns.len(), b.yarns.len()));
    }
    let (mut pa, mut pb, mut radii) = (Vec::new(), Vec::new(), Vec::new());
    for (yi, us) in samples.u.iter().enumerate() {
        if us.is_empty() {
            continue;
        }
        let (la, lb) = (centre_line(a, yi), centre_line(b, yi));
        if la.is_empty() || lb.is_empty() {
            return Err(CompareError::EmptyYarn(yi));
        }
        let radius = b.meta.yarns[b.yarns[yi].spec].radius;
        for &u in us {
            pa.push(position_at(&la, u));
            pb.push(position_at(&lb, u));
            radii.push(radius);
        }
    }
    if pa.is_empty() {
        return Err(CompareError::NoSamples);
    }
    let fit = RigidFit::of(&pa, &pb);
    let sum: f64 = pa
        .iter()
        .zip(&pb)
        .zip(&radii)
        .map(|((p, q), r)| ((fit.apply(p) - q).norm() / r).powi(2))
        .sum();
    Ok((sum / pa.len() as f64).sqrt())
}

/// Extents (x, y, z) of the bounding box of every yarn point's position.
pub fn extents(f: &Fabric) -> [f64; 3] {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for (yarn, y) in f.yarns.iter().enumerate() {
        for point in 0..y.points.len() {
            let x = f.point_position(PointRef { yarn, point });
            lo = lo.inf(&x);
            hi = hi.sup(&x);
        }
    }
    if lo.x > hi.x {
        return [0.0; 3];
    }
    let e = hi - lo;
    [e.x, e.y, e.z]
}

/// Signed error of `value` against `reference`, in percent.
pub fn percent(value: f64, reference: f64) -> f64 {
    100.0 * (value - reference) / reference.abs()
}

/// Signed relative error of `value` against `reference`.
pub fn relative(value: f64, reference: f64) -> f64 {
    (value - reference) / reference.abs()
}

/// One run's errors against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    pub rms_radii: f64,
    pub width_pct: f64,
    pub height_pct: f64,
    pub depth_pct: f64,
    pub energy_rel: f64,
}

/// The final state of one relaxation, as the errors need it.
#[derive(Clone, Debug)]
pub struct Measured {
    pub fabric: Fabric,
    pub extents: [f64; 3],
    /// Total potential energy of the final state under its own
    /// discretization (J).
    pub energy: f64,
}

impl Measured {
    /// `grid` is the compiled fabric's stitch grid: the extents are taken
    /// along the swatch's own frame where it has one (`StitchGrid::extents`),
    /// the lab bounding box otherwise.
    pub fn new(fabric: Fabric, energy: f64, grid: &StitchGrid) -> Self {
        Measured {
            extents: grid.extents(&fabric).unwrap_or_else(|| extents(&fabric)),
            fabric,
            energy,
        }
    }

    /// Errors of this state against `reference`.
    pub fn errors(&self, reference: &Measured, samples: &MaterialSamples) -> Result<Errors, CompareError> {
        let (e, r) = (self.extents, reference.extents);
        Ok(Errors {
            rms_radii: rms_radii(&self.fabric, &reference.fabric, samples)?,
            width_pct: percent(e[0], r[0]),
            height_pct: percent(e[1], r[1]),
            depth_pct: percent(e[2], r[2]),
            energy_rel: relative(self.energy, reference.energy),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::fixtures::{meta, push_yarn};

    const MM: f64 = 1e-3;
    const RADIUS: f64 = 0.5 * MM;

    /// One straight yarn along x (u = x) and one bent yarn, radius 0.5 mm.
    fn fabric() -> Fabric {
        let mut f = Fabric {
            meta: meta(&[([200, 100, 50], RADIUS)]),
            nodes: vec![],
            yarns: vec![],
            contacts: vec![],
            sim: None,
        };
        let straight: Vec<Vec3> = (0..5).map(|i| Vec3::new(i as f64 * MM, 0.0, 0.0)).collect();
        push_yarn(&mut f, 0, &straight);
        let bent = [
            Vec3::new(0.0, 2.0 * MM, 0.0),
            Vec3::new(1.0 * MM, 3.0 * MM, 0.5 * MM),
            Vec3::new(2.0 * MM, 2.0 * MM, 0.0),
        ];
        push_yarn(&mut f, 0, &bent);
        f
    }

    #[test]
    fn identical_states_have_zero_error() {
        let f = fabric();
        let samples = MaterialSamples::of(&f, 8);
        assert_eq!(samples.len(), (8 * 4 + 1) + (8 * 2 + 1));
        // Zero up to the rounding of the rigid fit's SVD.
        assert!(rms_radii(&f, &f.clone(), &samples).unwrap() < 1e-12);
    }

    #[test]
    fn points_sliding_along_an_unmoved_straight_yarn_are_no_error() {
        let reference = fabric();
        let mut slid = reference.clone();
        // The inner points of the straight yarn move along it, their
        // material coordinates with them (u = x on this yarn).
        for (k, shift) in [(1usize, 0.3 * MM), (2, -0.4 * MM), (3, 0.45 * MM)] {
            let p = &mut slid.yarns[0].points[k];
            p.u += shift;
            slid.nodes[p.node].x.x += shift;
        }
        assert_ne!(slid.nodes, reference.nodes);
        let samples = MaterialSamples::of(&reference, 8);
        let rms = rms_radii(&slid, &reference, &samples).unwrap();
        assert!(rms < 1e-12, "rms {rms}");
    }

    #[test]
    fn a_point_moved_off_the_yarn_is_an_error() {
        let reference = fabric();
        let mut moved = reference.clone();
        let node = moved.yarns[0].points[2].node;
        moved.nodes[node].x.y += RADIUS;
        let rms = rms_radii(&moved, &reference, &MaterialSamples::of(&reference, 8)).unwrap();
        assert!(rms > 0.05 && rms < 1.0, "rms {rms}");
    }

    #[test]
    fn a_rigid_motion_is_no_error() {
        let reference = fabric();
        let mut moved = reference.clone();
        let turn = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 1.1);
        let d = Vec3::new(0.3 * MM, -0.4 * MM, 1.2 * MM);
        for n in &mut moved.nodes {
            n.x = turn * n.x + d;
        }
        let rms = rms_radii(&moved, &reference, &MaterialSamples::of(&reference, 8)).unwrap();
        assert!(rms < 1e-9, "rms {rms}");
    }

    #[test]
    fn eil_points_are_compared_where_they_interpolate() {
        let reference = fabric();
        let mut eil = reference.clone();
        // An EIL point's own node is ignored: it sits on the segment between
        // its real neighbours, which on the straight yarn is the same line.
        eil.yarns[0].points[2].eil = true;
        let node = eil.yarns[0].points[2].node;
        eil.nodes[node].x.z += 5.0 * MM;
        let rms = rms_radii(&eil, &reference, &MaterialSamples::of(&reference, 8)).unwrap();
        assert!(rms < 1e-12, "rms {rms}");
    }

    #[test]
    fn extents_and_errors_are_signed_against_the_reference() {
        let reference = Measured::new(fabric(), -2.0, &StitchGrid::default());
        assert_eq!(reference.extents, [4.0 * MM, 3.0 * MM, 0.5 * MM]);
        let mut wider = reference.fabric.clone();
        let last = wider.yarns[0].points[4].node;
        wider.nodes[last].x.x = 5.0 * MM;
        let run = Measured::new(wider, -1.0, &StitchGrid::default());
        let e = run
            .errors(&reference, &MaterialSamples::of(&reference.fabric, 4))
            .unwrap();
        assert!((e.width_pct - 25.0).abs() < 1e-9);
        assert!(e.height_pct.abs() < 1e-9 && e.depth_pct.abs() < 1e-9);
        assert!((e.energy_rel - 0.5).abs() < 1e-12);
        assert!(e.rms_radii > 0.0);
    }

    #[test]
    fn different_yarn_counts_cannot_be_compared() {
        let a = fabric();
        let mut b = a.clone();
        b.yarns.pop();
        let err = rms_radii(&a, &b, &MaterialSamples::of(&b, 8)).unwrap_err();
        assert_eq!(err, CompareError::YarnCount(2, 1));
    }
}
