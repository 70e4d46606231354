"""The export layer's XML passes FMPy's schema and rule validation.

`cargo test -p fmi2-export` writes the description of its test-only model to
target/fmu-test/; the product FMUs are validated in test_fmus.py.
"""
import pathlib

import pytest
from fmpy.model_description import read_model_description
from fmpy.validation import validate_model_description

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_test_model_description_is_valid():
    path = ROOT / "target" / "fmu-test" / "Oscillator.modelDescription.xml"
    if not path.exists():
        pytest.fail(f"{path} missing: run `cargo test -p fmi2-export` first")
    md = read_model_description(str(path), validate=True)
    assert validate_model_description(md) == []
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    assert [u.variable.name for u in md.outputs] == outputs
    # outputs without direct feedthrough declare an empty dependency list
    assert all(u.dependencies == [] for u in md.outputs)
