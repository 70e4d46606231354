"""Cross-check of the Rust master against FMPy on the same two FMUs.

* ``fmpy_closed_loop.System`` drives MillingPlant + ChatterController with
  FMPy's FMU2Slave in a Python loop, in the order declared in ClosedLoop.ssd
  (Gauss-Seidel: controller, then plant; step 10 us), for 0.2 s; the Rust
  master (``cosim run target/fmu/ClosedLoop.ssp``) runs the same system and
  writes its CSV. Every recorded column must agree to 1e-12 relative (they
  are in fact bit-identical: same binaries, same call sequence).
* FMPy reads the shipped ClosedLoop.ssp (validating SystemStructure.ssd
  against the SSP 1.0 schema FMPy ships) and its own SSP master
  (``fmpy.ssp.simulation.simulate_ssp``, Jacobi order) runs it; the Rust
  master in Jacobi order gives the same numbers.
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssd
from fmpy.ssp.simulation import simulate_ssp

from conftest import ROOT, fmu_path
from fmpy_closed_loop import System

STOP = 0.2
RECORD = ["plant.x", "plant.v", "plant.cutting_force", "plant.actuator_force", "plant.u",
          "controller.y", "controller.u", "controller.e", "controller.z1", "controller.z2", "controller.z3"]


def cosim():
    """The cosim binary of this workspace (built here if needed), or $COSIM."""
    if "COSIM" in os.environ:
        return pathlib.Path(os.environ["COSIM"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "fmi-master", "--bin", "cosim"], cwd=ROOT, check=True)
    return target / "release" / "cosim"


def ssp_path(name="ClosedLoop.ssp"):
    path = fmu_path("MillingPlant").with_name(name)
    if not path.exists():
        pytest.fail(f"{path} is missing: run `cargo run --release -p packaging` first")
    return path


def run_rust(tmp_path, args, name, ssp="ClosedLoop.ssp"):
    out = tmp_path / f"{name}.csv"
    cmd = [str(cosim()), "run", str(ssp_path(ssp)), "--quiet", "-o", str(out)] + args
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}\n{r.stderr}"
    data = np.genfromtxt(out, delimiter=",", names=True, deletechars="")
    return data


def assert_close(name, rust, py):
    rust, py = np.asarray(rust), np.asarray(py)
    assert rust.shape == py.shape, name
    scale = np.maximum(np.abs(rust), np.abs(py))
    bad = np.abs(rust - py) > 1e-12 * scale
    assert not bad.any(), (f"{name}: {bad.sum()} of {len(rust)} samples differ by more than 1e-12 relative; "
                           f"first at index {np.argmax(bad)}: rust {rust[np.argmax(bad)]!r} vs FMPy {py[np.argmax(bad)]!r}")


@pytest.mark.parametrize("structure", ["off", "pid", "fopid", "adrc_fopid"])
def test_rust_master_matches_an_fmpy_loop_to_1e_12(tmp_path, structure):
    overrides = {"controller.structure": structure, "plant.seed": "3"}
    sets = sum((["--set", f"{k}={v}"] for k, v in overrides.items()), [])
    rust = run_rust(tmp_path, ["--stop-time", str(STOP), "--record", ",".join(RECORD)] + sets, structure)
    system = System(ssp_path())
    try:
        assert [c.name for c in system.sequence] == ["controller", "plant"]
        assert system.step == 1e-5
        times, py = system.run(STOP, overrides, RECORD)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / 1e-5) + 1
    assert np.array_equal(rust["time"], np.array(times)), "communication points t0 + n*h"
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    # The test is not vacuous: the tip moves, and (closed loop) the controller acts.
    assert np.std(py["plant.x"]) > 0
    if structure != "off":
        assert np.max(np.abs(py["controller.u"])) > 0


def test_fmpy_reads_the_shipped_ssp_with_schema_validation_and_runs_it(tmp_path):
    ssd = read_ssd(str(ssp_path()), validate=True)
    names = sorted(e.name for e in ssd.system.elements)
    assert names == ["controller", "plant"]
    assert len(ssd.system.connections) == 2
    # FMPy's own SSP master: Jacobi order, inputs start at 0, time accumulated (t += h).
    h, stop = 1e-5, 0.01
    fmpy_result = simulate_ssp(str(ssp_path()), stop_time=stop, step_size=h)
    rust = run_rust(tmp_path, ["--stop-time", str(stop), "--order", "jacobi", "--record", "plant.x,controller.u"],
                    "jacobi")
    n = round(stop / h)
    # FMPy's row k holds the outputs after step k+1; the CSV's row k+1.
    for ours, theirs in [("plant.x", "plant.x"), ("controller.u", "controller.u")]:
        assert_close(ours, rust[ours][1:n + 1], fmpy_result[theirs][:n])


def test_table2_ssp_binds_the_paper_gains_and_both_masters_apply_them(tmp_path):
    """ClosedLoopTable2.ssp: schema-valid, its inline parameter bindings (the paper's Table 2
    gains) are applied by both masters alike, and they change the result (the FMU defaults
    are the PSO-tuned gains)."""
    ssd = read_ssd(str(ssp_path("ClosedLoopTable2.ssp")), validate=True)
    controller = next(e for e in ssd.system.elements if e.name == "controller")
    assert controller.parameterBindings, "no parameter bindings on the controller"
    overrides = {"controller.structure": "adrc_fopid", "plant.seed": "3"}
    sets = sum((["--set", f"{k}={v}"] for k, v in overrides.items()), [])
    args = ["--stop-time", str(STOP), "--record", ",".join(RECORD)] + sets
    rust = run_rust(tmp_path, args, "table2", ssp="ClosedLoopTable2.ssp")
    system = System(ssp_path("ClosedLoopTable2.ssp"))
    try:
        bound = dict(next(c for c in system.components if c.name == "controller").bindings)
        assert float(bound["adrc.omega_o"]) == 2699.3 and float(bound["pid.kp"]) == 2300.0, bound
        times, py = system.run(STOP, overrides, RECORD)
    finally:
        system.close()
    for name in RECORD:
        assert_close(name, rust[name], py[name])
    tuned = run_rust(tmp_path, args, "tuned")
    assert not np.allclose(tuned["controller.u"], rust["controller.u"]), "the bindings had no effect"


def test_benchmark_dvf_rust_master_matches_an_fmpy_loop_to_1e_12(tmp_path):
    """Seed 000's Table 8 benchmark (Benchmark.ssp: MillingPlant bound to the Ozsoy plant,
    LinearController bound to the calibrated DVF) in the Rust master and in the FMPy loop, with
    cutting, noise and drift as bound: every recorded column agrees to 1e-12."""
    record = ["plant.x", "plant.u", "plant.actuator_force", "controller.v_x", "controller.F_x", "controller.w_x"]
    overrides = {"plant.seed": "5"}
    sets = sum((["--set", f"{k}={v}"] for k, v in overrides.items()), [])
    rust = run_rust(tmp_path, ["--stop-time", str(STOP), "--record", ",".join(record)] + sets, "benchmark",
                    ssp="Benchmark.ssp")
    system = System(ssp_path("Benchmark.ssp"))
    try:
        assert [c.name for c in system.sequence] == ["controller", "plant"]
        times, py = system.run(STOP, overrides, record)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / 1e-5) + 1
    for name in record:
        assert_close(name, rust[name], py[name])
    assert np.abs(np.asarray(py["controller.F_x"])).max() > 0.1, "the DVF acts"
