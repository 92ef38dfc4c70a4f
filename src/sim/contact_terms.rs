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
//! `system.rs`). An EIL point is interpolated *on* such a segment (docs/MODEL.md,
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
//! ([`minimize`]). The same cap includes additive CCD on every candidate
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

use super::params::SimParams;
use super::problem::EolProblem;
use super::system::Discretization;
use crate::contact::barrier::{AdaptiveStiffness, BarrierShape};
use crate::contact::exclusion::{ContactSide, JoinedSegments};
use crate::contact::{ContactMode, ContactSegments, ContactSet, ContactStencil, ThicknessParams};
use crate::energy::Stencil;
use crate::solver::assembly::{AnyStencilSet, AssemblyError, StencilSet};
use crate::solver::linear::LinearSolver;
use crate::solver::newton::{self, NewtonError, NewtonHooks, NewtonParams, NewtonReport, NewtonStatus, Problem};
use crate::topology::PointRef;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, Ordering};

type V3 = Vector3<f64>;

/// Name of the contact stencil set in the problem.
pub const CONTACT_SET: &str = "contact";

/// The contact treatment, as scenes and the CLI spell it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactModeName {
    None,
    Penalty,
    Barrier,
    Culled,
    #[default]
    Filtered,
}

impl std::str::FromStr for ContactModeName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(Self::None),
            "penalty" => Ok(Self::Penalty),
            "barrier" => Ok(Self::Barrier),
            "culled" => Ok(Self::Culled),
            "filtered" => Ok(Self::Filtered),
            _ => Err(format!(
                "unknown contact mode '{s}' (none, penalty, barrier, culled, filtered)"
            )),
        }
    }
}

/// Settings of non-persistent contact (see the module doc).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContactParams {
    pub mode: ContactModeName,
    /// Material thickness `h` (m); `None` = the thickest yarn's diameter
    /// (`SimParams::yarn_radii`; `2 rod.radius` when all yarns share it).
    pub thickness: Option<f64>,
    /// Hard core `eta = core_fraction * h` of full-thickness pairs (docs/MODEL.md,
    /// "Thickness contact"; 0 = single phase).
    pub core_fraction: f64,
    /// Culling window (segments) of the `culled` mode; default 11.
    pub cull_window: u32,
    /// Exclusion radius around persistent EoL contacts, in units of `h`.
    pub eol_exclusion: f64,
    /// Candidate margin in units of `h`: pairs within `(1 + margin) h` are
    /// listed per solve; nodes may move `0.45 margin h` before a rebuild.
    pub margin: f64,
    /// `kappa_min = stiffness_scale * kb / h^3`.
    pub stiffness_scale: f64,
    /// `kappa_max = max_stiffness_factor * kappa_min`.
    pub max_stiffness_factor: f64,
    /// kappa doubles while the smallest gap shrinks below `close_gap * h`.
    pub close_gap: f64,
    /// Stiffness of the `penalty` mode (N/m).
    pub penalty_stiffness: f64,
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            mode: ContactModeName::Filtered,
            thickness: None,
            core_fraction: 0.0,
            cull_window: 11,
            eol_exclusion: 1.0,
            margin: 1.0,
            stiffness_scale: 1.0,
            max_stiffness_factor: 1e4,
            close_gap: 1e-3,
            penalty_stiffness: 1e3,
        }
    }
}

impl ContactParams {
    pub fn mode(&self) -> ContactMode {
        match self.mode {
            ContactModeName::None => ContactMode::None,
            ContactModeName::Penalty => ContactMode::Penalty,
            ContactModeName::Barrier => ContactMode::Barrier,
            ContactModeName::Culled => ContactMode::Culled {
                window: self.cull_window,
            },
            ContactModeName::Filtered => ContactMode::Filtered,
        }
    }

    /// Thickness `h` for a yarn of radius `radius`.
    pub fn thickness_for(&self, radius: f64) -> f64 {
        self.thickness.unwrap_or(2.0 * radius)
    }
}

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
    pub restart: AtomicBool,
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
}

impl EolProblem {
    /// Adds the contact terms: picks kappa from the gradient balance, then
    /// builds the contact stencil set and the new pattern.
    pub fn attach_contact(&mut self, q: &[f64], mut terms: ContactTerms) -> Result<(), AssemblyError> {
        if terms.candidate_count() > 0 {
            let elastic = self.free_gradient(q)?;
            let barrier = terms.unit_barrier_gradient(q, &self.free);
            let kappa_min = terms.kappa;
            let balanced = AdaptiveStiffness::balanced(kappa_min, terms.kappa_max, &elastic, &barrier);
            terms.kappa = balanced.kappa;
        }
        let set: Box<dyn AnyStencilSet> = Box::new(terms.stencil_set());
        self.contact = Some(terms);
        self.replace_set(CONTACT_SET, Some(set))
    }

    /// Rebuilds the candidate list at `q` (after the trust radius bound a
    /// step) and doubles kappa if the gaps keep closing (IPC).
    pub fn refresh_contact(&mut self, q: &[f64], prev_min_gap: f64) -> Result<f64, AssemblyError> {
        let Some(terms) = self.contact.as_mut() else {
            return Ok(f64::INFINITY);
        };
        terms.rebuild(q);
        let gap = terms.min_gap(q);
        if gap < terms.close_gap && gap < prev_min_gap {
            terms.kappa = (2.0 * terms.kappa).min(terms.kappa_max.max(terms.kappa));
        }
        let set: Box<dyn AnyStencilSet> = Box::new(terms.stencil_set());
        self.replace_set(CONTACT_SET, Some(set))?;
        Ok(gap)
    }
}

/// Newton on `problem`, rebuilding the contact candidates whenever the
/// trust radius stops a step (module doc). Without contact this is exactly
/// [`newton::minimize`]. The iteration cap covers all rounds together.
pub fn minimize(
    problem: &mut EolProblem,
    q: &mut [f64],
    solver: &mut LinearSolver,
    params: &NewtonParams,
    mut hooks: NewtonHooks<'_>,
) -> Result<NewtonReport, NewtonError> {
    if problem.contact.is_none() {
        return newton::minimize(problem, q, solver, params, hooks);
    }
    let user_cancel = hooks.cancel;
    let mut history = Vec::new();
    let mut gap = f64::INFINITY;
    loop {
        let mut round = *params;
        round.max_iterations = params.max_iterations.saturating_sub(history.len()).max(1);
        let stop = AtomicBool::new(false);
        let report = {
            // Newton polls one flag: the user's cancel is copied into it
            // after each iteration, the trust restart by `RestartOnTrust`.
            let mut on_iter = |s: &newton::IterStats| {
                if let Some(cb) = hooks.on_iteration.as_mut() {
                    cb(s);
                }
                if user_cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    stop.store(true, Ordering::Relaxed);
                }
            };
            let round_hooks = NewtonHooks {
                on_iteration: Some(&mut on_iter),
                cancel: Some(&stop),
                on_accepted: hooks.on_accepted.as_mut().map(|cb| &mut **cb as &mut dyn FnMut(&[f64])),
            };
            newton::minimize(
                &mut RestartOnTrust { problem, stop: &stop },
                q,
                solver,
                &round,
                round_hooks,
            )?
        };
        let user_stopped = user_cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        let trust_hit = problem
            .contact
            .as_ref()
            .is_some_and(|c| c.restart.load(Ordering::Relaxed));
        history.extend(report.history);
        let more = trust_hit
            && !user_stopped
            && matches!(report.status, NewtonStatus::Cancelled | NewtonStatus::Blocked)
            && history.len() < params.max_iterations;
        if !more {
            let status = if trust_hit && report.status == NewtonStatus::Cancelled && !user_stopped {
                NewtonStatus::MaxIterations
            } else {
                report.status
            };
            return Ok(NewtonReport {
                status,
                history,
                energy: report.energy,
            });
        }
        gap = problem.refresh_contact(q, gap)?;
    }
}

/// Forwards to the problem and raises `stop` once a step was capped by the
/// trust radius, so Newton returns after that iteration.
struct RestartOnTrust<'a> {
    problem: &'a mut EolProblem,
    stop: &'a AtomicBool,
}

impl Problem for RestartOnTrust<'_> {
    fn energy(&mut self, q: &[f64]) -> f64 {
        self.problem.energy(q)
    }
    fn gradient_hessian(
        &mut self,
        q: &[f64],
        g: &mut [f64],
        h: &mut crate::sparse::CsrMatrix,
    ) -> Result<(), AssemblyError> {
        self.problem.gradient_hessian(q, g, h)
    }
    fn hessian_pattern(&self) -> crate::sparse::CsrMatrix {
        self.problem.hessian_pattern()
    }
    fn free(&self) -> &[bool] {
        self.problem.free()
    }
    fn max_step(&mut self, q: &[f64], dq: &[f64]) -> f64 {
        let cap = self.problem.max_step(q, dq);
        if self
            .problem
            .contact
            .as_ref()
            .is_some_and(|c| c.restart.load(Ordering::Relaxed))
        {
            self.stop.store(true, Ordering::Relaxed);
        }
        cap
    }
    fn bounds(&self, q: &[f64], lower: &mut [f64], upper: &mut [f64]) -> bool {
        self.problem.bounds(q, lower, upper)
    }
    fn must_rediscretize(&self, q: &[f64]) -> bool {
        self.problem.must_rediscretize(q)
    }
    fn blocks(&self) -> Vec<usize> {
        self.problem.blocks()
    }
    fn ordering_groups(&self) -> Vec<u32> {
        self.problem.ordering_groups()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_keys_select_the_mode() {
        let off: SimParams = serde_json::from_str("{}").expect("empty scene");
        assert_eq!(off.contact, None, "contact is off unless a scene asks for it");
        let on: SimParams = serde_json::from_str(r#"{"contact": {}}"#).expect("contact object");
        assert_eq!(on.contact.as_ref().map(|c| c.mode()), Some(ContactMode::Filtered));
        let culled: SimParams =
            serde_json::from_str(r#"{"contact": {"mode": "culled", "cull_window": 5}}"#).expect("culled");
        assert_eq!(
            culled.contact.as_ref().map(|c| c.mode()),
            Some(ContactMode::Culled { window: 5 })
        );
        assert!(serde_json::from_str::<SimParams>(r#"{"contact": {"mode": "tight"}}"#).is_err());
        assert_eq!("barrier".parse(), Ok(ContactModeName::Barrier));
        assert!("bogus".parse::<ContactModeName>().is_err());
    }
}
