//! The contact pipeline for one state: broad phase, filter, stencils, CCD.
//!
//! [`ContactSet`] holds what does not change within a solve (segments, their
//! rest graph, the mode and thickness). Each Newton iterate asks it for the
//! active stencils at `x` ([`ContactSet::stencils`]); each line search asks
//! for the largest collision-free step along `dx` ([`ContactSet::max_step`]).
//! If the rest data change (EoL nodes slide and `u` moves), rebuild it.

use super::barrier::BarrierShape;
use super::broad_phase::{edge_edge_candidates, overlapping_pairs, swept_segment_boxes};
use super::ccd::{max_step_fraction, CcdParams};
use super::distance::edge_edge_distance_sq;
use super::exclusion::JoinedSegments;
use super::filter::{needs_reference_distance, stencil_shape, uses_ccd, ContactMode, PairRest, ThicknessParams};
use super::rest::{ContactSegments, RestGraph};
use super::stencil::{EdgeEdgeBarrier, EdgeEdgePenalty};
use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};

type V3 = Vector3<f64>;

/// An active contact: the energy on nodes `[a0, a1, b0, b1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactStencil {
    pub nodes: [usize; 4],
    pub energy: ContactEnergy,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactEnergy {
    Barrier(EdgeEdgeBarrier),
    Penalty(EdgeEdgePenalty),
}

impl ContactStencil {
    /// Gathers the stencil's 12 local coordinates.
    pub fn local(&self, x: &[V3]) -> SVector<f64, 12> {
        SVector::<f64, 12>::from_fn(|r, _| x[self.nodes[r / 3]][r % 3])
    }
}

impl Stencil<12> for ContactStencil {
    fn value(&self, x: &SVector<f64, 12>) -> f64 {
        match &self.energy {
            ContactEnergy::Barrier(b) => b.value(x),
            ContactEnergy::Penalty(p) => p.value(x),
        }
    }

    fn gradient(&self, x: &SVector<f64, 12>) -> SVector<f64, 12> {
        match &self.energy {
            ContactEnergy::Barrier(b) => b.gradient(x),
            ContactEnergy::Penalty(p) => p.gradient(x),
        }
    }

    fn hessian(&self, x: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        match &self.energy {
            ContactEnergy::Barrier(b) => b.hessian(x),
            ContactEnergy::Penalty(p) => p.hessian(x),
        }
    }

    /// One distance evaluation for both derivatives; inactive pairs (most
    /// candidates of a solve) skip the eigen-projection.
    fn derivatives(&self, x: &SVector<f64, 12>, project: bool) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let (g, h) = match &self.energy {
            ContactEnergy::Barrier(b) => b.derivs(x),
            ContactEnergy::Penalty(p) => p.derivs(x),
        };
        if project && h.iter().any(|v| *v != 0.0) {
            (g, crate::energy::psd::project_psd(&h))
        } else {
            (g, h)
        }
    }
}

/// Segments, rest graph, mode and thickness of a contact problem.
#[derive(Clone, Debug)]
pub struct ContactSet {
    pub segments: ContactSegments,
    pub mode: ContactMode,
    pub params: ThicknessParams,
    pub ccd: CcdParams,
    /// Pairs joined by a persistent EoL contact (skipped in every mode).
    pub joined: Option<JoinedSegments>,
    graph: RestGraph,
}

impl ContactSet {
    pub fn build(segments: ContactSegments, mode: ContactMode, params: ThicknessParams) -> Self {
        let graph = RestGraph::new(&segments);
        Self {
            segments,
            mode,
            params,
            ccd: CcdParams::default(),
            joined: None,
            graph,
        }
    }

    /// Skips the pairs that `joined` marks (see [`super::exclusion`]).
    pub fn with_exclusion(mut self, joined: JoinedSegments) -> Self {
        self.joined = Some(joined);
        self
    }

    /// `dbar_min` of docs/MODEL.md, "Thickness contact".
    pub fn dbar_min(&self) -> f64 {
        self.graph.min_reference_distance()
    }

    /// The barrier of each candidate pair that the mode keeps.
    pub fn classify(&self, pairs: &[[u32; 2]]) -> Vec<([u32; 2], BarrierShape)> {
        let segs = &self.segments;
        let h = self.params.thickness;
        let dbar_min = self.dbar_min();
        let mut out = Vec::with_capacity(pairs.len());
        // Pairs arrive sorted by their first segment: one search per segment.
        for group in pairs.chunk_by(|p, q| p[0] == q[0]) {
            let i = group[0][0] as usize;
            let dbar = if needs_reference_distance(self.mode) {
                let targets: Vec<[usize; 2]> = group.iter().map(|p| segs.nodes[p[1] as usize]).collect();
                self.graph.reference_distances(segs.nodes[i], &targets, h)
            } else {
                vec![f64::INFINITY; group.len()]
            };
            for (&[a, b], dbar) in group.iter().zip(dbar) {
                let (a, b) = (a as usize, b as usize);
                if self.joined.as_ref().is_some_and(|j| j.joined(a, b)) {
                    continue;
                }
                let pair = PairRest {
                    same_yarn: segs.yarn[a] == segs.yarn[b],
                    index_gap: segs.index_in_yarn[a].abs_diff(segs.index_in_yarn[b]),
                    dbar,
                };
                if let Some(shape) = stencil_shape(self.mode, &pair, &self.params, dbar_min) {
                    out.push(([a as u32, b as u32], shape));
                }
            }
        }
        out
    }

    /// Every kept pair whose segments are closer than `reach` (at least the
    /// thickness) at `x`, active or not: the candidate list of a solve that
    /// keeps its Hessian pattern while positions move by less than
    /// `(reach - thickness) / 2` (see `sim::terms::thickness_contact`).
    pub fn candidates(&self, x: &[V3], reach: f64) -> Vec<([u32; 2], BarrierShape)> {
        if self.mode == ContactMode::None {
            return Vec::new();
        }
        let reach = reach.max(self.params.thickness);
        let segs = &self.segments.nodes;
        self.classify(&edge_edge_candidates(x, segs, reach))
            .into_iter()
            .filter(|([i, j], _)| {
                let (a, b) = (segs[*i as usize], segs[*j as usize]);
                edge_edge_distance_sq(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]) < reach * reach
            })
            .collect()
    }

    /// The stencil of a kept pair with barrier stiffness `kappa`.
    pub fn stencil(&self, pair: [u32; 2], shape: BarrierShape, kappa: f64) -> ContactStencil {
        let segs = &self.segments.nodes;
        let (a, b) = (segs[pair[0] as usize], segs[pair[1] as usize]);
        let energy = match self.mode {
            ContactMode::Penalty => ContactEnergy::Penalty(EdgeEdgePenalty {
                stiffness: self.params.penalty_stiffness,
                thickness: shape.activation,
            }),
            _ => ContactEnergy::Barrier(EdgeEdgeBarrier {
                stiffness: kappa,
                shape,
            }),
        };
        ContactStencil {
            nodes: [a[0], a[1], b[0], b[1]],
            energy,
        }
    }

    /// Largest fraction of `dx` keeping every listed pair outside its core
    /// (additive CCD on exactly these pairs; 1 for modes without CCD).
    pub fn max_step_pairs(&self, x: &[V3], dx: &[V3], pairs: &[([u32; 2], BarrierShape)]) -> f64 {
        if !uses_ccd(self.mode) {
            return 1.0;
        }
        let with_core: Vec<([u32; 2], f64)> = pairs.iter().map(|(p, s)| (*p, s.core)).collect();
        max_step_fraction(x, dx, &self.segments.nodes, &with_core, &self.ccd)
    }

    /// Active stencils at positions `x` with barrier stiffness `kappa`.
    pub fn stencils(&self, x: &[V3], kappa: f64) -> Vec<ContactStencil> {
        if self.mode == ContactMode::None {
            return Vec::new();
        }
        let segs = &self.segments.nodes;
        let candidates = edge_edge_candidates(x, segs, self.params.thickness);
        let mut out = Vec::new();
        for ([i, j], shape) in self.classify(&candidates) {
            let (a, b) = (segs[i as usize], segs[j as usize]);
            let d2 = edge_edge_distance_sq(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]);
            if d2 < shape.activation * shape.activation {
                out.push(self.stencil([i, j], shape, kappa));
            }
        }
        out
    }

    /// Largest fraction of the step `dx` (in `[0, 1]`) that keeps every
    /// barrier pair farther apart than its core. 1 for modes without CCD.
    pub fn max_step(&self, x: &[V3], dx: &[V3]) -> f64 {
        if !uses_ccd(self.mode) {
            return 1.0;
        }
        let segs = &self.segments.nodes;
        // Swept boxes inflated by the largest core: pairs coming within it
        // during the step are caught too.
        let boxes = swept_segment_boxes(x, dx, segs, self.params.core.max(0.0));
        let candidates = overlapping_pairs(&boxes, segs);
        let pairs: Vec<([u32; 2], f64)> = self
            .classify(&candidates)
            .into_iter()
            .map(|(p, shape)| (p, shape.core))
            .collect();
        max_step_fraction(x, dx, segs, &pairs, &self.ccd)
    }

    /// Smallest gap `d - eta` over the stencils (for adaptive stiffness).
    pub fn min_gap(&self, x: &[V3], stencils: &[ContactStencil]) -> f64 {
        stencils
            .iter()
            .map(|s| {
                let [a0, a1, b0, b1] = s.nodes.map(|n| &x[n]);
                let d = edge_edge_distance_sq(a0, a1, b0, b1).sqrt();
                match &s.energy {
                    ContactEnergy::Barrier(b) => d - b.shape.core,
                    ContactEnergy::Penalty(_) => d,
                }
            })
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests;
