#!/usr/bin/env python3
"""Reference values from ipc-toolkit's Python bindings (ipctk) for tests/contact_ipctk.rs.

Writes tests/fixtures/ipctk/{barrier,distance,ccd}.json. Run from the repository root:

    python3 -m pip install ipctk numpy
    python3 scripts/ipctk_fixtures.py

Conventions recorded in the files:
- barrier: ipctk's scalar barrier(d, dhat) and its derivatives are evaluated on
  the unsquared distance d, which is knitsim's convention. ipctk's
  BarrierPotential applies the same function to squared distances,
  b(d^2, dhat^2); one pair is recorded to pin that mapping down.
- distance: ipctk returns *squared* distances; types are ipctk's enum names.
- ccd: AdditiveCCD with its conservative_rescaling and min_distance recorded.
"""

import json
import os
import sys

import numpy as np
import ipctk

OUT = os.path.join(os.path.dirname(__file__), "..", "tests", "fixtures", "ipctk")
rng = np.random.default_rng(20240601)


def vec(a):
    return [float(v) for v in a]


def barrier_fixture():
    rows = []
    for dhat in [1e-4, 1e-3, 0.177, 1.0, 2.5]:
        for frac in [1e-6, 1e-3, 0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999999, 1.0, 1.5]:
            d = frac * dhat
            rows.append({
                "d": d, "dhat": dhat,
                "b": ipctk.barrier(d, dhat),
                "db": ipctk.barrier_first_derivative(d, dhat),
                "d2b": ipctk.barrier_second_derivative(d, dhat),
            })
    # BarrierPotential on one perpendicular edge-edge pair at distance 0.3.
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 0.3, -1], [0.5, 0.3, 1.0]])
    mesh = ipctk.CollisionMesh(V, np.array([[0, 1], [2, 3]]))
    coll = ipctk.NormalCollisions()
    coll.build(mesh, V, 0.5)
    pot = ipctk.BarrierPotential(0.5, 1.0)
    potential = {"vertices": V.tolist(), "edges": [[0, 1], [2, 3]], "distance": 0.3, "dhat": 0.5,
                 "stiffness": 1.0, "value": float(pot(coll, mesh, V))}
    return {"ipctk_version": ipctk.__version__ if hasattr(ipctk, "__version__") else "unknown",
            "rows": rows, "barrier_potential": potential}


def ee_case(label, pts):
    ea0, ea1, eb0, eb1 = [np.array(p, dtype=float) for p in pts]
    return {
        "label": label,
        "points": [vec(p) for p in (ea0, ea1, eb0, eb1)],
        "type": ipctk.edge_edge_distance_type(ea0, ea1, eb0, eb1).name,
        "distance_sq": float(ipctk.edge_edge_distance(ea0, ea1, eb0, eb1)),
    }


def pe_case(label, pts):
    p, e0, e1 = [np.array(q, dtype=float) for q in pts]
    return {
        "label": label,
        "points": [vec(q) for q in (p, e0, e1)],
        "type": ipctk.point_edge_distance_type(p, e0, e1).name,
        "distance_sq": float(ipctk.point_edge_distance(p, e0, e1)),
    }


def distance_fixture():
    ee = []
    for k in range(120):
        ee.append(ee_case(f"random {k}", rng.uniform(-1, 1, (4, 3))))
    # Segments of a yarn-like scale: short edges, some far apart, some close.
    for k in range(40):
        a0 = rng.uniform(-1, 1, 3)
        pts = [a0, a0 + rng.normal(0, 0.1, 3), a0 + rng.normal(0, 0.1, 3), a0 + rng.normal(0, 0.15, 3)]
        ee.append(ee_case(f"short {k}", pts))
    ee.append(ee_case("crossing 1e-3 apart", [[-1, 0, 0], [1, 0, 0], [0.2, -1, 1e-3], [0.2, 1, 1e-3]]))
    ee.append(ee_case("crossing 1e-6 apart", [[-1, 0, 0], [1, 0, 0], [0.2, -1, 1e-6], [0.2, 1, 1e-6]]))
    for tilt in [1e-2, 1e-3, 1e-6, 1e-8, 1e-10]:
        ee.append(ee_case(f"nearly parallel, interior, tilt {tilt:g}",
                          [[0, 0, 0], [1, 0, 0], [0.1, -tilt / 2, 0.3], [1.1, tilt / 2, 0.3]]))
        ee.append(ee_case(f"nearly parallel, end, tilt {tilt:g}",
                          [[0, 0, 0], [1, 0, 0], [0.1, 0, 0.3], [1.1, tilt, 0.3]]))
    ee.append(ee_case("parallel overlapping", [[0, 0, 0], [1, 0, 0], [0.1, 0, 0.3], [1.1, 0, 0.3]]))
    ee.append(ee_case("parallel disjoint", [[0, 0, 0], [1, 0, 0], [2, 0, 0.3], [3, 0, 0.3]]))
    ee.append(ee_case("antiparallel disjoint", [[0, 0, 0], [1, 0, 0], [3, 0, 0.3], [2, 0, 0.3]]))
    ee.append(ee_case("collinear disjoint", [[0, 0, 0], [1, 0, 0], [1.5, 0, 0], [2.5, 0, 0]]))
    ee.append(ee_case("coincident endpoint", [[0, 0, 0], [1, 0, 0], [1, 0, 0], [1.5, 1, 0.2]]))
    ee.append(ee_case("near-coincident endpoint", [[0, 0, 0], [1, 0, 0], [1.001, 0, 0], [1.5, 1, 0.2]]))
    ee.append(ee_case("zero-length A inside B", [[0.3, 0.5, 0], [0.3, 0.5, 0], [0, 0, 0], [1, 0, 0]]))
    ee.append(ee_case("zero-length A beyond B", [[1.3, 0.4, 0], [1.3, 0.4, 0], [0, 0, 0], [1, 0, 0]]))
    ee.append(ee_case("zero-length B inside A", [[0, 0, 0], [1, 0, 0], [0.4, 0.2, 0.1], [0.4, 0.2, 0.1]]))
    ee.append(ee_case("both zero-length", [[0, 0, 1], [0, 0, 1], [0, 0, 0], [0, 0, 0]]))

    pe = []
    for k in range(60):
        pe.append(pe_case(f"random {k}", rng.uniform(-1, 1, (3, 3))))
    pe.append(pe_case("interior", [[0.4, 0.3, 0.2], [0, 0, 0], [1, 0.1, 0]]))
    pe.append(pe_case("before e0", [[-0.4, 0.3, 0.2], [0, 0, 0], [1, 0.1, 0]]))
    pe.append(pe_case("after e1", [[1.4, -0.3, 0.2], [0, 0, 0], [1, 0.1, 0]]))
    pe.append(pe_case("on the line", [[0.5, 0.05, 0], [0, 0, 0], [1, 0.1, 0]]))
    pe.append(pe_case("zero-length edge", [[0.5, 0.5, 0], [0.2, 0.1, 0], [0.2, 0.1, 0]]))
    return {"edge_edge": ee, "point_edge": pe}


def ccd_fixture():
    rescale = 0.9
    ccd = ipctk.AdditiveCCD(conservative_rescaling=rescale)
    ee, pe = [], []

    def add_ee(label, x0, x1, min_distance):
        x0 = [np.array(p, dtype=float) for p in x0]
        x1 = [np.array(p, dtype=float) for p in x1]
        hit, toi = ccd.edge_edge_ccd(*x0, *x1, min_distance=min_distance, tmax=1.0)
        ee.append({"label": label, "x0": [vec(p) for p in x0], "x1": [vec(p) for p in x1],
                   "min_distance": min_distance, "hit": bool(hit), "toi": float(toi) if hit else 1.0})

    def add_pe(label, x0, x1, min_distance):
        x0 = [np.array(p, dtype=float) for p in x0]
        x1 = [np.array(p, dtype=float) for p in x1]
        hit, toi = ccd.point_edge_ccd(*x0, *x1, min_distance=min_distance, tmax=1.0)
        pe.append({"label": label, "x0": [vec(p) for p in x0], "x1": [vec(p) for p in x1],
                   "min_distance": min_distance, "hit": bool(hit), "toi": float(toi) if hit else 1.0})

    a = [[-1, 0, 0], [1, 0, 0]]
    b = [[0, -1, 1], [0, 1, 1]]
    add_ee("head-on", a + b, a + [[0, -1, -1], [0, 1, -1]], 0.0)
    add_ee("head-on, core 0.2", a + b, a + [[0, -1, -1], [0, 1, -1]], 0.2)
    add_ee("moving apart", a + b, a + [[0, -1, 2], [0, 1, 2]], 0.0)
    add_ee("rotating through", a + [[0.5, -1, 0.3], [0.5, 1, 0.3]], a + [[-0.5, 1, -0.3], [0.5, -1, -0.3]], 0.0)
    add_ee("parallel approach", [[0, 0, 0], [1, 0, 0], [0, 0, 1], [1, 0, 1]],
           [[0, 0, 0], [1, 0, 0], [0, 0, -1], [1, 0, -1]], 0.05)
    add_ee("grazing miss", a + b, a + [[0, -1, 0.01], [0, 1, 0.01]], 0.0)
    for k in range(30):
        x0 = rng.uniform(0, 1, (4, 3))
        x1 = x0 + rng.uniform(-1, 1, (4, 3))
        md = float(rng.choice([0.0, 0.01, 0.05]))
        d0 = np.sqrt(ipctk.edge_edge_distance(*x0))
        if d0 <= md:
            continue
        add_ee(f"random {k}", x0, x1, md)
    add_pe("falling point", [[0.5, 1, 0], [0, 0, 0], [1, 0, 0]], [[0.5, -3, 0], [0, 0, 0], [1, 0, 0]], 0.0)
    add_pe("falling point, core 0.1", [[0.5, 1, 0], [0, 0, 0], [1, 0, 0]], [[0.5, -3, 0], [0, 0, 0], [1, 0, 0]], 0.1)
    add_pe("edge sweeping", [[0.5, 0, 1], [0, 0, 0], [1, 0, 0]], [[0.5, 0, 1], [0, 0, 2], [1, 0, 2]], 0.0)
    for k in range(15):
        x0 = rng.uniform(0, 1, (3, 3))
        x1 = x0 + rng.uniform(-1, 1, (3, 3))
        add_pe(f"random {k}", x0, x1, 0.0)
    return {"method": "ipctk.AdditiveCCD", "conservative_rescaling": rescale,
            "max_iterations": "ipctk default", "tmax": 1.0, "edge_edge": ee, "point_edge": pe}


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, data in [("barrier", barrier_fixture()), ("distance", distance_fixture()), ("ccd", ccd_fixture())]:
        path = os.path.join(OUT, f"{name}.json")
        with open(path, "w") as f:
            json.dump(data, f, indent=1)
        print(f"wrote {path} ({os.path.getsize(path)} bytes)", file=sys.stderr)


if __name__ == "__main__":
    main()
