"""``motoflex compare A.json B.json`` (issue 17): differences in units of the combined
uncertainty, worked by hand."""
import json

import pytest

from motoflex_ros.cli.main import main


def _result(k, k_lo, k_hi, torsion=True):
    model = {"l": 0.3, "beta": 1.5, "b": 0.2, "k": k, "c": 0.001 * k,
             "ci": {"l": [0.29, 0.31], "beta": [1.49, 1.51], "b": [0.19, 0.21],
                    "k": [k_lo, k_hi], "c": [0.001 * k_lo, 0.001 * k_hi]}}
    return {"static": model, "torsion": dict(model, J=0.1) if torsion else None,
            "bending": None, "k_t": None, "k_b": None, "ci": {"k_t": [None, None],
                                                              "k_b": [None, None]}}


def test_compare_z_by_hand(tmp_path, capsys):
    # A: k = 100, s = 1 (interval 100 +/- 1.96); B: k = 103, s = 2 -> z = -3 / sqrt(5)
    (tmp_path / "a.json").write_text(json.dumps({"swingarm": _result(100.0, 98.04, 101.96)}))
    (tmp_path / "b.json").write_text(json.dumps({"my_swingarm": _result(103.0, 99.08, 106.92,
                                                                        torsion=False)}))
    assert main(["compare", str(tmp_path / "a.json"), str(tmp_path / "b.json"), "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    k = next(r for r in rows if r["model"] == "static" and r["quantity"] == "k")
    assert k["component"] == "swingarm / my_swingarm"
    assert k["difference"] == pytest.approx(-3.0)
    assert k["z"] == pytest.approx(-3.0 / 5**0.5, rel=1e-3)
    beta = next(r for r in rows if r["model"] == "static" and r["quantity"] == "beta")
    assert beta["z"] == pytest.approx(0.0)
    torsion_k = next(r for r in rows if r["model"] == "torsion" and r["quantity"] == "k")
    assert torsion_k["b"] is None and torsion_k["z"] is None   # B has no torsion test
    assert main(["compare", str(tmp_path / "a.json"), str(tmp_path / "b.json")]) == 0
    text = capsys.readouterr().out
    assert "-1.34" in text and "n/a" in text


def test_compare_flags_and_refuses(tmp_path, capsys):
    (tmp_path / "a.json").write_text(json.dumps({"frame": _result(100.0, 99.0, 101.0),
                                                 "swingarm": _result(1.0, 0.9, 1.1)}))
    (tmp_path / "b.json").write_text(json.dumps({"frame": _result(110.0, 109.0, 111.0)}))
    assert main(["compare", str(tmp_path / "a.json"), str(tmp_path / "b.json")]) == 0
    assert "-13.86 *" in capsys.readouterr().out   # 10 / (sqrt(2) * 1 / 1.96)
    (tmp_path / "c.json").write_text(json.dumps({"tube": {"k": 1}}))
    assert main(["compare", str(tmp_path / "a.json"), str(tmp_path / "c.json")]) == 2
    assert "key 'tube'" in capsys.readouterr().err


def test_compare_lists_the_principal_hinges(tmp_path, capsys):
    """Issue 22: the principal hinges compared in their order; one side not identified."""
    a = _result(100.0, 98.04, 101.96)
    hinge = {key: a["static"][key] for key in ("l", "beta", "b", "k", "c")}
    a["principal"] = {"identified": True, "hinges": [dict(hinge, ci=a["static"]["ci"]),
                                                     dict(hinge, k=50.0, ci={})]}
    b = _result(103.0, 99.08, 106.92)
    b["principal"] = {"identified": True, "hinges": [dict(hinge, k=103.0,
                                                          ci=b["static"]["ci"])]}
    (tmp_path / "a.json").write_text(json.dumps({"swingarm": a}))
    (tmp_path / "b.json").write_text(json.dumps({"swingarm": b}))
    assert main(["compare", str(tmp_path / "a.json"), str(tmp_path / "b.json"), "--json"]) == 0
    rows = [r for r in json.loads(capsys.readouterr().out) if r["model"].startswith("principal")]
    assert [(r["model"], r["quantity"]) for r in rows] == [
        (f"principal {i}", q) for i in (1, 2) for q in ("l", "beta", "b", "k", "c")]
    k1 = next(r for r in rows if r["model"] == "principal 1" and r["quantity"] == "k")
    assert k1["z"] == pytest.approx(-3.0 / 5**0.5, rel=1e-3)
    k2 = next(r for r in rows if r["model"] == "principal 2" and r["quantity"] == "k")
    assert k2["a"] == 50.0 and k2["b"] is None and k2["z"] is None
