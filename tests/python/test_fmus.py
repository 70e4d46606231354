"""FMPy accepts every product FMU (`product`: each name in packaging's products.json):
validation without problems, co-simulation only, declared units, one second with defaults.
The last two tests check what the plant and the controller do."""
import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import fmu_path, products


def test_the_product_list_names_the_shipped_fmus():
    names = products()
    assert len(set(names)) == len(names), names
    assert {"MillingPlant", "ChatterController"} <= set(names)


def test_fmpy_validate_reports_no_problems(product):
    problems = validate_fmu(str(fmu_path(product)))
    assert problems == [], "\n".join(problems)


def test_model_description_is_co_simulation_with_units(product):
    md = read_model_description(str(fmu_path(product)))
    assert md.coSimulation is not None and md.coSimulation.modelIdentifier == product
    assert md.modelExchange is None
    units = {u.name for u in md.unitDefinitions}
    assert units, "UnitDefinitions must declare the SI units used"
    for v in md.modelVariables:
        if v.type == "Real":
            # issue 31: 203 Real variables had no unit; dimensionless ones say "1"
            assert v.unit is not None, f"{v.name} has no unit"
            assert v.unit in units, f"{v.name}: unit {v.unit} not declared"
    assert md.copyright and md.license and md.generationDateAndTime, "optional attributes tools show"


def test_every_fmu_carries_its_model_png(product):
    import zipfile
    with zipfile.ZipFile(fmu_path(product)) as z:
        png = z.read("model.png")
    assert png.startswith(b"\x89PNG\r\n\x1a\n")


def test_simulates_one_second_with_defaults_to_finite_outputs(product):
    path = str(fmu_path(product))
    result = simulate_fmu(path, stop_time=1.0, output_interval=1e-3, fmi_type="CoSimulation")
    assert result["time"][-1] == pytest.approx(1.0)
    md = read_model_description(path)
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type in ("Real", "Integer")]
    assert outputs, f"{product} has no Real or Integer output"
    for name in outputs:
        assert np.all(np.isfinite(result[name])), name


def test_plant_simulates_one_second_with_defaults(plant_fmu):
    result = simulate_fmu(str(plant_fmu), stop_time=1.0, output_interval=1e-4, fmi_type="CoSimulation")
    md = read_model_description(str(plant_fmu))
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    # the default scenario cuts and is disturbed: the tip moves
    displacement = [n for n in outputs if n in ("x", "tip.x", "workpiece.x", "displacement")]
    assert displacement, f"no tip displacement among outputs {outputs}"
    x = result[displacement[0]]
    assert np.std(x) > 1e-9


def test_controller_simulates_with_an_input_signal(controller_fmu):
    t = np.arange(0.0, 0.05 + 1e-12, 1e-4)
    signal = np.array(list(zip(t, 1e-6 * np.sin(2 * np.pi * 143.0 * t))), dtype=[("time", np.float64), ("y", np.float64)])
    result = simulate_fmu(
        str(controller_fmu), stop_time=0.05, output_interval=1e-4, input=signal, fmi_type="CoSimulation"
    )
    u = result["u"]
    assert np.all(np.isfinite(u))
    md = read_model_description(str(controller_fmu))
    u_max = next(float(v.start) for v in md.modelVariables if v.name == "u_max")
    assert np.max(np.abs(u)) <= u_max
    assert np.max(np.abs(u[len(u) // 2 :])) > 0.0, "the default controller acts on a 1 um chatter-band input"
