"""The Rust master's closed loop, rewritten in Python on FMPy's FMU2Slave API.

Reads the system from an SSP archive (``target/fmu/ClosedLoop.ssp``): its
components, connections and this project's master annotation (step size,
Gauss-Seidel sequence), then runs the same call sequence as
``fmi-master/src/engine/`` (``assembly.rs``, ``mod.rs``):

1. per component, in document order: instantiate (loggingOn), setupExperiment(t0, stop),
   apply the SSD's inline parameter bindings, then the ``component.variable=value`` overrides;
2. enterInitializationMode for all, then exitInitializationMode for all;
3. read every connected output, set every connected input (document order);
4. for n = 0..N-1, t_n = t0 + n*h: for each component of the sequence, set its
   inputs from the latest outputs, doStep(t_n, h), read its outputs.

Used by ``test_cross_check.py`` (results compared with the Rust master's CSV)
and by the throughput benchmark ``fmi-master/benches/closed_loop.rs``, which
runs ``python fmpy_closed_loop.py --bench`` and prints steps/s as JSON.
"""
import argparse
import json
import shutil
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
SSC = "{http://ssp-standard.org/SSP1/SystemStructureCommon}"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
MASTER = "{urn:chatter-fmu:master:1}"


class Component:
    def __init__(self, name, fmu_path):
        self.name = name
        self.md = read_model_description(str(fmu_path))
        self.unzipdir = extract(str(fmu_path))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipdir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.out_vrs = []  # connected outputs, read after each step
        self.out = []
        self.in_vrs = []  # connected inputs
        self.in_src = []  # (component, index into its out list)

    def set_value(self, var_name, text):
        v = self.vars[var_name]
        vr = [v.valueReference]
        if v.type == "Real":
            self.fmu.setReal(vr, [float(text)])
        elif v.type == "Integer":
            self.fmu.setInteger(vr, [int(text)])
        elif v.type == "Enumeration":
            items = {item.name: int(item.value) for item in v.declaredType.items}
            self.fmu.setInteger(vr, [items[text] if text in items else int(text)])
        elif v.type == "Boolean":
            self.fmu.setBoolean(vr, [text in ("true", "1", "on")])
        else:
            self.fmu.setString(vr, [text])

    def read_outputs(self):
        if self.out_vrs:
            self.out = self.fmu.getReal(self.out_vrs)

    def write_inputs(self):
        if self.in_vrs:
            self.fmu.setReal(self.in_vrs, [src.out[i] for src, i in self.in_src])


class System:
    """The closed loop of an SSP archive, on FMPy."""

    def __init__(self, ssp_path):
        self.tmp = tempfile.mkdtemp(prefix="fmpy-closed-loop-")
        with zipfile.ZipFile(ssp_path) as z:
            z.extractall(self.tmp)
        root = ET.parse(Path(self.tmp) / "SystemStructure.ssd").getroot()
        system = root.find(f"{SSD}System")
        self.components = []
        for el in system.find(f"{SSD}Elements").findall(f"{SSD}Component"):
            c = Component(el.get("name"), Path(self.tmp) / el.get("source"))
            # inline parameter bindings (ssv:Parameter with one value element)
            path = f"{SSD}ParameterBindings/{SSD}ParameterBinding/{SSD}ParameterValues/{SSV}ParameterSet/{SSV}Parameters/{SSV}Parameter"
            c.bindings = [(p.get("name"), list(p)[0].get("value")) for p in el.findall(path)]
            self.components.append(c)
        by_name = {c.name: c for c in self.components}
        for conn in system.find(f"{SSD}Connections").findall(f"{SSD}Connection"):
            src, dst = by_name[conn.get("startElement")], by_name[conn.get("endElement")]
            sv, dv = src.vars[conn.get("startConnector")], dst.vars[conn.get("endConnector")]
            assert sv.type == dv.type == "Real", "this script connects Real variables only"
            if sv.valueReference not in src.out_vrs:
                src.out_vrs.append(sv.valueReference)
            dst.in_vrs.append(dv.valueReference)
            dst.in_src.append((src, src.out_vrs.index(sv.valueReference)))
        de = root.find(f"{SSD}DefaultExperiment")
        self.stop_time = float(de.get("stopTime"))
        settings = de.find(f"{SSD}Annotations/{SSC}Annotation/{MASTER}Settings")
        self.step = float(settings.get("stepSize"))
        assert settings.get("order", "gauss-seidel") == "gauss-seidel"
        self.sequence = [by_name[n] for n in settings.get("sequence").split()]

    def initialize(self, stop_time, overrides=None):
        """Instantiate, set parameters, initialize; consistent inputs at t0."""
        overrides = overrides or {}
        for c in self.components:
            c.fmu.instantiate(loggingOn=True)
            c.fmu.setupExperiment(startTime=0.0, stopTime=stop_time)
            for var, value in c.bindings:
                c.set_value(var, value)
            for target, value in overrides.items():
                comp, var = target.split(".", 1)
                if comp == c.name:
                    c.set_value(var, str(value))
        for c in self.components:
            c.fmu.enterInitializationMode()
        for c in self.components:
            c.fmu.exitInitializationMode()
        for c in self.components:
            c.read_outputs()
        for c in self.components:
            c.write_inputs()

    def run(self, stop_time, overrides=None, record=()):
        """Run to stop_time; returns (times, {name: values}) sampled at every step."""
        self.initialize(stop_time, overrides)
        by_name = {c.name: c for c in self.components}
        rec = [(by_name[r.split(".", 1)[0]], by_name[r.split(".", 1)[0]].vars[r.split(".", 1)[1]].valueReference)
               for r in record]
        values = {r: [] for r in record}

        def sample():
            for r, (c, vr) in zip(record, rec):
                values[r].append(c.fmu.getReal([vr])[0])

        h = self.step
        n_steps = round(stop_time / h)
        times = [0.0]
        sample()
        for n in range(n_steps):
            t = n * h
            for c in self.sequence:
                c.write_inputs()
                c.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
                c.read_outputs()
            times.append((n + 1) * h)
            sample()
        return times, values

    def bench(self, n_steps, overrides=None):
        """Steps per second of the bare loop (nothing recorded)."""
        self.initialize(n_steps * self.step, overrides)
        h = self.step
        seq = self.sequence
        began = time.perf_counter()
        for n in range(n_steps):
            t = n * h
            for c in seq:
                c.write_inputs()
                c.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
                c.read_outputs()
        return n_steps / (time.perf_counter() - began)

    def close(self):
        for c in self.components:
            try:
                c.fmu.terminate()
            finally:
                c.fmu.freeInstance()
            shutil.rmtree(c.unzipdir, ignore_errors=True)
        shutil.rmtree(self.tmp, ignore_errors=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("ssp", help="ClosedLoop.ssp")
    p.add_argument("--bench", action="store_true", help="print steps/s as JSON")
    p.add_argument("--steps", type=int, default=20000)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--set", action="append", default=[], help="component.variable=value")
    a = p.parse_args()
    overrides = dict(s.split("=", 1) for s in a.set)
    rates = []
    for _ in range(a.repeat):
        s = System(a.ssp)
        try:
            rates.append(s.bench(a.steps, overrides))
        finally:
            s.close()
    import fmpy
    json.dump({"steps": a.steps, "steps_per_s": max(rates), "all": rates, "fmpy": fmpy.__version__,
               "python": sys.version.split()[0]}, sys.stdout)
    print()


if __name__ == "__main__":
    main()
