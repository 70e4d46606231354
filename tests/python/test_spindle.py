"""Seed 002's shipped Spindle.ssp (MillingProcess + SpindleStructure + LinearController with
the printed Section 6.1 gains): FMPy reads it with schema validation, and an FMPy loop in the
declared Gauss-Seidel order (controller, process, spindle; step 1 us) agrees with the Rust master
(``cosim run Spindle.ssp``) to 1e-12 on every recorded column. 3 mm is above the open-loop
boundary (1.57 mm) and below the closed-loop one (3.59 mm at 37800 rpm)."""
import numpy as np
from fmpy.ssp.ssd import read_ssd

from fmpy_closed_loop import System
from test_cross_check import assert_close, run_rust, ssp_path

STOP = 0.005
RECORD = ["spindle.tool_x", "spindle.tool_y", "spindle.actuator_x", "process.force_x", "process.force_y",
          "controller.F_x", "controller.F_y", "controller.w_x"]


def run_both(tmp_path, overrides, name, check_system=lambda system: None):
    """Spindle.ssp with `overrides` in the Rust master and in the FMPy loop: every recorded
    column agrees to 1e-12, and the run is not vacuous (the tool moves, the controller acts)."""
    sets = sum((["--set", f"{k}={v}"] for k, v in overrides.items()), [])
    rust = run_rust(tmp_path, ["--stop-time", str(STOP), "--record", ",".join(RECORD)] + sets, name,
                    ssp="Spindle.ssp")
    system = System(ssp_path("Spindle.ssp"))
    try:
        check_system(system)
        times, py = system.run(STOP, overrides, RECORD)
    finally:
        system.close()
    assert len(rust["time"]) == len(times) == round(STOP / 1e-6) + 1
    for col in RECORD:
        assert_close(col, rust[col], py[col])
    assert np.std(py["spindle.tool_x"]) > 0
    assert np.max(np.abs(py["controller.F_x"])) > 0


def test_spindle_ssp_rust_master_matches_an_fmpy_loop_to_1e_12(tmp_path):
    ssd = read_ssd(str(ssp_path("Spindle.ssp")), validate=True)
    assert sorted(e.name for e in ssd.system.elements) == ["controller", "process", "spindle"]

    def check(system):
        assert [c.name for c in system.sequence] == ["controller", "process", "spindle"]
        assert system.step == 1e-6
        bound = dict(next(c for c in system.components if c.name == "controller").bindings)
        assert float(bound["Dc[1,1]"]) == 697159.9 and float(bound["Dc[2,1]"]) == -1071058.0, bound

    run_both(tmp_path, {"process.axial_depth": "0.003", "process.spindle_speed": "37800",
                        "controller.spindle_speed": "37800"}, "spindle", check)


def test_a_shipped_design_runs_the_same_in_fmpy_and_the_rust_master(tmp_path):
    """The Table II n_c = 2 design (``designs/table2_nc2.ssv``, a dynamic 2x2 controller with
    the Pyragas difference) with the x_F = 0.744 power-law process and a 10 ms entry ramp: the
    design's parameters are read from the shipped SSV (not restated here), set by name in both
    masters, and every recorded column agrees to 1e-12."""
    import xml.etree.ElementTree as ET
    ssv = ssp_path("Spindle.ssp").with_name("designs") / "table2_nc2.ssv"
    ns = {"ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues"}
    overrides = {}
    for p in ET.parse(ssv).getroot().iterfind(".//ssv:Parameter", ns):
        value = next(iter(p))
        overrides["controller." + p.get("name")] = value.get("value")
    assert overrides["controller.n_c"] == "2" and "controller.Ac[1,2]" in overrides, overrides
    scale = 1000.0 ** 1.744
    overrides.update({"process.exponent": "0.744", "process.kt": repr(462.0 * scale),
                      "process.kr": repr(38.6 * scale), "process.axial_depth": "0.002",
                      "process.depth_ramp_time": "0.002", "process.spindle_speed": "36000",
                      "controller.spindle_speed": "36000"})
    run_both(tmp_path, overrides, "design")
