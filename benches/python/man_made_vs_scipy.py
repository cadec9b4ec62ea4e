"""Every operator on a family of man-made solids against a dense scipy solve of the same pencil.

The solids are built as in the Python tests (`crates/dirac-py/tests/solids.py`),
over a grid of sizes: prisms of circular, elliptic and toothed sections with 8, 32 and 128
sides, each side one edge or cut into 2 or 3 (flat panels with columns of vertices between
their creases), 2, 3 and 8 rings, capped by fans of thin triangles (uncut sides only: a fan
over cut sides has degenerate triangles), around a centre, or open; cubes of flat grids;
cones; vases (conical and cylindrical bands, creased between them, bottom closed or open);
unions of cubes (an L-bracket, a frame with a hole, stairs) with faces of 1-3 grids; rounded
squares extruded (flat sides tangent to cylindrical fillets). The reference (`crates/dirac-py/tests/pencils.py`) finds the kernel of `P`
numerically and solves the compressed pencil densely, knowing nothing of flat vertices, pieces,
linear functions or rulings. Meshes above `--max-vertices` are skipped (the dense solve is
`(4n)³`). One line per mesh and operator, then the counts:

    python benches/python/man_made_vs_scipy.py --max-vertices 700

`OK`: the kernel dimensions agree and every nonzero eigenvalue is within `--rtol` of scipy's
(compared by `|λ|`, then by sign below the last `|λ|`: of a pair `±λ` at the edge of the `k`
either may be listed);
`ERROR`: the package raised (its message follows); `DIFFERENT`: anything else.

Open tubes of rounded squares have pairs near the kernel (`|λ|` below `10⁻³` of the next),
which the dense reference resolves only to about `10⁻⁶` relative (its `±λ` differ by that
much), where our native, real-block and complex-adjoint backends agree with each other to
better than `10⁻⁶`; with the default `--rtol` some show as `DIFFERENT`.
"""

from __future__ import annotations

import argparse
import itertools
import pathlib
import sys

import numpy as np

import dirac_spectra as ds

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "crates/dirac-py/tests"))
from pencils import OPERATORS, by_magnitude, dense_reference  # noqa: E402
from solids import cone, cube, cut, polygon, prism, revolve, rounded_square, voxels  # noqa: E402


def solids():
    """``(name, V, F)`` of every solid of the sweep."""
    sections = {
        "circle": lambda n: polygon([1.0] * n),
        "ellipse": lambda n: polygon([1.0] * n) * [2.0, 0.7],
        "toothed": lambda n: polygon([1.0, 1.2] * (n // 2)),
    }
    for (kind, section), sides, cuts, rings, caps in itertools.product(
        sections.items(), (8, 32, 128), (1, 2, 3), (2, 3, 8), ("fan", "centre", "none")
    ):
        if caps == "fan" and cuts > 1:
            continue
        yield (f"{kind} prism, {sides} sides cut in {cuts}, {rings} rings, caps {caps}",
               *prism(cut(section(sides), cuts), rings, caps))
    for cuts in (2, 5, 10):
        yield (f"cube of {cuts} x {cuts} grids", *cube(cuts))
    for around in (16, 100):
        yield (f"cone of {around}", *cone(around))
    vase = [(0.5, 0.0), (1.0, 0.3), (1.0, 0.8), (0.6, 1.0), (0.7, 1.3)]
    for around, bottom in itertools.product((8, 24, 48), ("centre", "none")):
        yield (f"vase of {around}, bottom {bottom}", *revolve(vase, around, bottom))
    unions = {
        "L-bracket": [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (0, 2, 0)],
        "frame": [(x, y, 0) for x in range(3) for y in range(3) if (x, y) != (1, 1)],
        "stairs": [(x, 0, z) for x in range(3) for z in range(x + 1)],
    }
    for (kind, cells), cuts in itertools.product(unions.items(), (1, 2, 3)):
        yield (f"{kind} of cubes, faces {cuts} x {cuts} grids", *voxels(cells, cuts))
    for segments, rings, caps in itertools.product((1, 2, 4, 8), (2, 4), ("fan", "centre", "none")):
        yield (f"rounded square of {segments} per corner, {rings} rings, caps {caps}",
               *prism(rounded_square(segments), rings, caps))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--max-vertices", type=int, default=700)
    parser.add_argument("-k", type=int, default=10)
    parser.add_argument("--rtol", type=float, default=1e-7)
    parser.add_argument("--threshold", type=float, default=1e-12,
                        help="the reference's kernel: eigenvalues of P below this × the largest")
    args = parser.parse_args()
    counts: dict[str, int] = {}
    for name, V, F in solids():
        if len(V) > args.max_vertices:
            continue
        for operator, tau in OPERATORS:
            label = operator if tau is None else f"{operator}:{tau}"
            dimension, reference = dense_reference(V, F, operator, tau, args.threshold)
            try:
                got = ds.spectrum(V, F, k=args.k, operator=operator, tau=tau, eigenvectors=False)
            except ds.errors.DiracError as error:
                status, detail = "ERROR", f"{type(error).__name__}: {error}"
                finite = len(reference) // 4
                detail += f" (scipy: kernel {dimension}, {finite} finite nonzero eigenvalues)"
            else:
                listed = np.count_nonzero(got.eigenvalues == 0)
                ours = by_magnitude(np.repeat(got.eigenvalues[listed:], 4))
                theirs = by_magnitude(reference)[: len(ours)]
                gap = np.max(np.abs(np.abs(ours) - np.abs(theirs)) / np.abs(theirs), initial=0)
                inside = np.abs(theirs) < np.abs(theirs[-1]) * (1 - 1e-8) if len(ours) else []
                signs = np.array_equal(np.sign(ours[inside]), np.sign(theirs[inside]))
                agree = got.kernel_dimension == dimension and gap <= args.rtol and signs
                status = "OK" if agree else "DIFFERENT"
                detail = f"kernel {got.kernel_dimension} (scipy {dimension}), largest gap {gap:.1e}"
                detail += "" if signs else ", signs differ"
            counts[status] = counts.get(status, 0) + 1
            print(f"{status:9} {name} [{len(V)} vertices] {label}: {detail}", flush=True)
    print(counts)


if __name__ == "__main__":
    main()
