//! The settings of a dynamic run (`knitsim drape`): gravity, damping,
//! friction against obstacles, the time step, duration and frame rate, the
//! stopping test, and which nodes are pinned and how they move.
//!
//! They sit in the scene under `"dynamics"` (`SimParams::dynamics`) and at
//! the bottom of the `sim` layers beside [`super::params`], because the
//! term builders read the damping and the obstacle friction. A relaxation
//! ignores everything here except `damping` and `obstacle_mu`, which are 0
//! unless a scene sets them.
//!
//! Pins are chosen by selectors on the fabric at the start of the run
//! (`sim::dynamics::pins` resolves them); a motion moves a pin set by a
//! translation or a stretch, linearly over a time interval.

use serde::{Deserialize, Serialize};

/// Settings of a dynamic run (module docs). Every key has a default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DynamicsParams {
    /// Gravitational acceleration (m/s^2). `knitsim drape` turns gravity
    /// on with this vector.
    pub gravity: [f64; 3],
    /// Mass-proportional (Rayleigh `alpha`) damping (1/s): a viscous force
    /// `-alpha M v`; 0 = none (`sim::terms::mass_damping`).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub damping: f64,
    /// Coulomb coefficient between yarn and every obstacle; 0 = no friction
    /// term (`sim::terms::obstacle_friction`).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub obstacle_mu: f64,
    /// Below this sliding speed (m/s) obstacle friction is smoothed into a
    /// stiff viscous force (the static regime), as in IPC's friction.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub friction_speed: f64,
    /// First time step (s); halved on a failed Newton solve, doubled back
    /// after converged ones, never above `max_dt`.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub dt: f64,
    /// Largest time step (s); `null` = `dt`.
    #[serde(deserialize_with = "crate::checked::optional_positive")]
    pub max_dt: Option<f64>,
    /// Simulated time at which the run stops (s) if it has not come to rest.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub duration: f64,
    /// Frames written per simulated second.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub frame_rate: f64,
    /// At rest: the largest speed of a real node (m/s) stays below this...
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub rest_speed: f64,
    /// ...for this long (s) of simulated time; 0 = never stop before `duration`.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub rest_time: f64,
    /// Newton's stopping test in each step: the largest free force of the
    /// step's incremental potential, as a fraction of the weight of the
    /// mean rest segment (`rho d_rest |g|`, or `rho d_rest 9.81` without
    /// gravity).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub newton_tol: f64,
    /// Newton iterations per attempt before the step is retried at half `dt`.
    pub newton_max_iterations: usize,
    /// Let yarn slide through its contacts at the Coulomb limit. Off by
    /// default: contacts stick, as while relaxing (`Schedule::stick`). A
    /// relaxed swatch is an equilibrium of sticking contacts whose
    /// tangential loads may exceed `mu` times their normal load; released
    /// to slide at the first step, such a swatch snaps instead of falling.
    #[serde(default)]
    pub sliding: bool,
    /// Pinned node sets (their coordinates are not unknowns).
    pub pins: Vec<PinSelector>,
    /// Prescribed motions of pin sets.
    pub motions: Vec<Motion>,
}

impl Default for DynamicsParams {
    fn default() -> Self {
        DynamicsParams {
            gravity: [0.0, 0.0, -9.81],
            damping: 0.0,
            obstacle_mu: 0.0,
            friction_speed: 1e-3,
            dt: 1e-3,
            max_dt: None,
            duration: 1.0,
            frame_rate: 50.0,
            rest_speed: 5e-3,
            rest_time: 0.05,
            newton_tol: 1e-2,
            newton_max_iterations: 50,
            sliding: false,
            pins: Vec::new(),
            motions: Vec::new(),
        }
    }
}

/// Which edge of the fabric, in its starting plane: `top` is largest `y`,
/// `right` largest `x`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Edge {
    Top,
    Bottom,
    Left,
    Right,
}

/// A set of nodes to pin, picked on the fabric's starting state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "select", rename_all = "snake_case", deny_unknown_fields)]
pub enum PinSelector {
    /// The node nearest each corner of the bounding box in the `x`-`y`
    /// plane (all four, or the two of an edge).
    Corners {
        #[serde(default)]
        edge: Option<Edge>,
    },
    /// Every node within `depth` (m) of an edge of the bounding box.
    Edge {
        edge: Edge,
        #[serde(default = "default_depth", deserialize_with = "crate::checked::positive")]
        depth: f64,
    },
    /// The stitch-contact nodes of the stitches in rows `rows[0]..=rows[1]`
    /// and columns `columns[0]..=columns[1]` (1-based, row 1 at the bottom,
    /// column 1 at the left).
    Stitches { rows: [usize; 2], columns: [usize; 2] },
    /// The first (`end: "start"`) or last point of a yarn (0-based index).
    YarnEnd { yarn: usize, end: YarnEnd },
    /// Nodes by index.
    Nodes { nodes: Vec<usize> },
}

fn default_depth() -> f64 {
    2e-3
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum YarnEnd {
    Start,
    End,
}

/// A prescribed motion of one pin set: its displacement grows linearly
/// from 0 at `start` to the full value at `end` (s) and stays there. A
/// motion with both a translation and a stretch stretches, then translates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motion {
    /// Index into `pins`.
    pub pins: usize,
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub start: f64,
    #[serde(deserialize_with = "crate::checked::positive")]
    pub end: f64,
    /// Move by this vector (m): pull, shear or compress an edge.
    #[serde(default)]
    pub translate: Option<[f64; 3]>,
    /// Scale positions about a centre per axis: a factor above 1
    /// stretches, below 1 compresses.
    #[serde(default)]
    pub stretch: Option<Stretch>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stretch {
    pub center: [f64; 3],
    pub factor: [f64; 3],
}

impl Motion {
    /// The fraction of the motion done at time `t`.
    pub fn progress(&self, t: f64) -> f64 {
        if t <= self.start {
            0.0
        } else if t >= self.end {
            1.0
        } else {
            (t - self.start) / (self.end - self.start)
        }
    }

    /// Where a node that started at `x0` is at time `t`.
    pub fn position(&self, x0: [f64; 3], t: f64) -> [f64; 3] {
        let s = self.progress(t);
        let mut out = x0;
        for i in 0..3 {
            if let Some(st) = &self.stretch {
                out[i] += s * (st.factor[i] - 1.0) * (x0[i] - st.center[i]);
            }
            if let Some(d) = &self.translate {
                out[i] += s * d[i];
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motions_interpolate_linearly_and_hold() {
        let m = Motion {
            pins: 0,
            start: 1.0,
            end: 3.0,
            translate: Some([0.0, 0.0, 2.0]),
            stretch: None,
        };
        assert_eq!(m.position([1.0, 1.0, 1.0], 0.5), [1.0, 1.0, 1.0]);
        assert_eq!(m.position([1.0, 1.0, 1.0], 2.0), [1.0, 1.0, 2.0]);
        assert_eq!(m.position([1.0, 1.0, 1.0], 9.0), [1.0, 1.0, 3.0]);
        let s = Motion {
            translate: None,
            stretch: Some(Stretch {
                center: [0.0; 3],
                factor: [2.0, 1.0, 0.5],
            }),
            ..m
        };
        assert_eq!(s.position([1.0, 1.0, 1.0], 3.0), [2.0, 1.0, 0.5]);
    }

    #[test]
    fn scene_text_reads_with_defaults_and_refuses_unknown_keys() {
        let p: DynamicsParams = serde_json::from_str(
            r#"{"gravity": [0, -9.81, 0], "pins": [{"select": "edge", "edge": "top"}],
                "motions": [{"pins": 0, "start": 0, "end": 1, "translate": [0, 0.01, 0]}]}"#,
        )
        .unwrap();
        assert_eq!(p.gravity, [0.0, -9.81, 0.0]);
        assert_eq!(p.dt, DynamicsParams::default().dt);
        assert_eq!(
            p.pins,
            vec![PinSelector::Edge {
                edge: Edge::Top,
                depth: 2e-3
            }]
        );
        assert!(serde_json::from_str::<DynamicsParams>(r#"{"gravty": [0, 0, 1]}"#).is_err());
        assert!(
            serde_json::from_str::<DynamicsParams>(r#"{"pins": [{"select": "edge", "edge": "top", "x": 1}]}"#).is_err()
        );
        assert!(serde_json::from_str::<DynamicsParams>(r#"{"dt": 0}"#).is_err());
    }
}
