"""A structure FMU this project did not export, in the loop with MillingProcess.fmu.

The shipped example ``packaging/examples/third_party/`` (built by its ``make_ssp.py``):
``TwoModeXY.py`` is a two-mode x-y tool structure written with pythonfmu (mode 1
along x at 600 Hz, mode 2 along y at 900 Hz, RK4 with the force held: a model a user might
bring). ``ThirdPartyStructure.ssd`` connects it to our process as a *tool* structure:
the process's ``force_x/y`` (the force on the tool) into the structure's ``tool_force_x/y``, the
structure's ``tool_x/y`` into the process's ``tool_x/y`` (the workpiece inputs stay 0); our
ChatterController measures ``tool_x`` and drives our InertialActuator, whose force enters the
structure's ``actuator_force_x/y``. Gauss-Seidel ``controller actuator structure process`` at
10 us for 0.05 s. The test builds the FMU with pythonfmu, packs the SSP, runs it in
the Rust master (``cosim run --preload libpython``) and in the FMPy loop of ``fmpy_closed_loop``,
and compares every recorded column to 1e-12. The same SSP runs in libcosim (libcosimpy, the
Open Simulation Platform's master): libcosim steps all components from the same communication
point and then exchanges (Jacobi), so it is compared with our master in ``--order jacobi``.
"""
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest

from conftest import fmu_path
from fmpy_closed_loop import System
from test_cross_check import assert_close, cosim

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "packaging" / "examples" / "third_party"))
import make_ssp  # noqa: E402  (the shipped example's builder)

STOP = 0.05
RECORD = ["process.force_x", "process.force_y", "process.chip_thickness", "structure.tool_x", "structure.tool_y",
          "controller.u", "actuator.force_x"]
LIBPYTHON = Path(sysconfig.get_config_var("LIBDIR")) / sysconfig.get_config_var("LDLIBRARY")


def build_ssp(tmp_path):
    return make_ssp.build(tmp_path, fmu_path("MillingProcess").parent)


def rust_run(ssp, out, *extra):
    cmd = [str(cosim()), "run", str(ssp), "--quiet", "--preload", str(LIBPYTHON), "--record", ",".join(RECORD),
           "-o", str(out), *extra]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}\n{r.stderr}"
    return np.genfromtxt(out, delimiter=",", names=True, deletechars="")


def test_a_pythonfmu_structure_runs_with_our_process_in_our_master_and_fmpy_alike(tmp_path):
    ssp = build_ssp(tmp_path)
    rust = rust_run(ssp, tmp_path / "rust.csv")
    system = System(ssp)
    try:
        assert [c.name for c in system.sequence] == ["controller", "actuator", "structure", "process"]
        times, py = system.run(STOP, {}, RECORD)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / 1e-5) + 1
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    # not vacuous: the tool moves in both axes under the cutting force, which pushes it
    # against the feed (-x, tangential drag of the teeth near the exit) and along +y on average
    x, y = np.asarray(py["structure.tool_x"]), np.asarray(py["structure.tool_y"])
    assert np.std(x[len(x) // 2:]) > 0 and np.std(y[len(y) // 2:]) > 0
    assert np.mean(py["process.force_x"]) < 0 < np.mean(py["process.force_y"])
    assert np.mean(x) < 0 < np.mean(y)
    # the controller acts: a non-zero command reaches the structure as the actuator's force
    assert np.max(np.abs(py["controller.u"])) > 0 and np.max(np.abs(py["actuator.force_x"])) > 0


def test_the_same_ssp_runs_in_libcosim_and_matches_our_master_in_jacobi_order(tmp_path):
    if sys.version_info[:2] != (3, 11):
        pytest.skip("libcosimpy 0.0.6 ships a CPython 3.11 wheel only (tests/python/requirements.txt)")
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    ssp = build_ssp(tmp_path)
    rust = rust_run(ssp, tmp_path / "jacobi.csv", "--order", "jacobi")
    log_output_level(CosimLogLevel.ERROR)
    ex = CosimExecution.from_ssp_file(str(ssp), step_size=10_000)  # libcosim counts time in ns
    assert ex.num_slaves() == 4
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    index = {s.name.decode(): s.index for s in ex.slave_infos()}
    refs = []
    for name in RECORD:
        comp, var = name.split(".")
        found = [v.reference for v in ex.slave_variables(index[comp]) if v.name.decode() == var]
        assert found, f"libcosim does not see {name}"
        refs.append((index[comp], found[0]))
    steps = round(STOP / 1e-5)
    cosim_rows = []
    for _ in range(steps):
        assert ex.step(1)
        cosim_rows.append([obs.last_real_values(i, [r])[0] for i, r in refs])
    cosim_rows = np.asarray(cosim_rows)
    assert len(rust["time"]) == steps + 1
    for j, name in enumerate(RECORD):
        # our row k+1 is the state after step k, as libcosim's last value after its k-th step.
        # libcosim passes h_n = t_{n+1} - t_n from integer nanoseconds, an ulp off 1e-5 now and
        # then: our FMUs step their nominal h (fmi2-export's clock), the Python structure
        # integrates the h it gets, so its displacements may differ by rounding: 1e-12 of the
        # column's largest value (pointwise relative would fail at zero crossings)
        ours, theirs = np.asarray(rust[name][1:]), cosim_rows[:, j]
        scale = np.max(np.abs(ours))
        worst = np.max(np.abs(ours - theirs))
        assert worst <= 1e-12 * scale, f"{name}: libcosim differs by {worst:e} (scale {scale:e})"
    assert np.std(cosim_rows[steps // 2:, 3]) > 0, "not vacuous: the tool moves"
