"""chatter_fmu: run FMI 2.0 systems (SSP, SSD or a single FMU) with the project's Rust master,
and plan/run/collect its studies as independent cases, from Python.

    import chatter_fmu
    sys = chatter_fmu.System("target/fmu/ClosedLoop.ssp")
    res = sys.simulate(stop_time=0.1, parameters={"plant.seed": 3}, record=["plant.x", "controller.u"])
    res["time"], res["plant.x"]          # numpy arrays

Simulations release the GIL. Errors of the master (a missing FMU, a bad parameter, an FMU that
refuses a step) raise ``ChatterError`` with the master's message.
"""
from __future__ import annotations

import os
from typing import Dict, Iterable, Optional, Sequence, Tuple

import numpy as np

from ._native import ChatterError, System as _System, case_ids, collect, plan_main_job as _plan_main_job, run_cases

__all__ = ["ChatterError", "System", "plan_main_job", "run_cases", "collect", "case_ids"]


class System:
    """A system of FMUs: ``.ssp``, ``.ssd`` (its FMUs in ``fmu_dir``) or one ``.fmu``."""

    def __init__(self, path: os.PathLike | str, fmu_dir: Optional[os.PathLike | str] = None):
        self._native = _System(os.fspath(path), None if fmu_dir is None else os.fspath(fmu_dir))

    def components(self) -> list[Tuple[str, str]]:
        """``(name, source)`` of every component."""
        return self._native.components()

    def simulate(self, stop_time: Optional[float] = None, step: Optional[float] = None,
                 start_time: Optional[float] = None, parameters: Optional[Dict[str, object]] = None,
                 record: Optional[Sequence[str]] = None,
                 output_interval: Optional[float] = None) -> Dict[str, np.ndarray]:
        """Run from start to stop (defaults: the system's) and return ``{"time": …, name: …}``.

        ``parameters`` maps ``component.variable`` to a value (bool, int, float, or str for
        enumeration items and text); ``record`` lists the recorded variables (default: every
        output), sampled every ``output_interval`` (default: every step).
        """
        names, time, values = self._native.simulate(stop_time, step, start_time, parameters,
                                                    None if record is None else list(record), output_interval)
        t = np.frombuffer(time, dtype=np.float64).copy()
        v = np.frombuffer(values, dtype=np.float64).reshape(len(t), len(names)) if names else np.empty((len(t), 0))
        out = {"time": t}
        for i, n in enumerate(names):
            out[n] = v[:, i].copy()
        return out


def plan_main_job(out: os.PathLike | str, fmu_dir: os.PathLike | str, seeds: Iterable[int] = range(1, 11),
                  cases: Sequence[Tuple[str, str]] = (("Open loop", "off"), ("PID", "pid"), ("FOPID", "fopid"),
                                                      ("ADRC-FOPID", "adrc_fopid")),
                  stop_time: Optional[float] = None, step: Optional[float] = None, csv_interval: float = 1e-3,
                  overrides: Sequence[str] = (), system: Optional[os.PathLike | str] = None) -> int:
    """Plan the main job (Table 5) into ``out`` as independent cases; returns their number.
    The same study as ``chatter plan main-job``."""
    return _plan_main_job(os.fspath(out), os.fspath(fmu_dir), list(seeds), [tuple(c) for c in cases], stop_time,
                          step, csv_interval, list(overrides), None if system is None else os.fspath(system))
