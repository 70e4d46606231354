"""A third-party x-y tool structure written with pythonfmu: two modes, one along x, one along y."""
import math
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class TwoModeXY(Fmi2Slave):
    author = "chatter-fmu tests"
    description = "Two-mode x-y tool structure (third-party style, pythonfmu)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.fx_hz = 600.0
        self.fy_hz = 900.0
        self.zeta = 0.03
        self.mass = 2.0
        self.tool_force_x = 0.0
        self.tool_force_y = 0.0
        self.actuator_force_x = 0.0
        self.actuator_force_y = 0.0
        self.tool_x = 0.0
        self.tool_y = 0.0
        self.vx = 0.0
        self.vy = 0.0
        for n in ("fx_hz", "fy_hz", "zeta", "mass"):
            self.register_variable(Real(n, causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable))
        # the cutting force and an active damper's force, both at the tool point
        for n in ("tool_force_x", "tool_force_y", "actuator_force_x", "actuator_force_y"):
            self.register_variable(Real(n, causality=Fmi2Causality.input))
        for n in ("tool_x", "tool_y"):
            self.register_variable(Real(n, causality=Fmi2Causality.output))

    def _mode(self, q, v, f_hz, force, h):
        # classical RK4 with the force held
        w = 2.0 * math.pi * f_hz
        c = 2.0 * self.zeta * w
        def acc(q, v):
            return force / self.mass - c * v - w * w * q
        k1q, k1v = v, acc(q, v)
        k2q, k2v = v + 0.5 * h * k1v, acc(q + 0.5 * h * k1q, v + 0.5 * h * k1v)
        k3q, k3v = v + 0.5 * h * k2v, acc(q + 0.5 * h * k2q, v + 0.5 * h * k2v)
        k4q, k4v = v + h * k3v, acc(q + h * k3q, v + h * k3v)
        return (q + h / 6.0 * (k1q + 2 * k2q + 2 * k3q + k4q), v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v))

    def do_step(self, current_time, step_size):
        fx = self.tool_force_x + self.actuator_force_x
        fy = self.tool_force_y + self.actuator_force_y
        self.tool_x, self.vx = self._mode(self.tool_x, self.vx, self.fx_hz, fx, step_size)
        self.tool_y, self.vy = self._mode(self.tool_y, self.vy, self.fy_hz, fy, step_size)
        return True
