"""The rerun recording of a run folder, as ``motoflex rerun``, ``campaign`` and ``view`` make it.

The core computes what is drawn (the identified motorcycle's weave, wobble and road test:
:mod:`motoflex_ros.vehicle.animation`; the bench's replayed shapes:
:mod:`motoflex_ros.bench.replayed_loads`); the record layer writes it (:func:`~motoflex_ros.record.
rerun_bag.convert_bag`).
"""
from motoflex_ros.units import kmh_to_ms

__all__ = ["write_recording", "MODE_SPEED_KMH"]

MODE_SPEED_KMH = 100.0   # speed of the animated modes and the road test [km/h]


def write_recording(bag, out=None, vehicle="touring", progress=False,
                    speed_kmh=MODE_SPEED_KMH):
    """Write ``bag``'s .rrd (``out``, default <bag>/<run>.rrd); returns (path, converted).

    ``vehicle``: a shipped vehicle name or YAML drawn with its modes and road test at
    ``speed_kmh`` (its lumped 'static' variant when the run folder holds identification
    results), or None.
    """
    from motoflex_ros.record.rerun_bag import convert_bag, run_identification
    motorcycle = None
    if vehicle is not None:
        from motoflex_ros.config import MOTORCYCLE_COMPONENTS
        from motoflex_ros.formats.component_file import load_component
        from motoflex_ros.study.identified_variants import identified_motorcycle
        from motoflex_ros.vehicle.animation import motorcycle_motion
        identified = run_identification(bag)
        components = {n: load_component(n) for n in MOTORCYCLE_COMPONENTS
                      if n in (identified or {})}
        model, description = identified_motorcycle(vehicle, identified, components)
        motorcycle = (motorcycle_motion(model, kmh_to_ms(speed_kmh)), description)
    return convert_bag(bag, out, motorcycle, progress=progress)
