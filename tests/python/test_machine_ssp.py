"""A user's machine as an SSP (`chatter machine ssp`), run in FMPy and libcosim: the machine
file's system (MillingProcess + ModalStructure + InertialActuator + ChatterController,
parameters bound from the file, enumerations as integers) driven by FMPy's FMU2Slave in the
SSD's order equals the Rust master (`cosim run`) to 1e-12 relative, and libcosim (which binds
the SSD's parameters itself, Jacobi) equals our master in Jacobi order to 1e-12."""
import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from fmpy_closed_loop import System
from test_cross_check import assert_close, cosim

CHATTER = ROOT / "target" / "release" / "chatter"
RECORD = ["structure.tool_x", "structure.tool_y", "process.force_x", "process.force_y", "controller.u", "actuator.force"]


def machine_ssp(tmp_path):
    """The example end mill with a PID controller, written as an SSP by `chatter machine ssp`."""
    ssp = tmp_path / "end_mill.ssp"
    machine = tmp_path / "end_mill.toml"
    text = (ROOT / "studies" / "machine" / "examples" / "end_mill.toml").read_text()
    machine.write_text(text + '\n[controller]\nstructure = "pid"\nset = { "pid.kp" = 1.1e3, "pid.kd" = 200.0 }\n')
    r = subprocess.run([str(CHATTER), "machine", "ssp", str(machine), "--out", str(ssp), "--rpm", "10000",
                        "--depth-mm", "2"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return ssp


def test_the_machine_ssp_runs_in_fmpy_as_in_the_rust_master(tmp_path):
    ssp = machine_ssp(tmp_path)
    stop = 0.02
    out = tmp_path / "rust.csv"
    r = subprocess.run([str(cosim()), "run", str(ssp), "--quiet", "--stop-time", str(stop), "--record",
                        ",".join(RECORD), "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    rust = np.genfromtxt(out, delimiter=",", names=True, deletechars="")
    system = System(ssp)
    try:
        assert [c.name for c in system.sequence] == ["controller", "actuator", "structure", "process"]
        times, py = system.run(stop, {}, RECORD)
    finally:
        system.close()
    assert np.array_equal(rust["time"], np.array(times))
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    assert np.max(np.abs(py["process.force_x"])) > 10.0 and np.max(np.abs(py["controller.u"])) > 0.0


# Measured: libcosim 0.0.6 runs this SSP with ChatterController's `structure` at its default
# (ADRC-FOPID): its controller.u equals our master's run of the same machine with
# structure = "adrc_fopid" exactly over 50 steps, although the SSD binds structure = 2 (PID) as
# ssv:Integer. The shipped SSPs bind enumerations only at their defaults, so test_all_masters does
# not see it. strict: the test fails once libcosim applies the binding, so the mark goes.
@pytest.mark.xfail(strict=True, reason="libcosim 0.0.6 leaves the enumeration `structure` at its default")
def test_the_machine_ssp_runs_in_libcosim_as_in_the_rust_master(tmp_path):
    from test_all_masters import LIBCOSIM_RUN, ours, system
    if sys.version_info[:2] != (3, 11):
        pytest.skip("libcosimpy 0.0.6 ships a CPython 3.11 wheel only (tests/python/requirements.txt)")
    ssp = machine_ssp(tmp_path)
    step, outputs, _ = system(ssp)
    ns = round(step * 1e9)
    assert abs(ns - step * 1e9) < 1e-6, step
    steps = 2000
    r = subprocess.run([sys.executable, "-c", LIBCOSIM_RUN, str(ssp), str(ns), str(steps), json.dumps(outputs)],
                       capture_output=True, text=True)
    assert r.returncode == 0, f"libcosim failed (exit {r.returncode}):\n{r.stderr[-2000:]}"
    theirs = np.asarray(json.loads(r.stdout))
    out = tmp_path / "jacobi.csv"
    r = subprocess.run([str(cosim()), "run", str(ssp), "--quiet", "--order", "jacobi", "--stop-time",
                        repr(steps * step), "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    mine = np.genfromtxt(out, delimiter=",", names=True, deletechars="")
    for j, col in enumerate(outputs):
        a, b = np.asarray(mine[col][1:]), theirs[:, j]
        scale = max(np.max(np.abs(a)), 1e-300)
        assert np.max(np.abs(a - b)) <= 1e-12 * scale, f"{col} differs by {np.max(np.abs(a - b)):e}"
    assert np.max(np.abs(theirs[:, outputs.index("process.force_x")])) > 10.0, "the tool cuts"
