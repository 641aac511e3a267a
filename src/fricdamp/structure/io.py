"""Import of structural matrices (Matrix Market; more formats register here)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

from fricdamp.errors import ModelError


def read_matrix(source, name: str = "matrix"):
    """Matrix from an array, a sparse matrix or a Matrix Market file path (``.mtx``)."""
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.is_file():
            raise ModelError(f"{name}: file {str(path)!r} does not exist")
        try:
            A = scipy.io.mmread(str(path))
        except (ValueError, OSError) as exc:
            raise ModelError(f"{name}: {str(path)!r} is not a readable Matrix Market file: "
                             f"{exc}") from exc
        return sp.csr_matrix(A) if sp.issparse(A) else np.asarray(A, float)
    return source
