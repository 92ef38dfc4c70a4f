#!/usr/bin/env python3
"""Read a mesh with meshio and check it against what the writer intended.

Usage: check_mesh.py FILE POINTS CELLS [--cell-type T] [--point-data NAME]...
                     [--cell-data NAME]...

Exits 0 and prints a JSON summary (counts, cell types, data field shapes, and
a value histogram of every integer point-data field) when everything matches;
exits 1 with one line per mismatch otherwise, 2 when meshio is missing or
cannot read the file. Used by tests/export_meshio.rs as an independent
reader of knitsim's VTK and OBJ output.
"""

import argparse
import json
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("path")
    parser.add_argument("points", type=int, help="expected number of points")
    parser.add_argument("cells", type=int, help="expected number of cells, all blocks")
    parser.add_argument("--cell-type", help="every cell block must have this meshio type")
    parser.add_argument("--point-data", action="append", default=[], help="required point field")
    parser.add_argument("--cell-data", action="append", default=[], help="required cell field")
    args = parser.parse_args()

    try:
        import meshio
    except ImportError as e:
        print(f"check_mesh: meshio is not installed ({e}); pip install -r tests/python-requirements.txt")
        return 2
    try:
        mesh = meshio.read(args.path)
    except Exception as e:  # meshio raises several unrelated types
        print(f"check_mesh: meshio {meshio.__version__} cannot read {args.path}: {e}")
        return 2

    errors = []
    n_points = len(mesh.points)
    n_cells = sum(len(block.data) for block in mesh.cells)
    types = sorted({block.type for block in mesh.cells})
    if n_points != args.points:
        errors.append(f"points: expected {args.points}, meshio read {n_points}")
    if n_cells != args.cells:
        errors.append(f"cells: expected {args.cells}, meshio read {n_cells}")
    if args.cell_type is not None and types != [args.cell_type]:
        errors.append(f"cell types: expected only {args.cell_type!r}, meshio read {types}")
    for name in args.point_data:
        if name not in mesh.point_data:
            errors.append(f"point data {name!r} missing (have {sorted(mesh.point_data)})")
        elif len(mesh.point_data[name]) != n_points:
            errors.append(f"point data {name!r} has {len(mesh.point_data[name])} rows for {n_points} points")
    for name in args.cell_data:
        if name not in mesh.cell_data:
            errors.append(f"cell data {name!r} missing (have {sorted(mesh.cell_data)})")
        else:
            rows = sum(len(block) for block in mesh.cell_data[name])
            if rows != n_cells:
                errors.append(f"cell data {name!r} has {rows} rows for {n_cells} cells")

    if errors:
        for e in errors:
            print(f"check_mesh: {args.path}: {e}")
        return 1

    summary = {
        "points": n_points,
        "cells": n_cells,
        "cell_types": types,
        "point_data_shapes": {k: list(v.shape) for k, v in mesh.point_data.items()},
        "cell_data_shapes": {k: [list(b.shape) for b in v] for k, v in mesh.cell_data.items()},
        "point_data_histograms": {
            k: {str(int(val)): int((v == val).sum()) for val in sorted(set(v.ravel().tolist()))}
            for k, v in mesh.point_data.items()
            if v.dtype.kind in "iu"
        },
    }
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
