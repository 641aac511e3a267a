"""ANSYS ``.full`` import (structure/io.py) on the example file that ansys-mapdl-reader ships.

ansys-mapdl-reader (with VTK) is the optional extra ``[ansys]``; CI installs it (README's test
command), so this test runs there.

Reference: the same file read independently with the reader's own API (``load_km``, upper
triangles completed here, constrained rows dropped) and solved by dense LAPACK ``eigh``: our
import must give the same matrices and, through fricdamp's modal solver, the same lowest
eigenfrequencies (1e-8: the same matrices, two eigen-solvers; the lowest mode is a
double one, which ARPACK resolves to ~2e-9).
"""

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

reader = pytest.importorskip("ansys.mapdl.reader")


def test_full_file_matches_the_readers_own_matrices_and_modes():
    from ansys.mapdl.reader import examples

    from fricdamp.solvers.modal import modes
    from fricdamp.structure.builders import from_matrices
    from fricdamp.structure.io import read_ansys_full

    M, K, ref = read_ansys_full(examples.fullfile)
    assert M.shape == K.shape and ref.shape == (M.shape[0], 2)
    assert abs(K - K.T).max() == 0 and abs(M - M.T).max() == 0
    _, k, m = reader.read_binary(examples.fullfile).load_km(sort=True)
    k = sp.csr_matrix(k + sp.triu(k, 1).T)
    m = sp.csr_matrix(m + sp.triu(m, 1).T)
    keep = np.flatnonzero(np.diff(k.indptr) + np.diff(m.indptr) > 0)
    k, m = k[keep][:, keep], m[keep][:, keep]
    np.testing.assert_allclose(K.toarray(), k.toarray(), rtol=0, atol=1e-12 * abs(k).max())
    np.testing.assert_allclose(M.toarray(), m.toarray(), rtol=0, atol=1e-12 * abs(m).max())
    lam = sla.eigh(k.toarray(), m.toarray(), eigvals_only=True, subset_by_index=[0, 5])
    f_ref = np.sqrt(lam) / (2 * np.pi)
    res = modes(from_matrices(M, K), 6)
    np.testing.assert_allclose(res.frequencies, f_ref, rtol=1e-8)
