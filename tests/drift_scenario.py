"""The small scenario several campaign tests disperse: a free-flying pair on a circular orbit, no
disturbance, ideal actuators, the baseline law (the caller sets its gains), starting 55 m apart."""

from __future__ import annotations


def drift_scenario(name: str, duration: float, semi_major_axis: float = 7.0e6) -> str:
    """The scenario's TOML text, ``[meta]`` to ``[relative]`` (``duration`` [s], 1 Hz, the orbit's
    ``semi_major_axis`` [m]); a campaign appends its gains, ``[campaign]`` and ``[dispersions]``."""
    return f"""
[meta]
name = "{name}"
[simulation]
duration = {float(duration)!r}
rate = 1.0
controller = "baseline"
[orbit]
semi_major_axis = {float(semi_major_axis)!r}
eccentricity = 0.0
inclination_deg = 30.0
[environment]
gravity_gradient = false
magnetic = false
j2 = false
drag = false
random_torque_std_chaser = 0.0
random_torque_std_target = 0.0
[plant]
actuators = "ideal"
max_force = 1.0
max_torque = 0.1
[chaser]
mass = 100.0
mass_profile = "constant"
attitude_frame = "eci"
quaternion = [0.0, 0.0, 0.0, 1.0]
[target]
attitude_frame = "eci"
quaternion = [0.0, 0.0, 0.0, 1.0]
[relative]
position = [50.0, 20.0, -10.0]
velocity = [0.0, -0.05, 0.01]
"""
