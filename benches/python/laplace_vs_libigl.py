"""Times, in one run and alternating, the Laplace spectrum from a mesh file, end to end:

* ``cli``: ``dirac spectrum MESH --operator laplace -k K --json -q`` (a subprocess; wall time of
  the process: reading the mesh, assembly, kernel, factorisation, Lanczos, residuals, JSON);
* ``cli-old`` (with ``--old BINARY``): the same with another build, e.g. the quaternionic path
  of a previous commit;
* ``python`` (when ``dirac_spectra`` is importable and ``--python`` is given):
  ``dirac_spectra.read_mesh`` + ``dirac_spectra.spectrum(operator="laplace")``;
* ``libigl``: what a researcher writes with libigl and scipy: ``igl.read_triangle_mesh``,
  ``L = -igl.cotmatrix`` (libigl's is negative semidefinite, ours positive), the barycentric
  ``igl.massmatrix`` (our vertex masses, docs/MATH.md "The operators"), and ARPACK ``eigsh``
  in shift-invert mode about a small negative shift (``L`` itself is singular) for the ``K``
  eigenvalues nearest it: the kernel (one zero per component) and the smallest nonzero ones,
  which is what ``-k K`` returns for Laplace (the kernel is listed by default).

The runners alternate, in an order rotated at each repetition. Prints the median wall time of
each over the repetitions, the median CPU time (user + system,
all threads; for the command line that of the child process), which a loaded machine disturbs
less, the ratios, and the largest relative difference of the eigenvalues against libigl (the kernel's zeros compared in absolute terms,
relative to the largest eigenvalue).

    python benches/python/laplace_vs_libigl.py --dirac target/release/dirac -k 20 MESH...

OpenBLAS is limited to one thread (unless ``OPENBLAS_NUM_THREADS`` is set): this process stays
alive between the runners, and OpenBLAS threads left spinning after ``eigsh`` took a core from
the command line that ran next (ARPACK's vector operations at these sizes gain nothing from
them).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import igl  # noqa: E402
import numpy as np  # noqa: E402
import scipy.sparse.linalg  # noqa: E402


def cli_spectrum(binary: str, path: str, k: int) -> np.ndarray:
    command = [binary, "spectrum", path, "--operator", "laplace", "-k", str(k), "--json", "-q"]
    run = subprocess.run(command, capture_output=True, text=True, check=True)
    return np.array(json.loads(run.stdout)["eigenvalues"])


def python_spectrum(path: str, k: int) -> np.ndarray:
    import dirac_spectra as ds

    V, F = ds.read_mesh(path)
    return ds.spectrum(V, F, k=k, operator="laplace").eigenvalues


def libigl_spectrum(path: str, k: int, tol: float) -> np.ndarray:
    V, F = igl.read_triangle_mesh(path)
    L = -igl.cotmatrix(V, F)
    M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_BARYCENTRIC)
    # A shift below the spectrum, relative to the operator's scale, makes L - σM definite.
    sigma = -1e-8 * L.diagonal().sum() / M.diagonal().sum()
    values = scipy.sparse.linalg.eigsh(
        L.tocsc(), k=k, M=M.tocsc(), sigma=sigma, which="LM", tol=tol
    )[0]
    return np.sort(values)


def cpu_seconds() -> float:
    """User + system time of this process and of its finished children."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed(function, *args) -> tuple[float, float, np.ndarray]:
    start, cpu = time.perf_counter(), cpu_seconds()
    values = function(*args)
    return time.perf_counter() - start, cpu_seconds() - cpu, values


def difference(values: np.ndarray, truth: np.ndarray) -> float:
    """Largest |a − b| / |b| over the nonzero eigenvalues, |a − b| / max|b| over the zeros."""
    a, b = np.sort(values), np.sort(truth)
    scale = np.abs(b).max()
    zero = np.abs(b) <= 1e-8 * scale
    relative = np.abs(a - b) / np.where(zero, scale, np.abs(b))
    return float(relative.max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("-k", type=int, default=20)
    parser.add_argument("--dirac", default="target/release/dirac")
    parser.add_argument("--old", help="a second dirac binary to time alongside (cli-old)")
    parser.add_argument("--python", action="store_true", help="also time dirac_spectra")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument(
        "--tol", type=float, default=1e-10, help="eigsh tolerance (ours: 1e-10 relative residual)"
    )
    args = parser.parse_args()
    runners = {"cli": lambda path: cli_spectrum(args.dirac, path, args.k)}
    if args.old:
        runners["cli-old"] = lambda path: cli_spectrum(args.old, path, args.k)
    if args.python:
        runners["python"] = lambda path: python_spectrum(path, args.k)
    runners["libigl"] = lambda path: libigl_spectrum(path, args.k, args.tol)
    for path in args.meshes:
        times: dict[str, list[float]] = {name: [] for name in runners}
        cpu: dict[str, list[float]] = {name: [] for name in runners}
        values = {}
        for repeat in range(args.repeats):
            # Rotated each repetition: whoever runs right after libigl (a Python process that
            # leaves the caches cold) would otherwise always be the same.
            order = list(runners.items())
            order = order[repeat % len(order) :] + order[: repeat % len(order)]
            for name, runner in order:
                t, c, v = timed(runner, path)
                times[name].append(t)
                cpu[name].append(c)
                values[name] = v
        median = {name: statistics.median(ts) for name, ts in times.items()}
        median_cpu = {name: statistics.median(cs) for name, cs in cpu.items()}
        row = {
            "mesh": path,
            "k": args.k,
            "repeats": args.repeats,
            "median_seconds": median,
            "median_cpu_seconds": median_cpu,
            "libigl_over": {
                name: median["libigl"] / median[name] for name in runners if name != "libigl"
            },
            "libigl_over_cpu": {
                name: median_cpu["libigl"] / median_cpu[name]
                for name in runners
                if name != "libigl"
            },
            "largest_relative_difference_to_libigl": {
                name: difference(values[name], values["libigl"])
                for name in runners
                if name != "libigl"
            },
        }
        if "cli-old" in median:
            row["old_over_new"] = median["cli-old"] / median["cli"]
        print(json.dumps(row))


if __name__ == "__main__":
    main()
