"""Seed 001's shipped system Afrac.ssp (TurningProcess + AfracController) in FMPy.

``fmpy_closed_loop.System`` drives the two FMUs with FMPy's FMU2Slave in the order declared in
Afrac.ssd (Gauss-Seidel controller, plant; step = the controller's sample period 0.1 ms) and the
Rust master (``cosim run target/fmu/Afrac.ssp``) runs the same system: every recorded column
agrees to 1e-12 relative. The run crosses the disturbance pulse (0.02 s), the chatter growth and
the first switch of the Table 5 schedule (0.6935 s) with the bumpless option (the path with the
most state: its offsets come on top of the switched run), so the convolution memory, the
fractional integrators and the speed-dependent delay of the plant are all exercised. The switched
run without the option is checked bitwise against the core in ``tests/tests/afrac.rs``; one FMPy
run (about 30 s of Python stepping) keeps the test command inside its time budget.
"""
import numpy as np
import pytest

from fmpy_closed_loop import System
from test_cross_check import assert_close, run_rust, ssp_path

STOP = 0.75  # a whole number of steps (7500)
RECORD = ["plant.x", "plant.v", "plant.q", "plant.delay", "plant.spindle_speed", "plant.feed",
          "controller.spindle_speed", "controller.feed", "controller.beta", "controller.eps1",
          "controller.h", "controller.delta_feed", "controller.G"]


@pytest.mark.parametrize("bumpless", ["true"])
def test_rust_master_matches_an_fmpy_loop_to_1e_12(tmp_path, bumpless):
    overrides = {"controller.bumpless": bumpless}
    sets = sum((["--set", f"{k}={v}"] for k, v in overrides.items()), [])
    rust = run_rust(tmp_path, ["--stop-time", str(STOP), "--record", ",".join(RECORD)] + sets, f"afrac-{bumpless}",
                    ssp="Afrac.ssp")
    system = System(ssp_path("Afrac.ssp"))
    try:
        assert [c.name for c in system.sequence] == ["controller", "plant"]
        assert abs(system.step / 1e-4 - 1) < 1e-12, "the step is the sample period"
        times, py = system.run(STOP, overrides, RECORD)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / system.step) + 1
    assert np.array_equal(rust["time"], np.array(times))
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    # the controller acted: the speed left 450 rpm and the order stepped from 1.9 to 1.75
    speed = np.array(py["controller.spindle_speed"])
    assert np.max(np.abs(speed - 450.0)) > 5.0
    beta = np.array(py["controller.beta"])
    assert beta[0] == 1.9 and beta[-1] == 1.75


def test_the_controller_simulates_alone_in_fmpy_with_defaults():
    """FMPy's own co-simulation driver: with x = v = 0 the controller holds 450 rpm and 0.1 mm/rev."""
    from fmpy import simulate_fmu
    from conftest import fmu_path

    ctrl = simulate_fmu(str(fmu_path("AfracController")), stop_time=0.05, output_interval=1e-4,
                        fmi_type="CoSimulation")
    assert np.all(ctrl["spindle_speed"] == 450.0) and np.all(ctrl["feed"] == 0.1)
