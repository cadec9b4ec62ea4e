"""Times, in one run and alternating, three ways to the k smallest |λ| of relative Dirac:

* ``python``: ``dirac_spectra.read_mesh`` + ``dirac_spectra.spectrum`` (threads as given);
* ``cli``: ``dirac spectrum MESH -k K --json -q`` (a subprocess; wall time of the process);
* ``scipy``: what a researcher writes with scipy on the same pencil: ``operator_matrices
  (form="real")``, one vertex pinned (exact on a closed connected curved mesh, whose kernel is
  the constants), SuperLU of the pinned ``A``, and ARPACK ``eigsh`` on ``G y = μ A y``
  (shift-invert at 0 of ``A x = λ G x``) for the ``4k`` largest ``|μ|``.

Prints the median of each over the repetitions and the ratios, and checks that the three agree.

    python benches/python/python_vs_cli_vs_scipy.py --dirac target/release/dirac -k 20 MESH...
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import time

import numpy as np
import scipy.sparse.linalg

import dirac_spectra as ds


def python_spectrum(path: str, k: int, threads: int) -> np.ndarray:
    V, F = ds.read_mesh(path)
    return ds.spectrum(V, F, k=k, threads=threads).eigenvalues


def cli_spectrum(binary: str, path: str, k: int, threads: int) -> np.ndarray:
    command = [binary, "spectrum", path, "-k", str(k), "--json", "-q"]
    if threads == 1:
        command.append("--single-thread")
    run = subprocess.run(command, capture_output=True, text=True, check=True)
    return np.array(json.loads(run.stdout)["eigenvalues"])


def scipy_spectrum(path: str, k: int) -> np.ndarray:
    V, F = ds.read_mesh(path)
    P, Q, _ = ds.operator_matrices(V, F, operator="relative-dirac", form="real")
    keep = np.arange(4, P.shape[0])
    P_r, Q_r = P[keep][:, keep].tocsc(), Q[keep][:, keep].tocsc()
    factor = scipy.sparse.linalg.splu(P_r)
    P_inverse = scipy.sparse.linalg.LinearOperator(P_r.shape, matvec=factor.solve)
    mu = scipy.sparse.linalg.eigsh(Q_r, k=4 * k, M=P_r, Minv=P_inverse, which="LM", tol=1e-10)[0]
    values = 1.0 / mu
    return values[np.argsort(np.abs(values), kind="stable")][::4]


def timed(function, *args) -> tuple[float, np.ndarray]:
    start = time.perf_counter()
    values = function(*args)
    return time.perf_counter() - start, values


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("-k", type=int, default=20)
    parser.add_argument("--dirac", default="target/release/dirac")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--no-scipy", action="store_true")
    args = parser.parse_args()
    for path in args.meshes:
        V, F = ds.read_mesh(path)
        times: dict[str, list[float]] = {"python": [], "cli": [], "scipy": []}
        values = {}
        for _ in range(args.repeats):
            for name in ["python", "cli"] + ([] if args.no_scipy else ["scipy"]):
                if name == "python":
                    t, v = timed(python_spectrum, path, args.k, args.threads)
                elif name == "cli":
                    t, v = timed(cli_spectrum, args.dirac, path, args.k, args.threads)
                else:
                    t, v = timed(scipy_spectrum, path, args.k)
                times[name].append(t)
                values[name] = v
        reference = np.sort(values["python"])
        for name, v in values.items():
            gap = np.max(np.abs(np.sort(v) - reference) / np.abs(reference))
            assert gap < 1e-6, f"{name} disagrees with python by {gap:.1e}"
        median = {name: statistics.median(t) for name, t in times.items() if t}
        line = f"{path}: n = {len(V)}, k = {args.k}, threads = {args.threads}, " + ", ".join(
            f"{name} {t:.2f} s" for name, t in median.items()
        )
        line += f"; python/cli {median['python'] / median['cli']:.3f}"
        if "scipy" in median:
            line += f", scipy/python {median['scipy'] / median['python']:.2f}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
