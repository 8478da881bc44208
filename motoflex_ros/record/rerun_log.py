"""Rerun recording of a run (.rrd): bench components, loads, deformation axes, identification.

Every function here takes plain numbers (numpy arrays, dicts, floats) so that it works with
whatever the core or a recorded bag provides; the vehicle part is in :mod:`.rerun_vehicle`.
Time is simulated time on the timeline ``sim_time`` (a duration, seconds). Entity paths:

=========================================  ==================================================
path                                       content
=========================================  ==================================================
/bench/<c>                                 Transform3D: component frame -> vehicle frame
/bench/<c>/structure                       deformed beam model (LineStrips3D) over time,
                                           displacements exaggerated by ``factor``
/bench/<c>/structure/undeformed            the unloaded beam model (static)
/bench/<c>/structure/clamps                clamp points (Points3D, static)
/bench/<c>/structure/load_point            loaded end q0 (Points3D, static)
/bench/<c>/structure/exaggeration          TextDocument stating the factor
/bench/<c>/load                            load arrow at the loaded end (Arrows3D) over time
/bench/<c>/load/force                      F_x, F_y, F_z [N] (Scalars) over time
/bench/<c>/load/end_displacement           u_x, u_y, u_z of the loaded end [m] over time
/bench/<c>/axes/<test>                     deformation axis of a test (LineStrips3D, static)
/bench/<c>/axes/<test>/joint               its revolute joint (Points3D, static)
/bench/<c>/axes/<test>/label               '<test> axis' at one end of the strip (static)
/bench/<c>/name                            the component's name above it (static)
/bench/<c>/axes/sweep                      axes of the frequency sweep (one strip per step)
/identification/<c>/<test>/<name>          identified value (Scalars, drawn as points) at the
                                           time it is known; its quantity and unit are
                                           :func:`quantity_of` and :data:`IDENTIFIED_QUANTITIES`
/identification/<c>/table                  the identified values as a table (TextDocument,
                                           markdown, static; beta in degrees)
=========================================  ==================================================

Frames: the bench entities are in the component frame (clamp O at the origin, x forward, z
up, symmetry plane x-z; Passigato et al. 2023, Sect. 4.2, Fig. 2); ``/bench/<c>`` carries the
placement of O in the vehicle frame (REP-103).
"""
import os

import numpy as np
import rerun as rr

from motoflex_ros.files import check_output_path
from motoflex_ros.lumped_stiffness.axis_line import axis_from_l_beta, axis_segment_xyz

__all__ = ["TIMELINE", "RunRecording", "log_component_frame",
           "log_structure", "log_structure_model", "log_load", "log_axis", "log_sweep_axes",
           "log_identification", "exaggeration_factor",
           "subsample_indices", "MAX_SHAPE_FRAMES", "IDENTIFIED_QUANTITIES", "quantity_of",
           "identification_markdown", "log_identification_table", "TABLE_COLUMNS"]

TIMELINE = "sim_time"
MAX_SHAPE_FRAMES = 400      # deformed shapes logged per component (evenly subsampled)
AXIS_COLORS = {"static": (40, 110, 255), "torsion": (30, 170, 60), "bending": (120, 200, 60),
               "principal_1": (148, 103, 189), "principal_2": (140, 86, 75),
               "principal_3": (227, 119, 194)}
STRUCTURE_COLOR = (230, 130, 30)
UNDEFORMED_COLOR = (150, 150, 150)
CLAMP_COLOR = (90, 200, 255)       # light blue, as the clamp dots of the paper's Figs. 2, 5-7
LOAD_COLOR = (255, 140, 0)         # orange, as the load dots of the paper's Figs. 2, 5-7
IDENTIFIED_QUANTITIES = {"l": "m", "beta": "rad", "b": "m", "k": "N m/rad", "c": "N m s/rad",
                         "J": "kg m^2", "f": "Hz", "omega_n": "rad/s", "zeta": "-"}
"""Unit of each identified quantity (Sect. 4.2 symbols; f the frequency of a test or mode)."""
_QUANTITY_OF_NAME = {"k_t": "k", "k_b": "k", "f_hz": "f", "omega_n_decay": "omega_n",
                     "zeta_decay": "zeta"}


class _IndexedStream(rr.RecordingStream):
    """A RecordingStream that keeps the entity paths it logged (``entity_paths``)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.entity_paths = set()

    def log(self, entity_path, *args, **kwargs):
        """Log as :meth:`rerun.RecordingStream.log`, keeping ``entity_path``."""
        self.entity_paths.add(entity_path)
        super().log(entity_path, *args, **kwargs)

    def send_columns(self, entity_path, *args, **kwargs):
        """Send as :meth:`rerun.RecordingStream.send_columns`, keeping ``entity_path``."""
        self.entity_paths.add(entity_path)
        super().send_columns(entity_path, *args, **kwargs)


class RunRecording:
    """A RecordingStream writing one run's .rrd (application 'motoflex_ros', id = run name).

    It writes to a temporary file next to ``rrd_path``; :meth:`close` renames it into place,
    so no half-written .rrd is left under the final name (as a context manager, an exception
    deletes the temporary file instead). Axes are REP-103 (right-handed, z up). ``layout``, a
    function of the set of logged entity paths that returns a blueprint, gives the viewer's
    layout; it is called and sent on :meth:`close`, when every path is known.
    """

    def __init__(self, rrd_path, run_name, layout=None):
        self.path = check_output_path(rrd_path)   # a regular file or a new path, never a device
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._tmp = self.path.with_name(f".{self.path.name}.{os.getpid()}.tmp")
        self._layout = layout
        self.stream = _IndexedStream("motoflex_ros", recording_id=str(run_name))
        self.stream.save(self._tmp)
        self.stream.send_recording_name(str(run_name))
        self.stream.log("/", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)

    def close(self, keep=True):
        """Flush and close the stream; move the file into place (``keep``) or delete it."""
        if keep and self._layout is not None:
            self.stream.send_blueprint(self._layout(self.stream.entity_paths))
        self.stream.flush()
        self.stream.disconnect()
        if keep:
            os.replace(self._tmp, self.path)
            return self.path
        self._tmp.unlink(missing_ok=True)
        return None

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *exc):
        self.close(keep=exc_type is None)


def subsample_indices(n, limit=MAX_SHAPE_FRAMES):
    """At most ``limit`` evenly spaced indices of ``range(n)``, always with the first and last."""
    if n <= limit:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, limit)).astype(int))


def exaggeration_factor(node_xyz, displacements, share=0.1):
    """Factor that makes the largest node displacement ``share`` of the model's size [-].

    Rounded down to 1, 2 or 5 times a power of ten so the stated factor reads well; 1 when
    nothing moves.
    """
    size = np.ptp(np.asarray(node_xyz, float), axis=0).max()
    peak = np.abs(np.asarray(displacements, float)).max(initial=0.0)
    if peak <= 0 or size <= 0:
        return 1.0
    raw = share * size / peak
    power = 10.0 ** np.floor(np.log10(raw))
    return float(max(m for m in (1, 2, 5) if m * power <= raw) * power)


def _segments(node_xyz, elements):
    node_xyz = np.asarray(node_xyz, float)
    return node_xyz[np.asarray(elements, int)]


def log_component_frame(rec, component, origin, bench_offset=(0.0, 0.0, 0.0)):
    """Static placement of the component frame: O in the vehicle frame [m] + ``bench_offset``.

    The offset [m] sets components that share a placement (frame and swingarm clamp at the
    same pivot) side by side on the bench; their x-z planes stay parallel.
    """
    translation = np.asarray(origin, float) + np.asarray(bench_offset, float)
    rec.log(f"/bench/{component}", rr.Transform3D(translation=translation), static=True)


def log_structure_model(rec, component, node_xyz, elements, clamp_xyz, load_xyz, factor,
                        source=None):
    """Static parts of /bench/<c>/structure: undeformed beams, clamps, load point, factor.

    ``source`` (text) says where the deformed shapes come from; it opens the stated factor.
    """
    base = f"/bench/{component}/structure"
    rec.log(f"{base}/undeformed", rr.LineStrips3D(_segments(node_xyz, elements),
                                                  colors=UNDEFORMED_COLOR, radii=0.002),
            static=True)
    rec.log(f"{base}/clamps", rr.Points3D(np.atleast_2d(clamp_xyz), colors=CLAMP_COLOR,
                                          radii=0.015), static=True)
    rec.log(f"{base}/load_point", rr.Points3D(np.atleast_2d(load_xyz), colors=LOAD_COLOR,
                                              radii=0.015), static=True)
    nodes = np.asarray(node_xyz, float)
    top = [nodes[:, 0].mean(), nodes[:, 1].mean(), nodes[:, 2].max() + 0.12]
    rec.log(f"/bench/{component}/name", rr.Points3D([top], colors=(40, 40, 40), radii=0.002,
                                                     labels=[component.replace("_", " ")],
                                                     show_labels=True), static=True)
    origin = f"{source}, " if source else ""
    rec.log(f"{base}/exaggeration", rr.TextDocument(
        f"Deformed shape of {component}: {origin}node displacements exaggerated x{factor:g} "
        "(the arrows and time series are true size)."), static=True)
    rec.log(base, rr.AnyValues(exaggeration_factor=float(factor)), static=True)


def log_structure(rec, component, node_xyz, elements, times, node_displacements, factor,
                  clamp_xyz, load_xyz, source=None):
    """The beam model of a component, deformed over time (Sect. 4.2 bench tests).

    Parameters
    ----------
    rec : rerun.RecordingStream
        The run's stream.
    component : str
        Component name (frame, front_assembly, swingarm, ...).
    node_xyz : array (n_nodes, 3)
        Undeformed node positions in the component frame [m].
    elements : array (n_elements, 2)
        Node index pairs of the beam elements.
    times : array (n_times,)
        Simulated time [s] of each shape.
    node_displacements : array (n_times, n_nodes, 3)
        Node translations [m]; drawn as ``node_xyz + factor * displacement``.
    factor : float
        Exaggeration of the displacements [-], stated in the recording.
    clamp_xyz, load_xyz : array (k, 3) and (3,)
        Clamp points and loaded end q0 [m].
    source : str, optional
        Where the shapes come from (stated with the factor in ``structure/exaggeration``).

    Returns
    -------
    int
        Number of shapes logged (at most :data:`MAX_SHAPE_FRAMES`).

    """
    log_structure_model(rec, component, node_xyz, elements, clamp_xyz, load_xyz, factor,
                        source)
    node_xyz = np.asarray(node_xyz, float)
    displacements = np.asarray(node_displacements, float)
    picks = subsample_indices(len(times))
    for i in picks:
        rec.set_time(TIMELINE, duration=float(times[i]))
        deformed = node_xyz + factor * displacements[i]
        rec.log(f"/bench/{component}/structure",
                rr.LineStrips3D(_segments(deformed, elements), colors=STRUCTURE_COLOR,
                                radii=0.004))
    return len(picks)


def _series(rec, path, times, values, names):
    values = np.asarray(values, float).reshape(len(times), -1)
    rec.log(path, rr.SeriesLines(names=list(names)), static=True)
    rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=np.asarray(times, float))],
                     columns=rr.Scalars.columns(scalars=values))


def log_load(rec, component, times, forces, load_xyz, end_displacements,
             displacement_times=None, arrow_m_per_n=None):
    """The load as an arrow at the loaded end and time series of load and end displacement.

    ``forces`` (n, 3) [N] in the component frame at ``times`` [s]; ``end_displacements``
    (m, 3) [m] of the loaded end at ``displacement_times`` [s] (default: ``times``);
    ``arrow_m_per_n`` [m/N] draws the largest force 0.15 m long by default. Returns the number
    of load samples logged.
    """
    times = np.asarray(times, float)
    forces = np.asarray(forces, float).reshape(len(times), 3)
    base = f"/bench/{component}/load"
    _series(rec, f"{base}/force", times, forces, ["F_x [N]", "F_y [N]", "F_z [N]"])
    _series(rec, f"{base}/end_displacement",
            times if displacement_times is None else displacement_times, end_displacements,
            ["u_x [m]", "u_y [m]", "u_z [m]"])
    peak = np.abs(forces).max(initial=0.0)
    scale = arrow_m_per_n if arrow_m_per_n is not None else (0.15 / peak if peak > 0 else 0.0)
    origins = np.tile(np.asarray(load_xyz, float), (len(times), 1))
    rec.send_columns(base, indexes=[rr.TimeColumn(TIMELINE, duration=times)],
                     columns=rr.Arrows3D.columns(vectors=forces * scale, origins=origins,
                                                 colors=np.tile(LOAD_COLOR, (len(times), 1))))
    return len(times)


def log_axis(rec, component, test, l, beta, q0, half_length=None):
    """Deformation axis of one test (static, torsion, bending, principal_<i>) and its joint, as
    Figs. 5-7.

    l [m], beta [rad] as identified (eqs. 5-6); q0 [m] the unloaded loaded end. The strip is
    drawn ``half_length`` [m] (default: |q0|) either side of the joint in the x-z plane.
    """
    axis = axis_from_l_beta(l, beta, q0)
    color = AXIS_COLORS.get(test, (200, 200, 200))
    path = f"/bench/{component}/axes/{test}"
    segment = axis_segment_xyz(l, beta, q0, half_length)
    rec.log(path, rr.LineStrips3D([segment], colors=color, radii=0.004), static=True)
    along, lift = AXIS_LABEL_PLACES.get(test, (1.0, 0.0))
    place = (segment[0] + segment[1]) / 2 + along * (segment[1] - segment[0]) / 2
    rec.log(f"{path}/label", rr.Points3D([place + [0.0, 0.0, lift]], colors=color,
                                         radii=0.003, labels=[f"{test} axis"],
                                         show_labels=True), static=True)
    rec.log(f"{path}/joint", rr.Points3D([[axis.x_j, 0.0, axis.z_j]], colors=color,
                                         radii=0.02), static=True)


AXIS_LABEL_PLACES = {"static": (1.0, 0.08), "torsion": (-1.0, 0.0), "bending": (0.45, -0.08)}
"""Where an axis' label sits: along its strip from the joint (-1 and 1: its ends) and lifted
by [m] (z), so the three labels of a component never share a spot (they met at the
joints, and the static and bending axes can be almost parallel)."""


def log_sweep_axes(rec, component, frequencies_hz, ls, betas, q0, half_length=None):
    """Axes of the harmonic sweep (Figs. 5-7, thin black lines): one strip per frequency."""
    strips = [axis_segment_xyz(l, b, q0, half_length) for l, b in zip(ls, betas)]
    rec.log(f"/bench/{component}/axes/sweep",
            rr.LineStrips3D(strips, colors=(20, 20, 20), radii=0.0015), static=True)
    rec.log(f"/bench/{component}/axes/sweep/frequencies", rr.TextDocument(
        "Sweep axes (thin black lines) at " + ", ".join(f"{f:.3g}" for f in frequencies_hz)
        + " Hz."), static=True)
    return len(strips)


def quantity_of(name):
    """The quantity of :data:`IDENTIFIED_QUANTITIES` an identified value's name gives, or None.

    'k_t' and 'k_b' are stiffnesses k; a mode's value is named '<mode>.<name>'
    ('torsion.f_hz'); bookkeeping ('ci.level', 'n_samples_decay') has no quantity.
    """
    *prefix, base = name.split(".")
    if "ci" in prefix:
        return None
    quantity = _QUANTITY_OF_NAME.get(base, base)
    return quantity if quantity in IDENTIFIED_QUANTITIES else None


def log_identification(rec, component, test, values, time_s):
    """Identified values of one test as scalars at ``time_s`` [s] of simulated time.

    ``values`` maps names (l, beta, b, k, c, J, f_hz, k_t, k_b, ...) to numbers in SI units;
    non-numeric or non-finite entries are skipped. A value with a quantity is drawn as a point
    named for its test and unit. Returns the names logged.
    """
    rec.set_time(TIMELINE, duration=float(time_s))
    logged = []
    for name, value in values.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
            continue
        if not np.isfinite(value):
            continue
        path = f"/identification/{component}/{test}/{name}"
        quantity = quantity_of(name)
        if quantity is not None:
            rec.log(path, rr.SeriesPoints(
                names=[f"{test} {name} [{IDENTIFIED_QUANTITIES[quantity]}]"]), static=True)
        rec.log(path, rr.Scalars(float(value)))
        logged.append(name)
    return logged


TABLE_COLUMNS = (("l", "l [m]", 1.0, ".4f"), ("beta", "\u03b2 [deg]", 180.0 / np.pi, ".2f"),
                 ("b", "b [m]", 1.0, ".4f"), ("k", "k [N m/rad]", 1.0, ".4g"),
                 ("c", "c [N m s/rad]", 1.0, ".4g"), ("J", "J [kg m\u00b2]", 1.0, ".4g"),
                 ("f_hz", "f [Hz]", 1.0, ".4g"))
"""Columns of the identification table: key, heading, factor from SI, format."""


def _table_cell(values, key, factor, spec, assumed):
    value = values.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
        return "-"
    if not np.isfinite(value):
        return "-"
    return format(value * factor, spec) + (" (assumed)" if assumed else "")


def identification_markdown(component, tests, split=None):
    """The identified values of ``component`` as a markdown table: one row per test of
    ``tests`` ({test: {name: SI value}}), beta in degrees, the static test's c marked assumed
    (c = 0.001 s x k, Passigato et al. 2023 Sect. 5.2.4), then k_t and k_b (eq. 12) of
    ``split``."""
    lines = ["| test | " + " | ".join(h for _, h, _, _ in TABLE_COLUMNS) + " |",
             "|---|" + "---:|" * len(TABLE_COLUMNS)]
    for test, values in tests.items():
        lines.append(f"| {test} | " + " | ".join(
            _table_cell(values, key, factor, spec, test == "static" and key == "c")
            for key, _, factor, spec in TABLE_COLUMNS) + " |")
    split = {k: v for k, v in (split or {}).items() if isinstance(v, (int, float))}
    if split:
        lines += ["", "Split of k (eq. 12): " + ", ".join(
            f"{name} = {value:.4g}" for name, value in split.items()) + " N m/rad."]
    lines += ["", "l, \u03b2, b: the axis (eqs. 5-7); the static test's c is assumed "
              "(0.001 s x k), not identified."]
    return "\n".join(lines)


def log_identification_table(rec, component, tests, split=None):
    """/identification/<component>/table: :func:`identification_markdown` (static)."""
    rec.log(f"/identification/{component}/table", rr.TextDocument(
        identification_markdown(component, tests, split), media_type=rr.MediaType.MARKDOWN),
        static=True)
