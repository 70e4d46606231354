"""chatter_fmu: run FMI 2.0 systems (SSP, SSD or a single FMU) with the project's Rust master,
and plan/run/collect its studies as independent cases, from Python.

    import chatter_fmu
    m = chatter_fmu.Machine.from_file("studies/machine/examples/end_mill.toml")   # your own machine
    lobes = m.lobes(points=60)                      # zero-order, multi-frequency, semi-discretisation
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

from ._native import ChatterError, Machine as _Machine, System as _System, case_ids, collect, fit_frf as _fit_frf, plan_main_job as _plan_main_job, run_cases

__all__ = ["ChatterError", "Machine", "System", "fit_frf", "plan_main_job", "run_cases", "collect", "case_ids"]


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


def fit_frf(files: Sequence[os.PathLike | str], band: Optional[Tuple[float, float]] = None,
            max_order: int = 40) -> Dict[str, object]:
    """Fit modes to measured FRF files (CSV or UFF 58; xx and yy required), as ``chatter frf
    fit``: ``modes`` (a structured array: frequency_hz, damping, stiffness_n_per_m, mass_kg,
    shape_x, shape_y, complexity), ``stabilisation`` (order, frequency_hz, damping, stability),
    the ``report``, the machine file's ``structure_toml`` and the ``band`` fitted (Hz)."""
    import io
    modes, stab, report, structure, fitted_band = _fit_frf([os.fspath(f) for f in files], band, max_order)
    return {"modes": np.genfromtxt(io.StringIO(modes), delimiter=",", names=True, ndmin=1),
            "stabilisation": np.genfromtxt(io.StringIO(stab), delimiter=",", names=True, dtype=None, encoding="utf-8"),
            "report": report, "structure_toml": structure, "band": fitted_band}


def _f64(b: bytes) -> np.ndarray:
    return np.frombuffer(b, dtype=np.float64).copy()


class Machine:
    """A user's machine from a machine file (TOML, units on quantities; the docs' "Your own
    machine"), with every analysis the ``chatter`` command runs on it. Lengths are in m and
    speeds in rpm in the results; errors name the field and the fix (``ChatterError``)."""

    def __init__(self, native):
        self._native = native

    @classmethod
    def from_file(cls, path: os.PathLike | str) -> "Machine":
        """Read a machine file."""
        return cls(_Machine.from_file(os.fspath(path)))

    @classmethod
    def from_dict(cls, tables: dict, name: str = "<dict>") -> "Machine":
        """A machine from a mapping with the machine file's tables, e.g.
        ``{"version": 1, "tool": {"teeth": 3, "diameter": "12 mm"}, ...}``."""
        import json
        return cls(_Machine.from_json(json.dumps(tables), name))

    def summary(self) -> str:
        """What the file describes (modes, static stiffness, the cut), as ``chatter machine check``."""
        return self._native.summary()

    def lobes(self, points: int = 200, rpm: Optional[Tuple[float, float]] = None,
              sd_m: Optional[int] = None) -> Dict[str, object]:
        """Open-loop lobes at ``points`` speeds over ``rpm`` (default: the file's range) by the
        zero-order, multi-frequency and time-periodic methods (the last converged to 0.1 %, or
        the semi-discretisation of order ``sd_m``): arrays ``rpm``, ``zero_order``,
        ``multi_frequency``, ``sd`` (the time-periodic critical depths in m, inf where stable),
        ``sd_kind`` (hopf/flip), and the ``report`` saying where they disagree."""
        lo, hi = (None, None) if rpm is None else rpm
        s, zo, mf, sd, kinds, report = self._native.lobes(points, lo, hi, sd_m)
        return {"rpm": _f64(s), "zero_order": _f64(zo), "multi_frequency": _f64(mf), "sd": _f64(sd),
                "sd_kind": np.array(kinds), "report": report}

    def closed_loop_lobes(self, structure: Optional[str] = None, points: int = 200,
                          rpm: Optional[Tuple[float, float]] = None) -> Dict[str, object]:
        """Closed-loop lobes of the file's controller (or ``structure`` with the shipped gains):
        ``rpm``, ``stability`` and ``saturation`` (the depth at which the cut's own force drives
        the command to the actuator's limit), ``usable`` = their minimum, all in m."""
        lo, hi = (None, None) if rpm is None else rpm
        s, st, sat, label = self._native.closed_loop_lobes(structure, points, lo, hi)
        st, sat = _f64(st), _f64(sat)
        return {"rpm": _f64(s), "stability": st, "saturation": sat, "usable": np.minimum(st, sat), "label": label}

    def validate(self, rpm: float, sd_m: Optional[int] = None) -> Dict[str, object]:
        """The time-periodic boundary at ``rpm`` (converged, or the semi-discretisation of order
        ``sd_m``) run through the FMUs at 0.97 and 1.03 of it: ``boundary`` (m), ``kind``, the
        growth ratios ``below`` and ``above`` (< 1 decays)."""
        b, kind, below, above = self._native.validate(rpm, sd_m)
        return {"rpm": rpm, "boundary": b, "kind": kind, "below": below, "above": above,
                "confirmed": below < 1.0 < above}

    def simulate(self, rpm: float, depth_mm: float, stop_time: float = 0.2,
                 record: Optional[Sequence[str]] = None) -> Dict[str, np.ndarray]:
        """Run the machine's FMUs (MillingProcess + ModalStructure [+ actuator + controller]) at
        ``rpm`` and ``depth_mm`` in the Rust master: ``{"time": …, "structure.tool_x": …}``."""
        names, time, values = self._native.simulate(rpm, depth_mm * 1e-3, stop_time,
                                                    None if record is None else list(record))
        t = _f64(time)
        v = _f64(values).reshape(len(t), len(names)) if names else np.empty((len(t), 0))
        out = {"time": t}
        for i, n in enumerate(names):
            out[n] = v[:, i].copy()
        return out

    def tune(self, structures: Sequence[str] = ("pid", "fopid", "adrc_fopid"), runs: int = 10,
             particles: int = 40, iterations: int = 60, seed: int = 1) -> Dict[str, Dict[str, object]]:
        """Tune each controller structure for this machine (``chatter tune --machine``): per
        structure its ``gains``, closed-loop ``b_min`` (m) at ``rpm``, the fresh-seed saturation
        check ``fresh_passed`` (of 10) and the ``ssv`` parameter set for ChatterController."""
        res = self._native.tune(list(structures), runs, particles, iterations, seed)
        return {s: {"gains": np.array(g), "b_min": b, "rpm": r, "fresh_passed": p, "ssv": ssv}
                for (s, g, b, r, p, ssv) in res}

    def measured_lobes(self, points: int = 200, rpm: Optional[Tuple[float, float]] = None) -> Dict[str, object]:
        """Zero-order lobes on the file's measured FRFs (``[structure] frf``, no fit) and on its
        modes over the same band: ``rpm``, ``measured``, ``modal`` (m; empty without modes),
        and the ``report`` with their difference."""
        lo, hi = (None, None) if rpm is None else rpm
        s, data, modal, report = self._native.measured_lobes(points, lo, hi)
        return {"rpm": _f64(s), "measured": _f64(data), "modal": _f64(modal), "report": report}

    def tap_test(self, path: os.PathLike | str, noise: float = 0.05, seed: int = 1, resolution: float = 1.0,
                 max_hz: float = 5000.0, binary: bool = False) -> None:
        """Write a synthetic tap test of this machine's modes (``.csv`` or ``.uff``; refused if
        the file exists): FRFs every ``resolution`` Hz up to ``max_hz`` with relative complex
        ``noise`` (seeded), as ``chatter frf synth``."""
        self._native.tap_test(os.fspath(path), noise, seed, resolution, max_hz, binary)

    def write_ssp(self, path: os.PathLike | str, rpm: float, depth_mm: float, stop_time: float = 1.0) -> None:
        """Write the machine's system as an SSP (refused if the file exists)."""
        self._native.write_ssp(os.fspath(path), rpm, depth_mm * 1e-3, stop_time)
