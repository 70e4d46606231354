"""Seed 003's shipped system SlidingModeFuzzy.ssp (ToolXyPlant + SlidingModeFuzzyController) in FMPy.

``fmpy_closed_loop.System`` drives the two FMUs with FMPy's FMU2Slave in the order declared in
SlidingModeFuzzy.ssd (Gauss-Seidel controller, plant; step = sample period 1e-4 s; the SSD binds
the calibrated forcing amplitudes) and the Rust master (``cosim run target/fmu/SlidingModeFuzzy.ssp``)
runs the same system: every recorded column agrees to 1e-12 relative, for DSMC-T2 (default) and
D-PID. The run covers ten delay periods, so the delay line, the damper and the fuzzy learning are
all exercised.
"""
import numpy as np
import pytest

from fmpy_closed_loop import System
from test_cross_check import assert_close, run_rust, ssp_path

STOP = 0.05  # 500 steps
RECORD = ["plant.x", "plant.y", "plant.vx", "plant.vy", "plant.F_x", "plant.damper_x",
          "controller.u_x", "controller.u_y", "controller.s_x", "controller.j_hat_x", "controller.h_hat_y",
          "controller.e_m_x", "controller.updates_y"]


@pytest.mark.parametrize("mode", ["dsmc_t2", "dpid"])
def test_rust_master_matches_an_fmpy_loop_to_1e_12(tmp_path, mode):
    sets = ["--set", f"controller.mode={mode}"]
    rust = run_rust(tmp_path, ["--stop-time", str(STOP), "--record", ",".join(RECORD)] + sets, f"smf-{mode}",
                    ssp="SlidingModeFuzzy.ssp")
    system = System(ssp_path("SlidingModeFuzzy.ssp"))
    try:
        assert [c.name for c in system.sequence] == ["controller", "plant"]
        assert abs(system.step - 1e-4) < 1e-15
        times, py = system.run(STOP, {"controller.mode": mode}, RECORD)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / system.step) + 1
    assert np.array_equal(rust["time"], np.array(times))
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    # the forcing reaches the tool and the controller acts on it
    assert np.max(np.abs(py["plant.x"])) > 1e-9
    assert np.max(np.abs(py["controller.u_x"])) > 0.0


def test_each_fmu_simulates_alone_in_fmpy_with_defaults():
    """FMPy's own driver: the tool with a constant 10 N on x and no forcing moves by about
    10 N / k_x; the controller with zero inputs stays finite."""
    from fmpy import simulate_fmu
    from conftest import fmu_path

    plant = simulate_fmu(str(fmu_path("ToolXyPlant")), stop_time=0.2, output_interval=1e-4,
                         start_values={"u_x": 10.0}, fmi_type="CoSimulation")
    assert np.all(np.isfinite(plant["x"]))
    assert 0.2 * 10.0 / 7.2e6 < np.max(plant["x"]) < 3.0 * 10.0 / 7.2e6
    ctrl = simulate_fmu(str(fmu_path("SlidingModeFuzzyController")), stop_time=0.01, output_interval=1e-4,
                        fmi_type="CoSimulation")
    assert np.all(np.isfinite(ctrl["u_x"]))
