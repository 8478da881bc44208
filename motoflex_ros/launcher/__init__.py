"""Process orchestration of the rig: every node a separate process on its own ROS domain."""
