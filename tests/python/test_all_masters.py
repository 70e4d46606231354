"""Every shipped SSP in three masters: ours (``cosim``), libcosim (libcosimpy, the Open
Simulation Platform's master) and FMPy's ``simulate_ssp``.

Both other masters step every component from the same communication point and then exchange
(Jacobi), so they are compared with our master in ``--order jacobi``, over the first
``STEPS`` steps of each system at its own step size:

* libcosim applies the SSD's parameter bindings itself (the shipped SSPs write enumerations as
  ``ssv:Integer``: libcosim 0.0.6 aborted on ``ssv:Enumeration``, ``ssp_parser.cpp:69: Internal
  error`` on ClosedLoopTable2.ssp and Spindle.ssp). It runs in a subprocess, so that an abort is
  a failed test, not a dead pytest. Agreement to 1e-12 of each column's largest value (libcosim
  passes ``t_{n+1} - t_n`` from integer nanoseconds).
* FMPy's ``simulate_ssp`` does not read the SSD's parameter bindings: they are passed as its
  ``parameter_set`` (its API for them). It starts every connection at 0 instead of the
  outputs at t0 (Afrac.ssp failed at once: TurningProcess refused ``spindle_speed = 0``; a
  stopped spindle does not cut now), so its first step differs from ours by one step of
  coupling: the tolerance is that of the coupling order, 10 times the difference between our
  own Jacobi and Gauss-Seidel runs of the same system (plus 1e-12 of the column's scale).

Skipped, with the reason: ForceControl.ssp in libcosim (its step, the controller's sample period
0.6/143 s, is not a whole number of nanoseconds, libcosim's clock).
"""
import json
import pathlib
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy.ssp.simulation import simulate_ssp

from test_cross_check import cosim, ssp_path

STEPS = 200
SYSTEMS = ["ClosedLoop.ssp", "ClosedLoopTable2.ssp", "DecomposedPlant.ssp", "Spindle.ssp", "ForceControl.ssp", "Benchmark.ssp",
           "SlidingModeFuzzy.ssp", "Afrac.ssp"]
LIBCOSIM_CANNOT = {
    "ForceControl.ssp": "its step (the FROH controller's sample period 0.6/143 s) is not a whole number of "
                        "nanoseconds, libcosim's time unit",
}
SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"


def path_of(name):
    """A shipped SSP by name, or any .ssp by its path."""
    return name if isinstance(name, pathlib.Path) else ssp_path(name)


def system(name):
    """The SSD of a shipped SSP (or of the .ssp at a path): its step, output connectors and
    parameter bindings."""
    with zipfile.ZipFile(path_of(name)) as z:
        root = ET.fromstring(z.read("SystemStructure.ssd"))
    step = float(root.find(f".//{SSD}DefaultExperiment").find(".//*[@stepSize]").get("stepSize"))
    outputs, bindings = [], []
    for comp in root.iter(f"{SSD}Component"):
        c = comp.get("name")
        outputs += [f"{c}.{k.get('name')}" for k in comp.iter(f"{SSD}Connector") if k.get("kind") == "output"]
        for p in comp.iter(f"{SSV}Parameter"):
            (v,) = list(p)
            tag, text = v.tag.split("}")[1], v.get("value")
            value = {"Real": float, "Integer": int, "Boolean": lambda s: s == "true"}[tag](text)
            bindings.append(SimpleNamespace(name=f"{c}.{p.get('name')}", value=value))
    return step, outputs, bindings


def ours(tmp_path, name, step, order):
    out = tmp_path / f"{pathlib.Path(name).name}.{order}.csv"
    cmd = [str(cosim()), "run", str(path_of(name)), "--quiet", "--order", order, "--stop-time", repr(STEPS * step),
           "-o", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}\n{r.stderr}"
    return np.genfromtxt(out, delimiter=",", names=True, deletechars="")


LIBCOSIM_RUN = """
import json, sys
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimObserver import CosimObserver
path, ns, steps, names = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), json.loads(sys.argv[4])
log_output_level(CosimLogLevel.ERROR)
ex = CosimExecution.from_ssp_file(path, step_size=ns)
obs = CosimObserver.create_last_value()
ex.add_observer(obs)
index = {s.name.decode(): s.index for s in ex.slave_infos()}
refs = []
for name in names:
    comp, var = name.split(".", 1)
    refs.append((index[comp], [v.reference for v in ex.slave_variables(index[comp]) if v.name.decode() == var][0]))
rows = []
for _ in range(steps):
    assert ex.step(1)
    rows.append([obs.last_real_values(i, [r])[0] for i, r in refs])
print(json.dumps(rows))
"""


# Measured, cause not found yet (issue 29's last session): libcosim's run of Benchmark.ssp differs
# from ours in Jacobi order by 1.9e-6 relative on plant.x (FMPy's simulate_ssp and the FMPy loop of
# test_cross_check agree with ours). strict: the test fails once they agree, so the mark goes.
LIBCOSIM_DIFFERS = {"Benchmark.ssp": "plant.x differs from our master by 1.9e-6 relative; cause not yet found"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=LIBCOSIM_DIFFERS[n]))
                                  if n in LIBCOSIM_DIFFERS else n for n in SYSTEMS])
def test_every_shipped_ssp_runs_in_libcosim_like_ours(tmp_path, name):
    if sys.version_info[:2] != (3, 11):
        pytest.skip("libcosimpy 0.0.6 ships a CPython 3.11 wheel only (tests/python/requirements.txt)")
    if name in LIBCOSIM_CANNOT:
        pytest.skip(f"libcosim cannot express {name}: {LIBCOSIM_CANNOT[name]}")
    step, outputs, _ = system(name)
    ns = round(step * 1e9)
    assert abs(ns - step * 1e9) < 1e-6, step
    r = subprocess.run([sys.executable, "-c", LIBCOSIM_RUN, str(ssp_path(name)), str(ns), str(STEPS),
                        json.dumps(outputs)], capture_output=True, text=True)
    assert r.returncode == 0, f"libcosim on {name} failed (exit {r.returncode}):\n{r.stderr[-2000:]}"
    theirs = np.asarray(json.loads(r.stdout))
    mine = ours(tmp_path, name, step, "jacobi")
    for j, col in enumerate(outputs):
        a, b = np.asarray(mine[col][1:]), theirs[:, j]
        scale = max(np.max(np.abs(a)), 1e-300)
        assert np.max(np.abs(a - b)) <= 1e-12 * scale, f"{name}: {col} differs by {np.max(np.abs(a - b)):e}"


# Measured, cause not found: FMPy's run of Spindle.ssp leaves our Jacobi run by 0.176 N in
# process.force_x over the first 200 steps, 11.7 times our own Jacobi/Gauss-Seidel difference
# (0.0150 N), where the other systems stay within 10 times. FMPy starts every connection at 0
# instead of the outputs at t0; whether that start alone explains the spindle's larger excursion is
# not shown. strict: the test fails once it passes, so the mark goes.
FMPY_DIFFERS = {"Spindle.ssp": "process.force_x 0.176 N from ours, 11.7x the coupling-order difference; cause not found"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=FMPY_DIFFERS[n]))
                                  if n in FMPY_DIFFERS else n for n in SYSTEMS])
def test_every_shipped_ssp_runs_in_fmpy_simulate_ssp_within_the_coupling_order(tmp_path, name):
    step, outputs, bindings = system(name)
    theirs = simulate_ssp(str(ssp_path(name)), stop_time=STEPS * step, step_size=step,
                          parameter_set=SimpleNamespace(parameters=bindings))
    jacobi, seidel = ours(tmp_path, name, step, "jacobi"), ours(tmp_path, name, step, "gauss-seidel")
    n = min(len(theirs), STEPS)
    moving = 0
    for col in outputs:
        a, b = np.asarray(jacobi[col][1:n + 1]), np.asarray(theirs[col][:n], dtype=float)
        coupling = np.max(np.abs(a - np.asarray(seidel[col][1:n + 1])))
        scale = np.max(np.abs(a))
        worst = np.max(np.abs(a - b))
        assert worst <= 10 * coupling + 1e-12 * scale, (
            f"{name}: {col}: FMPy differs by {worst:e}, our Jacobi and Gauss-Seidel by {coupling:e}")
        moving += scale > 0
    assert moving > 0, f"{name}: every output is zero (vacuous)"
