"""Build the example system "our MillingProcess on your structure" as an SSP archive.

    python make_ssp.py OUT_DIR [--fmu-dir target/fmu] [--structure PATH/Yours.fmu]

Without ``--structure`` the example structure ``TwoModeXY.py`` beside this file is built with
pythonfmu (``pip install pythonfmu``); with it, your own FMU goes in as
``resources/TwoModeXY.fmu`` (it must have the inputs ``tool_force_x/y`` [N] and the outputs
``tool_x/y`` [m], and ``actuator_force_x/y`` [N] for our active damper, or edit the
connections of ``ThirdPartyStructure.ssd``). Our MillingProcess, InertialActuator and
ChatterController FMUs come from ``--fmu-dir``. The SSP runs in our
master (``cosim run``), in FMPy and in libcosim (``CosimExecution.from_ssp_file``).
"""
import argparse
import subprocess
import sys
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


OURS = ("MillingProcess", "InertialActuator", "ChatterController")


def build(out_dir, fmu_dir, structure=None):
    """Write ``OUT_DIR/ThirdPartyStructure.ssp`` and return its path."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if structure is None:
        subprocess.run([sys.executable, "-m", "pythonfmu", "build", "-f", str(HERE / "TwoModeXY.py"),
                        "-d", str(out_dir)], check=True, capture_output=True)
        structure = out_dir / "TwoModeXY.fmu"
    ssp = out_dir / "ThirdPartyStructure.ssp"
    with zipfile.ZipFile(ssp, "w") as z:
        z.write(HERE / "ThirdPartyStructure.ssd", "SystemStructure.ssd")
        for name in OURS:
            z.write(Path(fmu_dir) / f"{name}.fmu", f"resources/{name}.fmu")
        z.write(structure, "resources/TwoModeXY.fmu")
    return ssp


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out_dir")
    ap.add_argument("--fmu-dir", default=str(HERE.parents[2] / "target" / "fmu"))
    ap.add_argument("--structure")
    a = ap.parse_args()
    print(build(a.out_dir, a.fmu_dir, a.structure))
