//! Segment pairs joined by a persistent EoL contact, which must not get a
//! thickness barrier near that contact.
//!
//! Why: an EoL contact node is *one* position shared by two yarns (docs/MODEL.md,
//! "Kinematics"; thickness is added only when rendering), so the two centrelines meet
//! there at distance zero. Any barrier between segments next to the node
//! would fight the persistent contact that holds them together. A barrier
//! pair is therefore dropped when one segment lies within `radius` (rest arc
//! length, along its own yarn) of one side of a contact and the other
//! segment within `radius` of the *other* side. Two segments near the same
//! side are one yarn folding back on itself there, which keeps its barrier.
//!
//! Measuring in `u` rather than through the node graph matters for EIL: when
//! both points of a contact are EIL this step, its node is on no segment,
//! yet the two yarns still meet at the interpolated points. The `u` of each
//! contact point is always defined, so the rule holds whatever the
//! assignment.

/// One side of a persistent contact: a yarn and the contact point's `u`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSide {
    pub yarn: u32,
    pub u: f64,
}

/// For each segment, the contact sides within the exclusion radius of it,
/// encoded `2 * contact + side` and sorted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JoinedSegments {
    near: Vec<Vec<u32>>,
}

impl JoinedSegments {
    /// `segments[i] = (yarn, u_start, u_end)`; `contacts[c]` lists both sides
    /// of contact `c`. `radius` is the exclusion distance in `u`.
    pub fn new(segments: &[(u32, f64, f64)], contacts: &[[ContactSide; 2]], radius: f64) -> Self {
        // Per yarn: contact `u`s sorted, with their contact index.
        let n_yarns = segments.iter().map(|s| s.0 as usize + 1).max().unwrap_or(0);
        let mut by_yarn: Vec<Vec<(f64, u32)>> = vec![Vec::new(); n_yarns];
        for (c, sides) in contacts.iter().enumerate() {
            for (k, s) in sides.iter().enumerate() {
                if let Some(list) = by_yarn.get_mut(s.yarn as usize) {
                    list.push((s.u, 2 * c as u32 + k as u32));
                }
            }
        }
        for list in &mut by_yarn {
            list.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        let near = segments
            .iter()
            .map(|&(yarn, u0, u1)| {
                let (lo, hi) = (u0.min(u1) - radius, u0.max(u1) + radius);
                let list = &by_yarn[yarn as usize];
                let first = list.partition_point(|e| e.0 < lo);
                let mut ids: Vec<u32> = list[first..].iter().take_while(|e| e.0 <= hi).map(|e| e.1).collect();
                ids.sort_unstable();
                ids.dedup();
                ids
            })
            .collect();
        Self { near }
    }

    /// Whether segments `i` and `j` are near opposite sides of one contact.
    pub fn joined(&self, i: usize, j: usize) -> bool {
        let (Some(a), Some(b)) = (self.near.get(i), self.near.get(j)) else {
            return false;
        };
        a.iter().any(|side| b.binary_search(&(side ^ 1)).is_ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_near_a_shared_contact_are_joined() {
        // Yarn 0: segments [0,1], [1,2], [2,3]; yarn 1: [0,1], [1,2].
        // Contact 0 at u = 1.5 on yarn 0 and u = 0.2 on yarn 1.
        let segs = [
            (0, 0.0, 1.0),
            (0, 1.0, 2.0),
            (0, 2.0, 3.0),
            (1, 0.0, 1.0),
            (1, 1.0, 2.0),
        ];
        let contacts = [[ContactSide { yarn: 0, u: 1.5 }, ContactSide { yarn: 1, u: 0.2 }]];
        let j = JoinedSegments::new(&segs, &contacts, 0.6);
        // Yarn 0 segments within 0.6 of u = 1.5: [0,1] (gap 0.5), [1,2], [2,3] (0.5).
        // Yarn 1 within 0.6 of 0.2: [0,1] only ([1,2] is 0.8 away).
        assert!(j.joined(1, 3) && j.joined(0, 3) && j.joined(2, 3));
        assert!(!j.joined(1, 4));
        // Both near the same side (yarn 0 folding back): not joined.
        assert!(!j.joined(0, 2));
        let tight = JoinedSegments::new(&segs, &contacts, 0.1);
        assert!(tight.joined(1, 3) && !tight.joined(0, 3));
    }
}
