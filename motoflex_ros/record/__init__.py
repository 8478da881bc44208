"""Recording of runs: rosbag2-compatible MCAP bags (:mod:`motoflex_ros.record.mcap_bag`).

Modules: ``mcap_bag`` (bags), ``tf_bag`` (/tf in the bag), ``log_time`` (the
simulated time a message is logged at), ``measured_bag`` (a rig's bag as
measurements); the rerun recording: ``rerun_log`` (bench components, loads, axes),
``rerun_bag`` (a recorded run to .rrd), ``rerun_bag_vehicle``, ``rerun_vehicle`` and
``rerun_motorcycle`` (the motorcycle), ``rerun_blueprint`` (the viewer layout),
``rerun_readback`` (reading a recording back), ``rerun_private`` (the rerun binary without the
user's configuration).
"""
