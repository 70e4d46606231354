"""A structure FMU this project did not export, in the loop with MillingProcess.fmu.

``third_party/TwoModeXY.py`` is a two-mode x-y tool structure written with pythonfmu (mode 1
along x at 600 Hz, mode 2 along y at 900 Hz, RK4 with the force held: a model a user might
bring). ``third_party/ThirdPartyStructure.ssd`` connects it to our process as a *tool* structure:
the process's ``force_x/y`` (the force on the tool) into the structure's ``tool_force_x/y``, the
structure's ``tool_x/y`` into the process's ``tool_x/y`` (the workpiece inputs stay 0), Gauss-Seidel
``structure process`` at 10 us for 0.05 s. The test builds the FMU with pythonfmu, packs the SSP, runs it in
the Rust master (``cosim run --preload libpython``) and in the FMPy loop of ``fmpy_closed_loop``,
and compares every recorded column to 1e-12.
"""
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import numpy as np

from conftest import fmu_path
from fmpy_closed_loop import System
from test_cross_check import assert_close, cosim

HERE = Path(__file__).resolve().parent / "third_party"
STOP = 0.05
RECORD = ["process.force_x", "process.force_y", "process.chip_thickness", "structure.tool_x", "structure.tool_y"]


def build_ssp(tmp_path):
    subprocess.run([sys.executable, "-m", "pythonfmu", "build", "-f", str(HERE / "TwoModeXY.py"), "-d", str(tmp_path)],
                   check=True, capture_output=True)
    ssp = tmp_path / "ThirdPartyStructure.ssp"
    with zipfile.ZipFile(ssp, "w") as z:
        z.write(HERE / "ThirdPartyStructure.ssd", "SystemStructure.ssd")
        z.write(fmu_path("MillingProcess"), "resources/MillingProcess.fmu")
        z.write(tmp_path / "TwoModeXY.fmu", "resources/TwoModeXY.fmu")
    return ssp


def test_a_pythonfmu_structure_runs_with_our_process_in_our_master_and_fmpy_alike(tmp_path):
    ssp = build_ssp(tmp_path)
    libpython = Path(sysconfig.get_config_var("LIBDIR")) / sysconfig.get_config_var("LDLIBRARY")
    out = tmp_path / "rust.csv"
    cmd = [str(cosim()), "run", str(ssp), "--quiet", "--preload", str(libpython), "--record", ",".join(RECORD),
           "-o", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}\n{r.stderr}"
    rust = np.genfromtxt(out, delimiter=",", names=True, deletechars="")
    system = System(ssp)
    try:
        assert [c.name for c in system.sequence] == ["structure", "process"]
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
