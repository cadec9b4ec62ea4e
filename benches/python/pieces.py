"""Writes meshes in many pieces, the test cases of docs/PERFORMANCE.md ("Meshes in many pieces"):

* ``copies N MESH OUT``: ``N`` copies of ``MESH``, the ``c``-th translated by ``c · spacing``
  along x (default spacing 3, which keeps unit-size copies apart);
* ``soup MESH OUT``: every face of ``MESH`` with its own three vertices, as an unwelded file
  (an STL export, say) comes.

    python benches/python/pieces.py copies 100 $MESHES/decimated-knight.off knights100.obj
    python benches/python/pieces.py soup $MESHES/spot.obj spot_soup.obj

Reads OBJ (``v`` and triangular ``f`` lines) and OFF; writes OBJ. Standard library only.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def read_mesh(path: Path) -> tuple[list[tuple[float, float, float]], list[tuple[int, int, int]]]:
    """Positions and triangles (0-based) of an OBJ or OFF file."""
    text = path.read_text()
    if path.suffix.lower() == ".off":
        tokens = [line.split("#")[0].split() for line in text.splitlines()]
        lines = [t for t in tokens if t]
        if lines[0][0].upper() != "OFF":
            raise SystemExit(f"{path}: not an OFF file")
        vertices, faces = int(lines[1][0]), int(lines[1][1])
        positions = [tuple(map(float, t[:3])) for t in lines[2 : 2 + vertices]]
        triangles = []
        for t in lines[2 + vertices : 2 + vertices + faces]:
            if int(t[0]) != 3:
                raise SystemExit(f"{path}: a face with {t[0]} corners")
            triangles.append(tuple(int(i) for i in t[1:4]))
        return positions, triangles
    positions, triangles = [], []
    for line in text.splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            positions.append(tuple(map(float, t[1:4])))
        elif t[0] == "f":
            if len(t) != 4:
                raise SystemExit(f"{path}: a face with {len(t) - 1} corners")
            triangles.append(tuple(int(c.split("/")[0]) - 1 for c in t[1:4]))
    return positions, triangles


def write_obj(path: Path, positions, triangles) -> None:
    with path.open("w") as out:
        out.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in positions)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    copies = commands.add_parser("copies", help="N translated copies of a mesh")
    copies.add_argument("count", type=int)
    copies.add_argument("mesh", type=Path)
    copies.add_argument("out", type=Path)
    copies.add_argument("--spacing", type=float, default=3.0)
    soup = commands.add_parser("soup", help="every face with its own vertices")
    soup.add_argument("mesh", type=Path)
    soup.add_argument("out", type=Path)
    args = parser.parse_args()

    positions, triangles = read_mesh(args.mesh)
    if args.command == "copies":
        n = len(positions)
        write_obj(
            args.out,
            [(x + c * args.spacing, y, z) for c in range(args.count) for x, y, z in positions],
            [(a + c * n, b + c * n, d + c * n) for c in range(args.count) for a, b, d in triangles],
        )
    else:
        write_obj(
            args.out,
            [positions[i] for t in triangles for i in t],
            [(3 * f, 3 * f + 1, 3 * f + 2) for f in range(len(triangles))],
        )


if __name__ == "__main__":
    main()
