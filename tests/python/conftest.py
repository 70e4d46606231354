"""Shared fixtures: where the packaged FMUs are (built by `cargo run --release -p packaging`).

`product` is parametrized over the model identifiers in `products.json`, which packaging
writes from its `PRODUCTS` list next to the FMUs: a product added there is checked by every
test that takes `product`, and a stale `.fmu` left in the folder is not.
"""
import json
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = pathlib.Path(os.environ.get("FMU_DIR", ROOT / "target" / "fmu"))
PRODUCT_LIST = FMU_DIR / "products.json"
MISSING = "products.json-missing"


def products() -> list:
    """The model identifiers of the shipped FMUs (packaging's PRODUCTS)."""
    if not PRODUCT_LIST.exists():
        return [MISSING]
    names = json.loads(PRODUCT_LIST.read_text())
    assert isinstance(names, list) and names and all(isinstance(n, str) for n in names), PRODUCT_LIST
    return names


def pytest_generate_tests(metafunc):
    if "product" in metafunc.fixturenames:
        metafunc.parametrize("product", products())


def fmu_path(name: str) -> pathlib.Path:
    if name == MISSING:
        pytest.fail(f"{PRODUCT_LIST} is missing: run `cargo run --release -p packaging` first")
    path = FMU_DIR / f"{name}.fmu"
    if not path.exists():
        pytest.fail(f"{path} is missing: run `cargo run --release -p packaging` first")
    return path


@pytest.fixture
def plant_fmu() -> pathlib.Path:
    return fmu_path("MillingPlant")


@pytest.fixture
def controller_fmu() -> pathlib.Path:
    return fmu_path("ChatterController")
