//! Non-persistent yarn-yarn contact in the simulator: the filtered thickness
//! barrier (docs/MODEL.md, "Thickness contact") wired into each Newton solve.
//!
//! **Modes** (`SimParams::contact`, scene key `"contact"`, CLI `--contact`):
//! `none`, `penalty`, `barrier`, `culled` (a window of `cull_window`
//! segments) and `filtered` (docs/MODEL.md, "Thickness contact"). A scene
//! without a `"contact"` key has no non-persistent contact and builds
//! nothing for it: no segment list, no broad phase, no CCD. A `"contact"`
//! object without `"mode"` means `filtered`.
//!
//! **Segments.** The contact geometry is the rod's own: per yarn, the
//! segments between consecutive non-EIL points (the stretch segments of
//! `terms::rod_segments`). An EIL point is interpolated *on* such a segment (docs/MODEL.md,
//! "Kinematics"), so it adds no geometry and needs no stencil of its own; when EIL
//! points change, the segment list changes with the next step. Reference
//! distances `dbar` are rest arc lengths, `|u_b - u_a|` at the current `u`
//! (`contact::rest`), so a sliding contact keeps a consistent filter.
//!
//! **Persistent contacts.** An EoL contact node is one position shared by
//! two yarns, so their centrelines meet there. Pairs with one segment within
//! `eol_exclusion * h` (in `u`) of one side of a contact and the other
//! within the same distance of the other side get no barrier
//! (`contact::exclusion`).
//!
//! **One candidate list per solve.** The Newton solver keeps one Hessian
//! pattern per solve, but contact pairs come and go. At the start of a solve
//! the broad phase lists every kept pair closer than `reach = h + margin`
//! (with the unfiltered thickness, docs/MODEL.md, "Thickness contact"); each becomes a
//! stencil (zero while farther than its activation). Any other pair started
//! more than `reach` apart, and as long as no node moves more than
//! `0.45 margin` from where the list was built it stays farther than `h`, so
//! its barrier is exactly zero and leaving it out is exact. The line search
//! cap enforces that trust radius; when it binds, the solve stops, the list
//! is rebuilt at the current positions and Newton continues
//! (`sim::problem::solve`). The same cap includes additive CCD on every candidate
//! pair, so no step can cross two segments (or pass inside a hard core).
//!
//! **Adaptive stiffness** (as in IPC; docs/MODEL.md, "Thickness contact"): at the start of each
//! solve kappa balances the elastic gradient against the barrier gradient
//! in least squares, clamped to `[kappa_min, kappa_max]`, and never drops
//! below the previous step's value. IPC derives `kappa_min` from the mass
//! scale, which quasi-static relaxation does not have; we use the bending
//! scale instead: `kappa_min = stiffness_scale * kb / h^3`, the stiffness at
//! which the barrier force at a fraction of `h` balances the force that bends
//! a yarn to a radius of about its thickness. kappa doubles (up to
//! `kappa_max`) when the smallest gap keeps shrinking below `close_gap * h`.

use crate::contact::barrier::{AdaptiveStiffness, BarrierShape};
use crate::contact::exclusion::{ContactSide, JoinedSegments};
use crate::contact::{ContactMode, ContactSegments, ContactSet, ContactStencil, ThicknessParams};
use crate::energy::Stencil;
use crate::sim::discretization::Discretization;
use crate::sim::params::SimParams;
use crate::solver::assembly::StencilSet;
use crate::topology::PointRef;
use nalgebra::Vector3;
use std::sync::atomic::{AtomicBool, Ordering};

type V3 = Vector3<f64>;

/// Name of the contact stencil set in the problem.
pub const CONTACT_SET: &str = "contact";

/// Contact state carried from step to step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactState {
    /// Barrier stiffness (0 before the first solve with contact).
    pub kappa: f64,
    /// Smallest gap `d - eta` at the end of the last step.
    pub min_gap: f64,
}

/// The contact part of one Newton solve.
pub struct ContactTerms {
    pub set: ContactSet,
    pub kappa: f64,
    n_nodes: usize,
    reach: f64,
    trust: f64,
    close_gap: f64,
    kappa_max: f64,
    /// Node positions where the candidate list was built.
    x_ref: Vec<V3>,
    on_segment: Vec<bool>,
    pairs: Vec<([u32; 2], BarrierShape)>,
    /// Set when the trust radius capped a step: the list must be rebuilt.
    restart: AtomicBool,
}

fn nodes_of(v: &[f64], n_nodes: usize) -> Vec<V3> {
    (0..n_nodes)
        .map(|i| V3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2]))
        .collect()
}

impl ContactTerms {
    /// The contact terms of a step, or `None` when contact is off.
    pub fn new(disc: &Discretization, q: &[f64], p: &SimParams, state: &ContactState) -> Option<Self> {
        let cp = p.contact.as_ref()?;
        let mode = cp.mode();
        if mode == ContactMode::None {
            return None;
        }
        let (f, l) = (disc.f, disc.l);
        // One thickness for every pair: the thickest yarn's diameter.
        let thickest = p.yarn_radii(disc.f).into_iter().fold(0.0, f64::max);
        let h = cp.thickness_for(if thickest > 0.0 { thickest } else { p.rod.radius });
        let mut segs = ContactSegments::default();
        let mut ranges = Vec::new();
        for (y, real) in disc.real.iter().enumerate() {
            for (k, w) in real.windows(2).enumerate() {
                let (pa, pb) = (PointRef { yarn: y, point: w[0] }, PointRef { yarn: y, point: w[1] });
                let (ua, ub) = (q[l.u(pa)], q[l.u(pb)]);
                segs.nodes
                    .push([f.yarns[y].points[w[0]].node, f.yarns[y].points[w[1]].node]);
                segs.yarn.push(y as u32);
                segs.index_in_yarn.push(k as u32);
                segs.rest_length.push((ub - ua).abs());
                ranges.push((y as u32, ua, ub));
            }
        }
        let contacts: Vec<[ContactSide; 2]> = f
            .contacts
            .iter()
            .map(|c| {
                [c.front, c.back].map(|pr| ContactSide {
                    yarn: pr.yarn as u32,
                    u: q[l.u(pr)],
                })
            })
            .collect();
        let joined = JoinedSegments::new(&ranges, &contacts, cp.eol_exclusion * h);
        let thickness = ThicknessParams {
            thickness: h,
            core: cp.core_fraction.clamp(0.0, 0.99) * h,
            penalty_stiffness: cp.penalty_stiffness,
        };
        let mut on_segment = vec![false; l.n_nodes];
        for s in &segs.nodes {
            on_segment[s[0]] = true;
            on_segment[s[1]] = true;
        }
        let set = ContactSet::build(segs, mode, thickness).with_exclusion(joined);
        let kappa_min = cp.stiffness_scale * p.rod.kb / (h * h * h);
        let mut kappa = state.kappa.max(kappa_min);
        let kappa_max = cp.max_stiffness_factor * kappa_min;
        let close = cp.close_gap * h;
        if state.kappa > 0.0 && state.min_gap < close {
            kappa = (2.0 * kappa).min(kappa_max.max(kappa));
        }
        let margin = cp.margin.max(1e-3) * h;
        let mut terms = ContactTerms {
            set,
            kappa,
            n_nodes: l.n_nodes,
            reach: h + margin,
            trust: 0.45 * margin,
            close_gap: close,
            kappa_max,
            x_ref: Vec::new(),
            on_segment,
            pairs: Vec::new(),
            restart: AtomicBool::new(false),
        };
        terms.rebuild(q);
        Some(terms)
    }

    /// Lists the candidates at `q` and makes it the trust centre.
    fn rebuild(&mut self, q: &[f64]) {
        self.x_ref = nodes_of(q, self.n_nodes);
        self.pairs = self.set.candidates(&self.x_ref, self.reach);
        self.restart.store(false, Ordering::Relaxed);
    }

    /// The candidate stencils as a set on the node coordinates.
    pub fn stencil_set(&self) -> StencilSet<ContactStencil, 12> {
        let mut stencils = Vec::with_capacity(self.pairs.len());
        let mut dofs = Vec::with_capacity(self.pairs.len());
        for &(pair, shape) in &self.pairs {
            let s = self.set.stencil(pair, shape, self.kappa);
            dofs.push(std::array::from_fn(|r| (3 * s.nodes[r / 3] + r % 3) as u32));
            stencils.push(s);
        }
        StencilSet::new(CONTACT_SET, stencils, dofs)
    }

    /// Number of candidate pairs in the current list.
    pub fn candidate_count(&self) -> usize {
        self.pairs.len()
    }

    /// Gradient of the unit-stiffness barrier sum on free rows.
    fn unit_barrier_gradient(&self, q: &[f64], free: &[bool]) -> Vec<f64> {
        let mut g = vec![0.0; q.len()];
        let x = nodes_of(q, self.n_nodes);
        for &(pair, shape) in &self.pairs {
            let s = self.set.stencil(pair, shape, 1.0);
            let gl = s.gradient(&s.local(&x));
            for r in 0..12 {
                let i = 3 * s.nodes[r / 3] + r % 3;
                if free[i] {
                    g[i] += gl[r];
                }
            }
        }
        g
    }

    /// Smallest gap `d - eta` over the candidates at `q` (infinite if none).
    pub fn min_gap(&self, q: &[f64]) -> f64 {
        let x = nodes_of(q, self.n_nodes);
        let stencils: Vec<ContactStencil> = self
            .pairs
            .iter()
            .map(|&(p, s)| self.set.stencil(p, s, self.kappa))
            .collect();
        self.set.min_gap(&x, &stencils)
    }

    /// The state to carry into the next step.
    pub fn state(&self, q: &[f64]) -> ContactState {
        ContactState {
            kappa: self.kappa,
            min_gap: self.min_gap(q),
        }
    }

    /// Largest safe fraction of `dq`: CCD on the candidates and the trust
    /// radius that keeps the candidate list exact (module doc).
    pub fn max_step(&self, q: &[f64], dq: &[f64]) -> f64 {
        let x = nodes_of(q, self.n_nodes);
        let dx = nodes_of(dq, self.n_nodes);
        let ccd = self.set.max_step_pairs(&x, &dx, &self.pairs);
        let mut trust: f64 = 1.0;
        for (i, d) in dx.iter().enumerate() {
            let dd = d.norm_squared();
            if !self.on_segment[i] || dd == 0.0 {
                continue;
            }
            let r = x[i] - self.x_ref[i];
            let c = r.norm_squared() - self.trust * self.trust;
            if c >= 0.0 {
                trust = 0.0;
                break;
            }
            let b = r.dot(d);
            // Positive root of dd a^2 + 2 b a + c = 0 (c < 0: one root > 0).
            let a = (-b + (b * b - dd * c).sqrt()) / dd;
            trust = trust.min(a);
        }
        if trust < 1.0 && trust <= ccd {
            self.restart.store(true, Ordering::Relaxed);
        }
        ccd.min(trust)
    }

    /// Whether [`max_step`](Self::max_step) capped a step at the trust
    /// radius since the list was built: the list must be rebuilt before
    /// Newton goes on.
    pub fn trust_exceeded(&self) -> bool {
        self.restart.load(Ordering::Relaxed)
    }

    /// Picks kappa from the balance of the elastic free-row gradient
    /// `elastic` against the barrier's at `q` (module doc).
    pub fn balance_stiffness(&mut self, q: &[f64], elastic: &[f64], free: &[bool]) {
        if self.candidate_count() > 0 {
            let barrier = self.unit_barrier_gradient(q, free);
            let kappa_min = self.kappa;
            let balanced = AdaptiveStiffness::balanced(kappa_min, self.kappa_max, elastic, &barrier);
            self.kappa = balanced.kappa;
        }
    }

    /// Rebuilds the candidate list at `q` (after the trust radius bound a
    /// step) and doubles kappa if the gaps keep closing (IPC); returns the
    /// smallest gap now.
    pub fn refresh(&mut self, q: &[f64], prev_min_gap: f64) -> f64 {
        self.rebuild(q);
        let gap = self.min_gap(q);
        if gap < self.close_gap && gap < prev_min_gap {
            self.kappa = (2.0 * self.kappa).min(self.kappa_max.max(self.kappa));
        }
        gap
    }
}
