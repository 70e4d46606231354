"""Shared fixtures: where the packaged FMUs are (built by `cargo run --release -p packaging`)."""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = pathlib.Path(os.environ.get("FMU_DIR", ROOT / "target" / "fmu"))


def fmu_path(name: str) -> pathlib.Path:
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
