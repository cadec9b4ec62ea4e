"""The examples of docs/PYTHON.md run and print what the text says."""

from __future__ import annotations

import re

import numpy as np

from conftest import REPOSITORY


def python_blocks() -> list[str]:
    text = (REPOSITORY / "docs" / "PYTHON.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def test_the_walk_through_and_the_scipy_check_run(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    blocks = python_blocks()
    walk = next(b for b in blocks if "matplotlib" in b)
    check = next(b for b in blocks if "x = s.eigenvectors[:, 3, :]" in b)
    pinned = next(b for b in blocks if "sla.splu" in b)
    namespace: dict = {}
    exec(walk, namespace)
    assert (tmp_path / "spot-phi3.png").stat().st_size > 10_000
    assert namespace["s"].kernel_dimension == 1
    exec(check, namespace)
    relative = np.linalg.norm(namespace["P"] @ namespace["x"] - namespace["lam"] * (
        namespace["Q"] @ namespace["x"])) / np.linalg.norm(namespace["lam"] * (
            namespace["Q"] @ namespace["x"]))
    assert relative < 1e-9
    # The scipy recipe gives the package's eigenvalues (on the unnormalised mesh here).
    import dirac_spectra as ds

    V, F = namespace["V"], namespace["F"]
    exec(pinned, namespace)
    lam = np.sort(namespace["lam"][np.argsort(np.abs(namespace["lam"]))][::4])
    expected = np.sort(ds.spectrum(V, F, k=10).eigenvalues)
    np.testing.assert_allclose(lam, expected, rtol=1e-8)


def test_every_code_fence_of_the_documents_is_well_formed():
    # A fence line is ``` alone or with a language; text after a closing fence would leave the
    # block open, and everything after it would render as code.
    for document in sorted((REPOSITORY / "docs").glob("*.md")) + [REPOSITORY / "README.md"]:
        fences = [
            (number, line)
            for number, line in enumerate(document.read_text().splitlines(), 1)
            if line.lstrip().startswith("```")
        ]
        for number, line in fences:
            assert re.fullmatch(r"\s*```[\w+-]*", line), f"{document.name}:{number}: {line!r}"
        assert len(fences) % 2 == 0, f"{document.name}: an unclosed code block"
