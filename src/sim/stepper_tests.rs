use super::*;
use crate::sim::discretization::assignment::tests::crossing_fabric;
use crate::topology::PointRef;

/// Yarn 0's contact point starts 0.21 from a fixed point (rest segment
/// 1/3, safety distance 0.033): real, and the assignment holds.
fn crossing() -> Simulation {
    let f = crossing_fabric(
        &[
            [0.7, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.49, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.7, -0.5, 0.0],
            [0.7, 0.5, 0.0],
        ],
        [
            &[(1, 0.0, true), (2, 0.49, true), (0, 0.7, false), (3, 1.0, true)],
            &[(4, 0.0, true), (0, 0.5, false), (5, 1.0, true)],
        ],
        1.0,
        2,
        1,
    );
    Simulation::new(f, SimParams::default(), LinearSolver::direct(), 1e-2)
}

#[test]
fn a_contact_slid_next_to_a_fixed_point_is_a_pending_kind_change() {
    let mut sim = crossing();
    assert_eq!(sim.pending_kind_changes(), 0);
    let contact = PointRef { yarn: 0, point: 2 };
    assert!(!sim.state.assignment.is_eil(&sim.state.layout, contact));
    // Slid to 0.01 from the fixed point at 0.49: the next step would
    // make it EIL.
    let u = sim.state.layout.u(contact);
    sim.state.q[u] = 0.5;
    assert_eq!(sim.pending_kind_changes(), 1);
    sim.reassign(sim.params.assign);
    assert!(sim.state.assignment.is_eil(&sim.state.layout, contact));
    assert_eq!(sim.pending_kind_changes(), 0, "the new assignment holds");
}
