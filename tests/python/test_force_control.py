"""Seed 004's shipped system ForceControl.ssp (MillingForcePlant + FrohMracController) in FMPy.

``fmpy_closed_loop.System`` drives the two FMUs with FMPy's FMU2Slave in the order declared in
ForceControl.ssd (Gauss-Seidel controller, plant; step = sample period / 20) and the Rust master
(``cosim run target/fmu/ForceControl.ssp``) runs the same system: every recorded column agrees
to 1e-12 relative. The run crosses the first depth step (3 s) and ends at the second (6 s), so the adaptation, the FROH ramp
and the plant's depth profile are all exercised.
"""
import numpy as np

from fmpy_closed_loop import System
from test_cross_check import assert_close, run_rust, ssp_path

STOP = 6.0  # a whole number of steps (1430)
RECORD = ["plant.F_p", "plant.f_a", "plant.b", "plant.f_c", "plant.f_c_rate",
          "controller.F_p", "controller.f_c", "controller.f_c_rate", "controller.f_hold", "controller.u_k",
          "controller.F_m", "controller.a_hat", "controller.b0_hat", "controller.b1_hat"]


def test_rust_master_matches_an_fmpy_loop_to_1e_12(tmp_path):
    rust = run_rust(tmp_path, ["--stop-time", str(STOP), "--record", ",".join(RECORD)], "force", ssp="ForceControl.ssp")
    system = System(ssp_path("ForceControl.ssp"))
    try:
        assert [c.name for c in system.sequence] == ["controller", "plant"]
        ts = 60.0 / 715.0
        assert abs(ts / system.step - 20) < 1e-9, "the step is a twentieth of the sample period"
        times, py = system.run(STOP, {}, RECORD)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / system.step) + 1
    assert np.array_equal(rust["time"], np.array(times))
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    # the loop holds 1.2 kN before the depth step and the depth doubles at 3 s
    t = np.array(times)
    force = np.array(py["plant.F_p"])
    settled = (t > 2.0) & (t < 3.0)
    assert np.all(np.abs(force[settled] - 1200.0) < 12.0), force[settled].min()
    b = np.array(py["plant.b"])
    assert np.all(b[(t > 3.001) & (t < 5.999)] == 4.0) and b[-1] == 1.0, "depth 4 mm from 3 s, 1 mm from 6 s"


def test_each_fmu_simulates_alone_in_fmpy_with_defaults():
    """FMPy's own co-simulation driver: the plant with a constant 20 mm/s command settles at
    K_p(2 mm) * 20 = 1007 N; the controller with its default 1.2 kN reference and a zero force
    measurement commands a growing feed (it sees no force) without failing."""
    from fmpy import simulate_fmu
    from conftest import fmu_path

    plant = simulate_fmu(str(fmu_path("MillingForcePlant")), stop_time=2.5, output_interval=60 / 715 / 20,
                         start_values={"f_c": 20.0}, fmi_type="CoSimulation")
    kp = 1200.0 * 2.0 * 60.0 / (715.0 * 4.0)
    assert abs(plant["F_p"][-1] - kp * 20.0) < 1e-6 * kp * 20.0
    assert np.all(plant["b"] == 2.0)
    ctrl = simulate_fmu(str(fmu_path("FrohMracController")), stop_time=1.0, output_interval=60 / 715 / 20,
                        fmi_type="CoSimulation")
    assert np.all(np.isfinite(ctrl["f_c"])) and ctrl["f_c"][-1] > 0.0
