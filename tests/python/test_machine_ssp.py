"""A user's machine as an SSP (`chatter machine ssp`), run in FMPy: the machine file's system
(MillingProcess + ModalStructure + InertialActuator + ChatterController, parameters bound from
the file, enumerations as integers) driven by FMPy's FMU2Slave in the SSD's order equals the Rust
master (`cosim run`) to 1e-12 relative."""
import subprocess

import numpy as np

from conftest import ROOT
from fmpy_closed_loop import System
from test_cross_check import assert_close, cosim

CHATTER = ROOT / "target" / "release" / "chatter"
RECORD = ["structure.tool_x", "structure.tool_y", "process.force_x", "process.force_y", "controller.u", "actuator.force"]


def test_the_machine_ssp_runs_in_fmpy_as_in_the_rust_master(tmp_path):
    ssp = tmp_path / "end_mill.ssp"
    machine = tmp_path / "end_mill.toml"
    text = (ROOT / "studies" / "machine" / "examples" / "end_mill.toml").read_text()
    machine.write_text(text + '\n[controller]\nstructure = "pid"\nset = { "pid.kp" = 1.1e3, "pid.kd" = 200.0 }\n')
    r = subprocess.run([str(CHATTER), "machine", "ssp", str(machine), "--out", str(ssp), "--rpm", "10000",
                        "--depth-mm", "2"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
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
