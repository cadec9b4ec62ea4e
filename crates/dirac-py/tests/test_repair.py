"""``dirac_spectra.repair``: soups repair to the mesh they came from, the maps and counts are
those known by construction, errors are typed, and invalid meshes point to repair."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg

import dirac_spectra as ds
from conftest import torus

TETRAHEDRON_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
TETRAHEDRON_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def soup(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every face with three vertices of its own: face t uses 3t, 3t + 1, 3t + 2."""
    return V[F.ravel()], np.arange(3 * len(F)).reshape(-1, 3)


def test_a_torus_soup_repairs_to_the_torus():
    V, F = torus(24, 10)
    Vs, Fs = soup(V, F)
    repaired = ds.repair(Vs, Fs)
    assert repaired.vertices.shape == V.shape and repaired.faces.shape == F.shape
    assert repaired.report["merged_vertices"]["count"] == 3 * len(F) - len(V)
    assert [name for name, step in repaired.report.items() if step["count"]] == ["merged_vertices"]
    assert repaired.summary.startswith(f"merged {3 * len(F) - len(V)} vertices")
    np.testing.assert_array_equal(repaired.face_origin, np.arange(len(F)))
    # Output faces through vertex_origin name soup vertices at the corners of the same soup
    # faces, in the same order (so the same orientation).
    np.testing.assert_array_equal(Vs[repaired.vertex_origin[repaired.faces]], Vs[Fs])
    np.testing.assert_array_equal(repaired.vertices, Vs[repaired.vertex_origin])
    # The soup vertex of each torus vertex is a copy of it: the maps compose to a bijection.
    torus_vertex = F.ravel()[repaired.vertex_origin]
    assert sorted(torus_vertex) == list(range(len(V)))
    first = ds.spectrum(V, F, k=10, operator="laplace").eigenvalues
    second = ds.spectrum(repaired.vertices, repaired.faces, k=10, operator="laplace").eigenvalues
    np.testing.assert_allclose(second, first, rtol=1e-10, atol=1e-12)


def test_the_repaired_laplacian_has_the_torus_spectrum_by_scipy():
    V, F = torus(16, 8)
    repaired = ds.repair(*soup(V, F))
    # scipy's eigsh on both pencils L x = λ M x (shift-invert near 0; the constant comes first).
    def smallest(V, F):
        L, M = ds.laplacian(V, F)
        return np.sort(scipy.sparse.linalg.eigsh(L, k=6, M=M, sigma=-1e-3, which="LM")[0])

    np.testing.assert_allclose(
        smallest(repaired.vertices, repaired.faces), smallest(V, F), rtol=1e-9, atol=1e-10
    )


def test_each_defect_is_counted():
    V = np.vstack([TETRAHEDRON_V, [[0.0, 0, 0], [9, 9, 9], [np.nan, 0, 0]]])
    F = np.vstack([
        [[0, 2, 1], [4, 1, 3], [0, 3, 2], [1, 3, 2]],  # vertex 4 copies 0; face 3 flipped
        [[0, 2, 1], [0, 1, 7], [0, -1, 2], [0, 6, 1], [1, 1, 2]],
    ])
    with pytest.raises(ds.MeshError, match="dirac_spectra.repair"):
        ds.spectrum(V, F, k=3)
    repaired = ds.repair(V, F)
    counts = {name: step["count"] for name, step in repaired.report.items() if step["count"]}
    assert counts == {
        "merged_vertices": 1,
        "flipped_faces": 1,
        "removed_duplicate_faces": 1,
        "removed_faces_out_of_range": 2,
        "removed_faces_non_finite": 1,
        "removed_faces_repeated_vertex": 1,
        "removed_unreferenced": 2,
    }
    assert repaired.report["merged_vertices"]["examples"] == [[4, 0]]
    assert repaired.report["removed_duplicate_faces"]["examples"] == [[4, 0]]
    assert repaired.report["removed_faces_out_of_range"]["examples"] == [5, 6]
    assert repaired.report["removed_unreferenced"]["examples"] == [5, 6]
    np.testing.assert_array_equal(repaired.faces, TETRAHEDRON_F)
    np.testing.assert_array_equal(repaired.face_origin, [0, 1, 2, 3])
    np.testing.assert_array_equal(repaired.vertex_origin, [0, 1, 2, 3])
    assert repaired.changed
    again = ds.repair(repaired.vertices, repaired.faces)
    assert not again.changed and again.summary == "nothing to repair"
    np.testing.assert_array_equal(again.faces, repaired.faces)


def test_repair_is_frozen_and_errors_are_typed():
    repaired = ds.repair(TETRAHEDRON_V, TETRAHEDRON_F)
    with pytest.raises(AttributeError):
        repaired.faces = None  # type: ignore[misc]
    with pytest.raises(ds.OptionsError, match="merge distance"):
        ds.repair(TETRAHEDRON_V, TETRAHEDRON_F, merge_distance=-1.0)
    with pytest.raises(ds.MeshError, match="no face is left") as error:
        ds.repair(TETRAHEDRON_V, [[0, 0, 1]])
    assert "dirac_spectra.repair(V, F)" not in str(error.value)


def test_read_mesh_can_repair(tmp_path):
    path = tmp_path / "soup.obj"
    Vs, Fs = soup(TETRAHEDRON_V, TETRAHEDRON_F)
    lines = [f"v {x} {y} {z}" for x, y, z in Vs] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in Fs]
    # An unused vertex makes the file invalid as it is.
    path.write_text("\n".join(lines + ["v 5 5 5"]) + "\n")
    with pytest.raises(ds.MeshError, match=r"read_mesh\(path, repair=True\)"):
        ds.read_mesh(path)
    V, F = ds.read_mesh(path, repair=True)
    assert V.shape == (4, 3)
    # Vertices are numbered by their first copy in the file; each face has its corners.
    np.testing.assert_array_equal(V[F], TETRAHEDRON_V[TETRAHEDRON_F])
    repaired = ds.read_and_repair(path)
    assert repaired.report["merged_vertices"]["count"] == 8
    assert repaired.report["removed_unreferenced"]["examples"] == [12]
    with pytest.raises(FileNotFoundError):
        ds.read_and_repair(tmp_path / "missing.obj")


@pytest.mark.parametrize("operator", ["relative-dirac", "extrinsic-dirac"])
def test_the_dirac_operators_of_a_soup_point_to_repair_in_python_terms(operator):
    # Every face of a soup is its own flat piece: D_N vanishes, and D_f has only each face's
    # constant and linear function, nothing else; the error says how to weld the pieces with
    # this package, not with the command line's --repair.
    Vs, Fs = soup(*torus(12, 6))
    with pytest.raises(ds.KernelError, match=r"dirac_spectra\.repair\(V, F\)") as error:
        ds.spectrum(Vs, Fs, k=4, operator=operator)
    assert "--repair" not in str(error.value)
    assert f"{len(Fs)} separate" in str(error.value)
    repaired = ds.repair(Vs, Fs)
    assert ds.spectrum(repaired.vertices, repaired.faces, k=4, operator=operator).converged.all()


def test_a_mobius_strip_is_named_non_orientable_without_pointing_to_repair():
    # Eight quads glued with a half twist: every operator refuses it, naming a face, and the
    # message does not send the user to a repair that would only say the same.
    n = 8
    V = []
    for i in range(n):
        u = 2 * np.pi * i / n
        for w in (-0.3, 0.3):
            r, z = 1 + w * np.cos(u / 2), w * np.sin(u / 2)
            V.append([r * np.cos(u), r * np.sin(u), z])
    F = []
    for i in range(n):
        a, b = 2 * i, 2 * i + 1
        c, d = (2 * i + 2, 2 * i + 3) if i + 1 < n else (1, 0)
        F += [[a, c, d], [a, d, b]]
    with pytest.raises(ds.MeshError, match="not orientable") as error:
        ds.spectrum(np.array(V), np.array(F), k=3, operator="laplace")
    assert 0 <= error.value.face < len(F)
    assert "repair" not in str(error.value)
    with pytest.raises(ds.MeshError, match="not orientable"):
        ds.repair(np.array(V), np.array(F))
