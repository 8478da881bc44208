"""Recording of runs: rosbag2-compatible MCAP bags (:mod:`motoflex_ros.record.mcap_bag`)."""
