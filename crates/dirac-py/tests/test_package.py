"""The package as a user meets it: agreement with the command line, invariances, inputs, errors,
pickling, threads and the GIL."""

from __future__ import annotations

import json
import os
import pickle
import re
import signal
import subprocess
import threading
import time
import warnings

import numpy as np
import pytest

import dirac_spectra as ds
from conftest import grid, random_rotation, torus
from reference import icosphere


def test_the_same_spectrum_as_the_command_line_on_spot(dirac_binary, tmp_path):
    V, F = ds.default_mesh()
    path = tmp_path / "spot.obj"
    ds.write_mesh(path, V, F)
    run = subprocess.run(
        [str(dirac_binary), "spectrum", str(path), "-k", "12", "--json", "-q"],
        capture_output=True, text=True, check=True,
    )
    report = json.loads(run.stdout)
    result = ds.spectrum(V, F, k=12)
    assert report["converged"] is True
    assert report["kernel_dimension"] == result.kernel_dimension
    np.testing.assert_allclose(result.eigenvalues, report["eigenvalues"], rtol=1e-12)


def test_the_default_mesh_reads_back_from_every_writable_format(tmp_path):
    V, F = ds.default_mesh()
    assert V.shape == (2930, 3) and F.shape == (5856, 3)
    assert V.dtype == np.float64 and F.dtype == np.int64
    for name in ["spot.obj", "spot.ply"]:
        ds.write_mesh(tmp_path / name, V, F)
        V2, F2 = ds.read_mesh(tmp_path / name)
        np.testing.assert_array_equal(F2, F)
        np.testing.assert_allclose(V2, V, rtol=1e-15 if name.endswith("ply") else 1e-12)


def write_stl(path, triangles: np.ndarray, binary: bool) -> None:
    """``triangles`` ``(m, 3, 3)`` as an STL file, each with its own corners (written here with
    numpy, not by the package, which writes no STL)."""
    if binary:
        records = np.zeros(len(triangles), dtype=[("normal", "<f4", 3), ("corners", "<f4", 9),
                                                  ("attribute", "<u2")])
        records["corners"] = triangles.reshape(-1, 9)
        header = b"solid written by numpy".ljust(80) + np.uint32(len(triangles)).tobytes()
        path.write_bytes(header + records.tobytes())
    else:
        facets = "".join(
            "facet normal 0 0 0\n outer loop\n"
            + "".join(f"  vertex {x!r} {y!r} {z!r}\n" for x, y, z in corners)
            + " endloop\nendfacet\n"
            for corners in triangles.tolist()
        )
        path.write_text(f"solid spot\n{facets}endsolid spot\n")


@pytest.mark.parametrize("binary", [False, True])
def test_an_stl_file_reads_as_the_mesh_it_was_written_from(tmp_path, binary):
    V, F = ds.default_mesh()
    path = tmp_path / "spot.stl"
    write_stl(path, V[F], binary)
    V2, F2 = ds.read_mesh(path)
    # The corners shared by several triangles are one vertex again, and the faces keep their
    # order, corners and orientation.
    assert V2.shape == V.shape and F2.shape == F.shape
    expected = V[F].astype(np.float32) if binary else V[F]
    np.testing.assert_array_equal(V2[F2], expected)
    first = ds.spectrum(V, F, k=6, operator="laplace").eigenvalues
    np.testing.assert_allclose(ds.spectrum(V2, F2, k=6, operator="laplace").eigenvalues, first,
                               rtol=1e-6 if binary else 1e-12)


@pytest.mark.parametrize("operator", ["relative-dirac", "laplace", "extrinsic-dirac"])
def test_eigenvalues_are_invariant_under_rigid_motions(operator):
    V, F = torus(30, 12)
    rng = np.random.default_rng(7)
    # Bumps break the torus's symmetries, so that no eigenspace is cut at k.
    V = V * (1 + 0.05 * rng.uniform(-1, 1, (len(V), 1)))
    moved = V @ random_rotation(rng).T + rng.normal(size=3) * 10
    first = ds.spectrum(V, F, k=10, operator=operator)
    second = ds.spectrum(moved, F, k=10, operator=operator)
    np.testing.assert_allclose(second.eigenvalues, first.eigenvalues, rtol=1e-8)
    # So are the per-vertex |φ|² sums over an eigenspace-complete set (all ten pairs here are
    # compared through the Dirac kernel signature at one time).
    t = [1.0 / abs(first.eigenvalues[-1])]
    np.testing.assert_allclose(ds.dks(second, times=t).values, ds.dks(first, times=t).values,
                               rtol=1e-6)


def test_any_real_dtype_and_memory_order_gives_the_same_spectrum(sphere):
    V, F = sphere
    reference = ds.spectrum(V, F, k=6).eigenvalues
    for V2, F2 in [
        (np.asfortranarray(V), np.asfortranarray(F)),
        (V.astype(np.longdouble), F.astype(np.uint32)),
        (V.tolist(), F.astype(np.int16).tolist()),
        (V[:, [0, 1, 2]], F[::1]),
    ]:
        np.testing.assert_allclose(ds.spectrum(V2, F2, k=6).eigenvalues, reference, rtol=1e-12)
    single = ds.spectrum(V.astype(np.float32), F, k=6).eigenvalues
    np.testing.assert_allclose(single, reference, rtol=1e-5)


def test_bad_dtypes_and_shapes_say_what_was_expected(sphere):
    V, F = sphere
    with pytest.raises(TypeError, match=r"F must hold vertex indices .*F\.astype\(np.int64\)"):
        ds.spectrum(V, F.astype(float))
    with pytest.raises(TypeError, match="V must hold real numbers"):
        ds.spectrum(V.astype(complex), F)
    with pytest.raises(ValueError, match=r"V must have shape \(n, 3\).*got shape \(642, 2\)"):
        ds.spectrum(V[:, :2], F)
    with pytest.raises(ValueError, match=r"F must have shape \(m, 3\)"):
        ds.spectrum(V, F.ravel())
    with pytest.raises(TypeError, match="k must be an integer"):
        ds.spectrum(V, F, k=2.5)


def test_mesh_errors_name_the_bad_element(sphere):
    V, F = sphere
    repeated = F.copy()
    repeated[17, 2] = repeated[17, 0]
    with pytest.raises(ds.MeshError, match="face 17 repeats vertex") as error:
        ds.spectrum(V, repeated)
    assert isinstance(error.value, ValueError) and error.value.face == 17
    out_of_range = F.copy()
    out_of_range[3, 1] = len(V) + 5
    with pytest.raises(ds.MeshError, match="face 3 refers to vertex 647") as error:
        ds.spectrum(V, out_of_range)
    assert error.value.vertex == 647
    negative = F.copy()
    negative[9, 0] = -1
    with pytest.raises(ds.MeshError, match="face 9 refers to vertex -1"):
        ds.spectrum(V, negative)
    broken = V.copy()
    broken[40, 1] = np.nan
    with pytest.raises(ds.MeshError, match="vertex 40 has a non-finite coordinate"):
        ds.laplacian(broken, F)


def test_file_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        ds.read_mesh(tmp_path / "missing.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 x\n")
    with pytest.raises(ds.MeshFileError, match="line 3"):
        ds.read_mesh(bad)
    with pytest.raises(ds.MeshFileError, match="unknown mesh format"):
        ds.read_mesh(tmp_path / "mesh.3ds")
    (tmp_path / "folder.obj").mkdir()
    with pytest.raises(OSError, match="is a directory, not a mesh file"):
        ds.read_mesh(tmp_path / "folder.obj")
    V, F = icosphere(0)
    with pytest.raises(ds.MeshFileError, match="cannot write this format"):
        ds.write_mesh(tmp_path / "mesh.stl", V, F)


def test_option_errors(sphere):
    V, F = sphere
    cases = [
        (dict(operator="dirac"), "unknown operator \"dirac\"; expected one of laplace"),
        (dict(operator="family"), "needs tau"),
        (dict(operator="laplace", tau=0.5), "takes no tau"),
        (dict(operator="family", tau=1.5), "tau = 1.5 is outside"),
        (dict(operator="anisotropic-laplace"), "needs anisotropy"),
        (dict(operator="anisotropic-laplace", tau=0.5), "takes no tau"),
        (dict(operator="laplace", anisotropy=1.0), "takes no anisotropy"),
        (dict(operator="anisotropic-laplace", anisotropy=-1.0), r"anisotropy = -1 is outside \[0, ∞\)"),
        (dict(k=0), "cannot compute 0 eigenvalues"),
        (dict(k=10_000), "cannot compute 10000 eigenvalues"),
        (dict(backend="gpu"), "unknown backend"),
        (dict(normalize="unit-volume"), "unknown normalize"),
        (dict(threads=3), "the solver uses 1 or 2 threads"),
        (dict(flat_tolerance=-1.0), "flat tolerance -1 must be"),
        (dict(tolerance=0.0), "tolerance 0 must lie strictly between 0 and 1"),
        (dict(max_restarts=0), "max_restarts must be at least 1"),
        (
            dict(well=ds.PotentialWell(radius=0.3, center=10_000)),
            r"centre vertex 10000 does not exist \(the mesh has \d+ vertices\): give one from 0",
        ),
    ]
    for options, message in cases:
        with pytest.raises(ds.OptionsError, match=message):
            ds.spectrum(V, F, **options)
    with pytest.raises(ds.OptionsError, match="unknown form"):
        ds.operator_matrices(V, F, form="quaternion")


def test_kernel_errors_suggest_python_keywords():
    V, F = grid(6, 6)
    with pytest.raises(ds.KernelError, match="include_kernel=True") as error:
        ds.spectrum(V, F, k=4)
    assert "--" not in str(error.value)
    kernel = ds.spectrum(V, F, k=4, include_kernel=True)
    assert kernel.kernel_dimension == len(V) and np.all(kernel.eigenvalues == 0)
    V, F = icosphere(0)
    with pytest.raises(ds.KernelError, match="asked for 12 nonzero eigenvalues"):
        ds.spectrum(V, F, k=12)


def test_a_nearly_flat_region_raises_singular_error_with_the_vertex():
    # A plane with noise far below the curvature of any real surface: with flat_tolerance = 0
    # no face is flat and the operator nearly vanishes everywhere except one bump.
    V, F = grid(12, 12)
    rng = np.random.default_rng(1)
    V = V.copy()
    V[:, 2] += 1e-12 * rng.uniform(-1, 1, len(V))
    centre = np.argmin(np.linalg.norm(V[:, :2] - 0.5, axis=1))
    V[centre, 2] = 0.2
    raised = None
    try:
        ds.spectrum(V, F, k=4, flat_tolerance=0.0)
    except (ds.SingularError, ds.NotConvergedError) as error:
        raised = error
    assert isinstance(raised, ds.SingularError), f"expected SingularError, got {raised!r}"
    assert isinstance(raised, ArithmeticError) and "flat_tolerance=" in str(raised)
    # The advice works: the tolerance it names flattens the noisy plane, not the bump (the
    # largest flatness next to the failing vertex is the bump's, 8.7; advising a tolerance
    # above it made every face flat and the operator vanish).
    advised = float(re.search(r"flat_tolerance=([0-9.e+-]+)", str(raised)).group(1))
    assert advised < 1e-2
    result = ds.spectrum(V, F, k=4, flat_tolerance=advised)
    assert np.all(np.abs(result.eigenvalues) > 1.0)


def test_non_convergence_carries_the_converged_part(sphere):
    V, F = sphere
    with pytest.raises(ds.NotConvergedError) as error:
        ds.spectrum(V, F, k=40, max_restarts=1, tolerance=1e-14)
    partial = error.value.partial
    assert isinstance(error.value, ds.SolverError) and error.value.wanted == 40
    assert isinstance(partial, ds.Spectrum) and partial.k < 40
    assert np.all(partial.converged)
    full = ds.spectrum(V, F, k=40)
    # Every converged pair is one of the true ones.
    for lam in partial.eigenvalues:
        assert np.min(np.abs(full.eigenvalues - lam)) <= 1e-8 * abs(lam)


def test_descriptor_errors_and_values(sphere):
    V, F = sphere
    dirac = ds.spectrum(V, F, k=10)
    with pytest.raises(ds.DescriptorError, match="negative"):
        ds.hks(dirac)
    without = ds.spectrum(V, F, k=4, eigenvectors=False)
    assert without.eigenvectors is None
    with pytest.raises(ds.DescriptorError, match="eigenvectors=True"):
        ds.dks(without)
    # HKS from a Laplace spectrum: Σ_i e^{−tλ_i} |φ_i(v)|², checked here directly.
    laplace = ds.spectrum(V, F, k=10, operator="laplace")
    times = np.array([0.01, 0.1])
    expected = np.einsum(
        "ti,pi->pt", np.exp(-np.outer(times, laplace.eigenvalues)),
        np.sum(laplace.eigenvectors**2, axis=2),
    )
    np.testing.assert_allclose(ds.hks(laplace, times=times).values, expected, rtol=1e-12)
    # From a mesh directly, with spectrum options.
    from_mesh = ds.hks(V, F, times=times, k=10)
    np.testing.assert_allclose(np.asarray(from_mesh), expected, rtol=1e-9)
    wave = ds.wks(laplace, count=5)
    assert wave.values.shape == (len(V), 5) and wave.sigma > 0
    # Σ_v m_v WKS_e(v) = 1 for every energy (mass-normalised eigenvectors).
    np.testing.assert_allclose(laplace.mass @ wave.values, 1.0, rtol=1e-10)
    segmentation = ds.segmentation_descriptor(dirac)
    np.testing.assert_allclose(
        segmentation.values[:, 0],
        np.linalg.norm(dirac.eigenvectors[:, 0, :], axis=1) / np.sqrt(abs(dirac.eigenvalues[0])),
    )


def test_results_pickle(sphere):
    V, F = sphere
    result = ds.spectrum(V, F, k=5, operator="family", tau=0.25)
    copy = pickle.loads(pickle.dumps(result))
    np.testing.assert_array_equal(copy.eigenvalues, result.eigenvalues)
    np.testing.assert_array_equal(copy.eigenvectors, result.eigenvectors)
    assert copy.tau == 0.25 and copy.statistics == result.statistics
    error = None
    try:
        ds.spectrum(V, F, k=30, max_restarts=1, tolerance=1e-14)
    except ds.NotConvergedError as e:
        error = e
    assert error is not None
    assert pickle.loads(pickle.dumps(error.partial)).k == error.partial.k


def test_one_thread_by_default():
    V, F = torus(160, 60)  # 9600 vertices: a solve of about a second
    wall, cpu = time.perf_counter(), time.process_time()
    ds.spectrum(V, F, k=20)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    assert cpu <= 1.15 * wall + 0.05, f"{cpu:.2f} s of CPU in {wall:.2f} s with one thread"
    assert ds.spectrum(V, F, k=4, threads=2).k == 4


def _spectrum_in_a_worker(V, F):
    return ds.spectrum(V, F, k=8, threads=2).eigenvalues


def test_a_forked_worker_solves_after_the_parent_used_two_threads():
    # The parent's helper thread does not exist in a child made by fork: the child must not
    # wait for it, and computes the same halves on its own threads, so the same numbers.
    import multiprocessing

    V, F = torus(160, 60)
    parent = ds.spectrum(V, F, k=8, threads=2).eigenvalues
    with multiprocessing.get_context("fork").Pool(1) as pool:
        child = pool.apply_async(_spectrum_in_a_worker, (V, F)).get(timeout=120)
    np.testing.assert_array_equal(child, parent)


def test_the_gil_is_released_during_a_solve():
    V, F = torus(160, 60)
    done = threading.Event()
    solve_time = []

    def solve():
        start = time.perf_counter()
        ds.spectrum(V, F, k=20)
        solve_time.append(time.perf_counter() - start)
        done.set()

    worker = threading.Thread(target=solve)
    ticks = []
    worker.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    gaps = np.diff(ticks)
    assert solve_time[0] > 0.3
    # This thread kept running while the other one solved.
    assert len(ticks) > 50 and gaps.max() < 0.25 * solve_time[0], (len(ticks), gaps.max())


def test_progress_is_reported_and_an_exception_from_it_stops_the_solve():
    V, F = torus(160, 60)
    states = []
    start = time.perf_counter()
    full = ds.spectrum(V, F, k=40, progress=states.append)
    full_seconds = time.perf_counter() - start
    # Every restart is reported, and steps between restarts at least every 0.1 s.
    assert {s["restarts"] for s in states} >= set(range(1, full.statistics["restarts"] + 1))
    assert full.statistics["restarts"] >= 3
    assert states[-1]["locked"] <= states[-1]["wanted"] == 40
    assert all(s["operator_applications"] > 0 for s in states)

    class Stop(Exception):
        pass

    def stop_after_one(state):
        raise Stop(state["restarts"])

    # Wall time against wall time (the solver's own total leaves out the assembly).
    start = time.perf_counter()
    with pytest.raises(Stop):
        ds.spectrum(V, F, k=40, progress=stop_after_one)
    assert time.perf_counter() - start < 0.7 * full_seconds


def test_a_time_limit_stops_the_solver_with_what_converged():
    V, F = torus(160, 60)
    states = []
    full = ds.spectrum(V, F, k=40, progress=states.append)
    # A limit that has passed at the first report (a restart, or a step 0.1 s into the solve)
    # stops the solver there: the pairs locked by then, each the full solve's to its residuals.
    with pytest.raises(ds.NotConvergedError, match="stopped at the time limit of 0.000000001 s") as error:
        ds.spectrum(V, F, k=40, time_limit=1e-9)
    assert error.value.stopped_at_time_limit
    partial = error.value.partial
    assert partial.statistics["restarts"] <= 1 < full.statistics["restarts"]
    assert len(partial.eigenvalues) < 40
    for value in partial.eigenvalues:
        assert np.min(np.abs(full.eigenvalues - value)) <= 1e-8 * abs(value)
    # A limit that leaves room changes nothing, even one beyond what a clock holds.
    for roomy in (600, 1e300):
        np.testing.assert_array_equal(
            ds.spectrum(V, F, k=40, time_limit=roomy).eigenvalues, full.eigenvalues
        )
    with pytest.raises(ds.NotConvergedError) as other:
        ds.spectrum(V, F, k=40, max_restarts=1)
    assert not other.value.stopped_at_time_limit
    for bad in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ds.OptionsError, match="time_limit"):
            ds.spectrum(V, F, k=4, time_limit=bad)
    with pytest.raises(TypeError, match="time_limit"):
        ds.spectrum(V, F, k=4, time_limit="1 s")


def test_ctrl_c_interrupts_a_long_solve():
    V, F = torus(160, 60)
    # Wall time, as `elapsed` below is (the solver's own total leaves out the assembly).
    start = time.perf_counter()
    ds.spectrum(V, F, k=40)
    full = time.perf_counter() - start
    # Python's own Ctrl-C handler, also where the test runs with SIGINT ignored (a background
    # job of a non-interactive shell inherits SIG_IGN, and Python keeps it).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        timer = threading.Timer(0.2 * full, os.kill, (os.getpid(), signal.SIGINT))
        start = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            ds.spectrum(V, F, k=40)
        elapsed = time.perf_counter() - start
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert elapsed < 0.8 * full, f"interrupted after {elapsed:.2f} s of a {full:.2f} s solve"


def test_geodesic_distance_on_the_sphere_and_the_potential_well(sphere):
    V, F = sphere
    north = int(np.argmax(V[:, 2]))
    distance = ds.geodesic_distance(V, F, north)
    exact = np.arccos(np.clip(V @ V[north], -1, 1))  # great-circle distance on the unit sphere
    assert distance[north] == 0.0
    assert np.max(np.abs(distance - exact)) < 0.05 * np.pi
    U = ds.potential_well(V, F, radius=1.0, center=north)
    # U = c σ(γ (d − β)) with the paper's γ = 100, c = 10¹⁰.
    expected = 1e10 / (1 + np.exp(np.clip(-100 * (distance - 1.0), -700, 700)))
    np.testing.assert_allclose(U, expected, rtol=1e-9, atol=1e-300)
    assert U[north] < 1e-30 and U.max() > 0.99e10
    with pytest.raises(ds.OptionsError, match="source vertex 9999 does not exist"):
        ds.geodesic_distance(V, F, [0, 9999])


def test_the_family_on_a_mesh_far_from_unit_area_warns():
    """The family weighs D_N by scale: unnormalised and far from unit area it warns, with the
    weight tau amounts to at unit area; normalised, or with another operator, it does not."""
    V, F = torus(12, 8)
    small = V * 1e-2
    with pytest.warns(ds.ScaleWarning, match='normalize="unit-area"'):
        ds.spectrum(small, F, k=4, operator="family", tau=0.5, eigenvectors=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds.spectrum(small, F, k=4, operator="family", tau=0.5, normalize="unit-area")
        ds.spectrum(small, F, k=4, operator="laplace")
        ds.spectrum(V, F, k=4, operator="family", tau=0.5)
