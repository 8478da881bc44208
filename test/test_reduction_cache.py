"""A mesh component's Craig-Bampton reduction is kept on disk and reused (issue 15,
structures/reduction_cache.py): the second reduction reads the cache (the solver is not called)
and equals the first exactly; a changed material, mesh, option or unreadable entry computes
again; ``MOTOFLEX_CACHE_DIR=off`` keeps nothing. On the L bracket of hexahedra (2,919 DOFs)."""
import numpy as np
import pytest
import yaml

from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.mesh_examples import write_bracket_component
from motoflex_ros.structures import component_model as components_module


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("MOTOFLEX_CACHE_DIR", str(folder))
    return folder


@pytest.fixture
def bracket(tmp_path):
    return write_bracket_component(tmp_path / "mesh")


def _entries(folder):
    return sorted(folder.glob("*.npz")) if folder.exists() else []


def _no_solver(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("reduced again although the cache holds it")
    monkeypatch.setattr(components_module, "craig_bampton", refuse)


def test_second_reduction_reads_the_cache(cache, bracket, monkeypatch):
    first, _ = load_component(str(bracket)).craig_bampton(20, 600.0, 0.02)
    assert len(_entries(cache)) == 1
    _no_solver(monkeypatch)
    again, _ = load_component(str(bracket)).craig_bampton(20, 600.0, 0.05)
    for name in ("M", "K", "transform", "boundary", "frequencies_hz"):
        assert np.array_equal(np.asarray(getattr(first, name)),
                              np.asarray(getattr(again, name))), name
    assert again.zeta == 0.05   # the damping asked for, not the cached one's
    reduced = load_component(str(bracket)).clamped_reduced()
    assert reduced.K.shape[0] == first.K.shape[0] - 6


def test_what_changes_the_reduction_changes_the_key(cache, bracket):
    comp = load_component(str(bracket))
    base, _ = comp.craig_bampton()
    comp.craig_bampton(n_modes=5)
    assert len(_entries(cache)) == 2                       # an option
    cfg = yaml.safe_load(bracket.read_text())
    cfg["material"]["E"] = 2 * cfg["material"]["E"]
    bracket.write_text(yaml.safe_dump(cfg))
    stiffer, _ = load_component(str(bracket)).craig_bampton()
    assert len(_entries(cache)) == 3                       # the material
    assert np.allclose(stiffer.frequencies_hz, np.sqrt(2) * base.frequencies_hz, rtol=1e-9)
    mesh = bracket.parent / cfg["mesh"]["file"]
    mesh.write_bytes(mesh.read_bytes() + b"\n")
    load_component(str(bracket)).craig_bampton()
    assert len(_entries(cache)) == 4                       # the mesh file


def test_unreadable_entry_is_computed_again(cache, bracket):
    first, _ = load_component(str(bracket)).craig_bampton()
    (entry,) = _entries(cache)
    entry.write_bytes(b"not an npz")
    again, _ = load_component(str(bracket)).craig_bampton()
    assert np.allclose(again.K, first.K, rtol=1e-12, atol=0)
    assert entry.stat().st_size > 1000                     # replaced by a good one


def test_cache_off_keeps_nothing(tmp_path, bracket, monkeypatch):
    monkeypatch.setenv("MOTOFLEX_CACHE_DIR", "off")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    load_component(str(bracket)).craig_bampton()
    assert not (tmp_path / "xdg").exists()
