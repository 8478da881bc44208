"""The Craig-Bampton reductions of mesh components, kept on disk (issue 15).

A solid mesh of 1e5-1e6 DOFs takes seconds to minutes to reduce (one sparse factorisation and
a shift-invert eigensolution); the bench, the vehicle and the studies all ask for the same
reduction. It is kept in a cache folder keyed by a SHA-256 of everything it depends on:

- the component's YAML file and its mesh file (bytes: material, sets, spider points, rigid
  parts, units, the mesh itself),
- the options (number of modes, highest frequency [Hz]),
- the source of the code that builds it (the solid elements, the mesh component, the
  assembly, the Craig-Bampton reduction and the sparse solver; the mesh reader's, in
  :mod:`motoflex_ros.formats`, comes with the input files), so that a changed formulation
  never returns an old result.

The damping ratio is not in the key: it changes no reduced matrix (the reduced models built
from the cached one take the ratio asked for). Folder: ``MOTOFLEX_CACHE_DIR`` if set (``off``:
no cache), else ``$XDG_CACHE_HOME/motoflex_ros/reductions`` or
``~/.cache/motoflex_ros/reductions``. Entries are written atomically (a temporary file renamed
into place); an entry that cannot be read is computed again and replaced.
"""
import hashlib
import os
import tempfile
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from motoflex_ros.files import check_output_path
from motoflex_ros.structures.craig_bampton import CraigBamptonModel

__all__ = ["cache_folder", "reduction_key", "load_reduction", "store_reduction", "CODE_FILES"]

FORMAT = 1
CODE_FILES = ("solid.py", "mesh_component.py", "assembly.py",
              "craig_bampton.py", "sparse_solver.py", "reduction_cache.py")
"""The structures modules whose source is part of the key."""


def cache_folder():
    """The cache folder (Path), or None when ``MOTOFLEX_CACHE_DIR=off``."""
    given = os.environ.get("MOTOFLEX_CACHE_DIR")
    if given:
        return None if given.lower() == "off" else Path(given)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "motoflex_ros" / "reductions"


def _file_digest(path):
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def reduction_key(files, n_modes, f_max_hz):
    """Hex SHA-256 of the input ``files`` (the component's YAML and mesh), the options and the
    code (module docstring)."""
    digest = hashlib.sha256(f"format {FORMAT}; modes {int(n_modes)}; "
                            f"f_max {float(f_max_hz)!r}\n".encode())
    for path in files:
        digest.update(_file_digest(path).encode())
    here = Path(__file__).parent
    for name in CODE_FILES:
        digest.update(_file_digest(here / name).encode())
    return digest.hexdigest()


def load_reduction(key, zeta):
    """The cached CraigBamptonModel of ``key`` with damping ratio ``zeta``, or None (no cache,
    no entry, or an entry that cannot be read)."""
    folder = cache_folder()
    path = None if folder is None else folder / f"{key}.npz"
    if path is None or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if "transform" in data:
                transform = data["transform"]
            else:
                transform = sp.csc_matrix((data["t_data"], data["t_indices"], data["t_indptr"]),
                                          shape=tuple(data["t_shape"]))
            return CraigBamptonModel(data["M"], data["K"], transform, data["boundary"],
                                     data["frequencies_hz"], zeta)
    except (OSError, ValueError, KeyError):
        return None


def store_reduction(key, cb):
    """Write ``cb`` (a CraigBamptonModel) under ``key``; does nothing without a cache folder.
    A folder that cannot be written leaves the result uncached (the computation stands)."""
    folder = cache_folder()
    if folder is None:
        return
    arrays = {"M": cb.M, "K": cb.K, "boundary": cb.boundary,
              "frequencies_hz": cb.frequencies_hz}
    if sp.issparse(cb.transform):
        t = sp.csc_matrix(cb.transform)
        arrays.update(t_data=t.data, t_indices=t.indices, t_indptr=t.indptr,
                      t_shape=np.array(t.shape))
    else:
        arrays["transform"] = np.asarray(cb.transform)
    tmp = None
    try:
        target = check_output_path(folder / f"{key}.npz")   # never a rename over a FIFO
        folder.mkdir(parents=True, exist_ok=True)
        handle, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
        with os.fdopen(handle, "wb") as stream:
            np.savez(stream, **arrays)
        os.replace(tmp, target)
    except OSError:   # also a full disk: no temporary file left behind
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)

