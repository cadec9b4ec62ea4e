"""Times the level-L icosphere Laplacian spectrum of `compare eigs` against scipy, alternating.

`compare eigs --cases native,real-scalar` solves the pencil `M x = μ (L + εM) x` (cotangent
Laplacian `L`, barycentric masses `M`, `ε = 1e-3`, constants deflated, tolerance 1e-8) for the
`k` largest `μ`, natively over the quaternions (`L⊗I`) and over `f64`; its JSON times the
factorisation and the Lanczos iteration on the assembled pencil. The scipy case is what a
researcher writes for the real scalar Laplacian of the same mesh: `eigsh(L, k + 1, M,
sigma=-ε, tol=1e-8)`, shift-invert ARPACK with SuperLU on `L + εM` (the same operator,
`(L + εM)⁻¹ M`), the constant's eigenvalue included and dropped; its time covers the
factorisation and the iteration, not the assembly. The icosphere, `L` and `M` are those the
Python tests build with numpy (`crates/dirac-py/tests/reference.py`), independently of the Rust
code, and the eigenvalues `λ = 1/μ − ε` of every path must agree with scipy's.

    taskset -c 0 python benches/python/eigs_vs_scipy.py --compare target/release/compare \\
        --level 5 -k 60 --repeats 5 --single-thread

Run it under `taskset -c 0` for one core: `--single-thread` keeps our solver on one thread,
and OpenBLAS is limited to one thread before numpy is imported.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.sparse  # noqa: E402
import scipy.sparse.linalg  # noqa: E402

# The numpy references of the Python tests: the icosphere, the cotangent Laplacian, the masses.
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "crates/dirac-py/tests"))
from reference import cotangent_laplacian, icosphere  # noqa: E402

EPSILON = 1e-3
TOLERANCE = 1e-8


def scipy_spectrum(L, M, k: int) -> np.ndarray:
    values = scipy.sparse.linalg.eigsh(L, k=k + 1, M=M, sigma=-EPSILON, which="LM", tol=TOLERANCE)[0]
    return np.sort(values)[1:]


def ours(compare: str, level: int, k: int, single_thread: bool) -> dict:
    command = [compare, "eigs", "--level", str(level), "-k", str(k), "--repeats", "1"]
    command += ["--cases", "native,real-scalar"] + (["--single-thread"] if single_thread else [])
    return json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--compare", default="target/release/compare")
    parser.add_argument("--level", type=int, default=5)
    parser.add_argument("-k", type=int, default=60)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--single-thread", action="store_true")
    args = parser.parse_args()
    V, F = icosphere(args.level)
    L, mass = cotangent_laplacian(V, F)
    M = scipy.sparse.diags_array(mass).tocsc()
    times: dict[str, list[float]] = {"native": [], "real-scalar": [], "scipy": []}
    for _ in range(args.repeats):
        report = ours(args.compare, args.level, args.k, args.single_thread)
        start = time.perf_counter()
        reference = scipy_spectrum(L, M, args.k)
        times["scipy"].append(time.perf_counter() - start)
        for case in ["native", "real-scalar"]:
            result = report[case]
            assert result["converged"] == args.k, f"{case}: {result}"
            times[case].append(result["seconds"])
            values = np.sort(1.0 / np.array(result["eigenvalues"]) - EPSILON)
            gap = np.max(np.abs(values - reference) / reference)
            assert gap < 1e-6, f"{case} disagrees with scipy by {gap:.1e}"
    median = {case: statistics.median(t) for case, t in times.items()}
    print(
        f"level {args.level} ({len(V)} vertices), k = {args.k}, "
        f"{'one thread' if args.single_thread else 'two threads'}, medians of {args.repeats}: "
        + ", ".join(f"{case} {t:.3f} s" for case, t in median.items())
        + f"; native/real-scalar {median['native'] / median['real-scalar']:.2f}, "
        f"native/scipy {median['native'] / median['scipy']:.2f}, "
        f"real-scalar/scipy {median['real-scalar'] / median['scipy']:.2f}"
    )
    print("all samples:", json.dumps({case: [round(t, 3) for t in s] for case, s in times.items()}))


if __name__ == "__main__":
    main()
