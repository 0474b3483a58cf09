"""Controller designs.  Each maps the measurement layout of the plant to a command.

A design provides gains ``k`` (a :class:`~rpo.symbolic.physics.layout.Layout`), integrated controller
states ``xc`` (adaptive estimates, observer states; may be empty), diagnostic outputs, and
:meth:`law` returning SymPy expressions for

* ``cmd`` (9): wheel torque command (body, N m), thruster force command (body, N), thruster
  torque command (body, N m) -- see :data:`COMMAND`;
* ``xc_dot``: the controller-state derivative (integrated by RK4 with the measurement held);
* ``diag``: values to log (sliding surfaces, estimates, ...).
"""

from __future__ import annotations

from ..physics.layout import XYZ, Layout


def command_layout() -> Layout:
    c = Layout("cmd")
    c.add("tau_w", 3, "N m", "torque commanded to the wheels, chaser body", XYZ)
    c.add("F", 3, "N", "force commanded to the thrusters, chaser body", XYZ)
    c.add("tau_thr", 3, "N m", "torque commanded to the thrusters, chaser body", XYZ)
    return c
