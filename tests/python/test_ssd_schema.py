"""The master's SSD writer output is valid SSP 1.0 (the XSD files FMPy ships).

`cargo test -p ssp` writes target/ssd-test/Full.ssd (every construct the
writer emits) and `cargo test -p fmi-master` writes ClosedLoop.ssd (the
embedded default scenario); the shipped ClosedLoop.ssp is checked in
test_cross_check.py.
"""
import os
import pathlib

import pytest
from lxml import etree
from fmpy.ssp.ssd import validate_tree

from conftest import ROOT

TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))


@pytest.mark.parametrize("name", ["Full.ssd", "ClosedLoop.ssd"])
def test_written_ssd_validates_against_the_ssp_1_0_schema(name):
    path = TARGET / "ssd-test" / name
    if not path.exists():
        pytest.fail(f"{path} missing: run `cargo test -p ssp -p fmi-master` first")
    validate_tree(etree.parse(str(path)).getroot(), "SystemStructureDescription.xsd")
