"""A user's machine from Python: the same answers as `chatter`, arrays out, errors that name the
field and the fix."""
import pathlib

import numpy as np
import pytest

import chatter_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
END_MILL = ROOT / "studies" / "machine" / "examples" / "end_mill.toml"


def test_from_file_and_from_dict_describe_the_same_machine():
    import tomllib
    m = chatter_fmu.Machine.from_file(END_MILL)
    d = chatter_fmu.Machine.from_dict(tomllib.loads(END_MILL.read_text()))
    assert m.summary() == d.summary()
    assert "| x[0] | 600.0 |" in m.summary()


def test_a_bad_machine_names_the_field_and_the_fix():
    import tomllib
    t = tomllib.loads(END_MILL.read_text())
    t["material"]["kt"] = 800
    with pytest.raises(chatter_fmu.ChatterError, match=r'material.kt: .*did you mean "800 N/mm\^2"'):
        chatter_fmu.Machine.from_dict(t)


def test_lobes_closed_loop_and_validation_in_numpy():
    m = chatter_fmu.Machine.from_file(END_MILL)
    lobes = m.lobes(points=6, rpm=(10000.0, 16000.0))
    assert lobes["rpm"].shape == lobes["sd"].shape == (6,)
    # at 10,000 rpm the converged time-periodic boundary (3.879 mm; SD m = 40: 3.877) is the
    # boundary the FMUs confirm
    assert abs(lobes["sd"][0] - 3.877e-3) < 0.01e-3
    assert lobes["zero_order"][0] < lobes["sd"][0]
    assert "zero-order" in lobes["report"]
    v = m.validate(16000.0)
    assert v["confirmed"] and v["kind"] == "hopf", v
    cl = m.closed_loop_lobes("pid", points=4)
    assert np.all(cl["usable"] <= cl["stability"]) and cl["label"].startswith("pid (shipped")


def test_simulate_through_the_fmus():
    m = chatter_fmu.Machine.from_file(END_MILL)
    run = m.simulate(rpm=10000.0, depth_mm=2.0, stop_time=0.02, record=["structure.tool_x", "process.force_x"])
    assert run["time"].shape == run["structure.tool_x"].shape and len(run["time"]) == 2001
    assert np.max(np.abs(run["process.force_x"])) > 10.0


def test_tune_returns_a_parameter_set(tmp_path):
    m = chatter_fmu.Machine.from_file(END_MILL)
    res = m.tune(["pid"], runs=1, particles=6, iterations=3)
    assert set(res) == {"pid"} and "<ssv:ParameterSet" in res["pid"]["ssv"] and res["pid"]["b_min"] > 0
    ssp = tmp_path / "mine.ssp"
    m.write_ssp(ssp, rpm=10000.0, depth_mm=2.0)
    assert ssp.is_file()
    with pytest.raises(chatter_fmu.ChatterError, match="exists"):
        m.write_ssp(ssp, rpm=10000.0, depth_mm=2.0)
