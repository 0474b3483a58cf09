"""The non-SI units a scenario file may use (degrees, rpm), as factors to SI."""

import math

DEG = math.pi / 180.0          # [rad/deg]
RPM = 2.0 * math.pi / 60.0     # [rad/s per rpm]
