"""Unit conversions used across the package (SI inside; km/h only at the edges).

The paper gives speeds in km/h (40-210 km/h, Sect. 4.3); everything inside works in m/s.
"""
import numpy as np

__all__ = ["KMH_PER_MS", "NS_PER_S", "kmh_to_ms", "ms_to_kmh"]

KMH_PER_MS = 3.6  # 1 m/s = 3.6 km/h
NS_PER_S = 1_000_000_000  # ROS time stamps and bag log times are integer nanoseconds


def kmh_to_ms(speed_kmh):
    """Speed(s) [km/h] in [m/s] (float array, or a NumPy float for a scalar)."""
    return np.asarray(speed_kmh, dtype=float) / KMH_PER_MS


def ms_to_kmh(speed_ms):
    """Speed(s) [m/s] in [km/h] (float array, or a NumPy float for a scalar)."""
    return np.asarray(speed_ms, dtype=float) * KMH_PER_MS
