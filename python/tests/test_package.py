"""The installed wheel: the closed loop from Python equals the Rust master (`cosim run`) to
1e-12, errors carry the master's message, and the study API matches `chatter`."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import chatter_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = pathlib.Path(os.environ.get("FMU_DIR", ROOT / "target" / "fmu"))
COSIM = ROOT / "target" / "release" / "cosim"
CHATTER = ROOT / "target" / "release" / "chatter"


def test_the_closed_loop_equals_the_rust_master(tmp_path):
    ssp = FMU_DIR / "ClosedLoop.ssp"
    res = chatter_fmu.System(ssp).simulate(stop_time=0.05, parameters={"plant.seed": 3},
                                           record=["plant.x", "controller.u"])
    assert res["time"].shape == res["plant.x"].shape and len(res["time"]) == 5001
    csv = tmp_path / "run.csv"
    r = subprocess.run([str(COSIM), "run", str(ssp), "--stop-time", "0.05", "--set", "plant.seed=3",
                        "--record", "plant.x,controller.u", "--output", str(csv)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    ref = np.genfromtxt(csv, delimiter=",", names=True)
    cols = ref.dtype.names
    np.testing.assert_allclose(res["time"], ref[cols[0]], rtol=0, atol=1e-12)
    for name, col in (("plant.x", 1), ("controller.u", 2)):
        scale = max(1.0, float(np.max(np.abs(ref[cols[col]]))))
        assert np.max(np.abs(res[name] - ref[cols[col]])) <= 1e-12 * scale, name
    assert np.std(res["plant.x"]) > 0


def test_a_bad_fmu_path_raises_with_the_master_message(tmp_path):
    with pytest.raises(chatter_fmu.ChatterError, match=r"cannot open FMU .*nowhere\.fmu: no such file"):
        chatter_fmu.System(tmp_path / "nowhere.fmu").simulate(stop_time=0.01)
    with pytest.raises(chatter_fmu.ChatterError, match="nowhere.ssp"):
        chatter_fmu.System(tmp_path / "nowhere.ssp")


def test_an_unknown_parameter_raises(tmp_path):
    sys = chatter_fmu.System(FMU_DIR / "ClosedLoop.ssp")
    with pytest.raises(chatter_fmu.ChatterError, match="ghost"):
        sys.simulate(stop_time=0.001, parameters={"plant.ghost": 1.0})


def test_the_study_api_matches_chatter(tmp_path):
    args = dict(seeds=[1, 2], cases=[("Open loop", "off"), ("FOPID", "fopid")], stop_time=0.05)
    a, b = tmp_path / "py", tmp_path / "cli"
    assert chatter_fmu.plan_main_job(a, FMU_DIR, **args) == 4
    ran, skipped = chatter_fmu.run_cases(a, shard="1/2")
    assert len(ran) == 2 and not skipped
    ran, skipped = chatter_fmu.run_cases(a)
    assert len(ran) == 2 and len(skipped) == 2
    table = chatter_fmu.collect(a)
    assert "FOPID" in table
    r = subprocess.run([str(CHATTER), "main-job", "--out", str(b), "--seeds", "2", "--stop-time", "0.05",
                        "--cases", "Open loop=off,FOPID=fopid"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (a / "table5.md").read_bytes() == (b / "table5.md").read_bytes()
    assert (a / "runs_summary.csv").read_bytes() == (b / "runs_summary.csv").read_bytes()
