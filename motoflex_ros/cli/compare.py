"""``motoflex compare A.json B.json``: two identifications side by side (issue 17).

To hold a virtual bench against a real one: l, beta, b, k, c, J of the static, torsion and
bending models, k_t, k_b (eq. 12) and l, beta, b, k, c of the principal hinges (beyond the
paper, in their order) of both files (``motoflex identify --out``, with or
without ``--measured``), with their difference in units of the combined uncertainty,
z = (A - B) / sqrt(s_A^2 + s_B^2), s = half the 95 % interval / 1.96 (the intervals are
value +/- 1.96 s, :mod:`motoflex_ros.identify.uncertainty`). |z| > 2: the two differ beyond
their uncertainty (marked '*'). Components are paired by name; two files of one component
each are paired whatever their names (a virtual 'swingarm' against a bench 'my_swingarm').
"""
import math
import sys

from motoflex_ros.cli.output import emit_json, print_table
from motoflex_ros.errors import ConfigError
from motoflex_ros.identify.results import MODEL_TESTS

__all__ = ["register", "run", "compare_results", "QUANTITIES", "Z_FLAG"]

QUANTITIES = ("l", "beta", "b", "k", "c", "J")
Z_FLAG = 2.0
_Z95 = 1.959963984540054


def register(subparsers):
    """Add the ``compare`` verb."""
    p = subparsers.add_parser("compare", help="compare two identifications (virtual vs real)",
                              description="Compare l, beta, b, k, c, J and k_t, k_b of two "
                                          "identification files, with the differences in "
                                          "units of the combined uncertainty.")
    p.add_argument("a", metavar="A.json", help="first identification (motoflex identify --out)")
    p.add_argument("b", metavar="B.json", help="second identification")
    p.add_argument("--json", action="store_true", help="print the comparison as JSON only")
    p.set_defaults(func=run)


def _sigma(entry, key):
    ci = (entry.get("ci") or {}).get(key)
    if not ci or any(v is None or not math.isfinite(v) for v in ci):
        return None
    return (ci[1] - ci[0]) / (2.0 * _Z95)


def _value(entry, key):
    value = entry.get(key) if entry else None
    return value if isinstance(value, (int, float)) and math.isfinite(value) else None


def _row(component, model, key, ea, eb):
    a, b = _value(ea, key), _value(eb, key)
    sa = _sigma(ea, key) if ea else None
    sb = _sigma(eb, key) if eb else None
    diff = a - b if a is not None and b is not None else None
    z = None
    if diff is not None and sa is not None and sb is not None and (sa or sb):
        z = diff / math.hypot(sa, sb)
    return {"component": component, "model": model, "quantity": key, "a": a, "b": b,
            "a_ci": (ea or {}).get("ci", {}).get(key), "b_ci": (eb or {}).get("ci", {}).get(key),
            "difference": diff, "z": z}


def _pairs(data_a, data_b, path_a, path_b):
    common = [name for name in data_a if name in data_b]
    if common:
        return [(name, name) for name in common]
    if len(data_a) == 1 and len(data_b) == 1:
        return [(next(iter(data_a)), next(iter(data_b)))]
    raise ConfigError(path_b, "", f"no component in common with {path_a} ({', '.join(data_a)} "
                                  f"against {', '.join(data_b)}); two files of one component "
                                  f"each are compared whatever their names")


def compare_results(data_a, data_b, path_a="A", path_b="B"):
    """Rows of the comparison of two results mappings ({component: result})."""
    rows = []
    for name_a, name_b in _pairs(data_a, data_b, path_a, path_b):
        ra, rb = data_a[name_a], data_b[name_b]
        label = name_a if name_a == name_b else f"{name_a} / {name_b}"
        for model in MODEL_TESTS:
            for key in QUANTITIES:
                ea, eb = ra.get(model), rb.get(model)
                if (ea and key in ea) or (eb and key in eb):
                    rows.append(_row(label, model, key, ea, eb))
        for key in ("k_t", "k_b"):
            rows.append(_row(label, "eq. 12", key, ra, rb))
        ha, hb = _principal_hinges(ra), _principal_hinges(rb)
        for i in range(max(len(ha), len(hb))):
            ea, eb = (ha[i] if i < len(ha) else None), (hb[i] if i < len(hb) else None)
            for key in QUANTITIES[:5]:
                rows.append(_row(label, f"principal {i + 1}", key, ea, eb))
    return rows


def _number_or_null(value):
    return value is None or (isinstance(value, (int, float)) and not isinstance(value, bool))


def _check_entry(entry, keys, path, where):
    """ConfigError naming the file and the dotted key where a model (or a component's eq. 12
    values) of a result is not shaped as ``motoflex identify --out`` writes it: a mapping of
    numbers (or null) with ``ci`` a mapping of [low, high] pairs."""
    if entry is None:
        return
    if not isinstance(entry, dict):
        raise ConfigError(path, where, f"expected a mapping (or null), got "
                                       f"{type(entry).__name__}")
    for key in keys:
        if not _number_or_null(entry.get(key)):
            raise ConfigError(path, f"{where}.{key}", f"expected a number or null, got "
                                                      f"{type(entry.get(key)).__name__}")
    ci = entry.get("ci")
    if ci is None:
        return
    if not isinstance(ci, dict):
        raise ConfigError(path, f"{where}.ci", f"expected a mapping {{quantity: [low, high]}}, "
                                               f"got {type(ci).__name__}")
    for key in keys:
        pair = ci.get(key)
        if pair is not None and (not isinstance(pair, list) or len(pair) != 2 or
                                 not all(map(_number_or_null, pair))):
            raise ConfigError(path, f"{where}.ci.{key}", "expected [low, high]: two numbers "
                                                         "(or null)")


def _principal_hinges(result):
    """The principal hinges of a result (issue 22; [] when not identified or absent)."""
    principal = result.get("principal")
    if not isinstance(principal, dict) or not principal.get("identified"):
        return []
    return list(principal.get("hinges") or [])


def _load(path):
    from motoflex_ros.formats.json_yaml import load_results_file
    data = load_results_file(path)
    for name, result in data.items():
        if not isinstance(result, dict) or "static" not in result:
            raise ConfigError(path, str(name), "not an identification result (no 'static'); "
                                               "give files of motoflex identify --out")
        for model in MODEL_TESTS:
            _check_entry(result.get(model), QUANTITIES, path, f"{name}.{model}")
        _check_entry(result, ("k_t", "k_b"), path, str(name))
    return data


def _text(value, spec=".5g"):
    return "n/a" if value is None else f"{value:{spec}}"


def _interval(ci):
    if not ci or any(v is None for v in ci):
        return "n/a"
    return f"[{ci[0]:.4g}, {ci[1]:.4g}]"


def run(args):
    """Print the comparison; returns the exit code."""
    rows = compare_results(_load(args.a), _load(args.b), args.a, args.b)
    if args.json:
        emit_json(rows)
        return 0
    table = [[r["component"], r["model"], r["quantity"], _text(r["a"]), _interval(r["a_ci"]),
              _text(r["b"]), _interval(r["b_ci"]), _text(r["difference"], ".3g"),
              _text(r["z"], "+.2f") + (" *" if r["z"] is not None and abs(r["z"]) > Z_FLAG
                                       else "")]
             for r in rows]
    print_table(["component", "model", "", "A", "A 95 % interval", "B", "B 95 % interval",
                 "A - B", "z"], table)
    flagged = sum(1 for r in rows if r["z"] is not None and abs(r["z"]) > Z_FLAG)
    sys.stdout.write(f"\nz = (A - B) / combined standard uncertainty; {flagged} of "
                     f"{sum(r['z'] is not None for r in rows)} differences beyond |z| > "
                     f"{Z_FLAG:g} (*)\n")
    return 0
