"""Measured FRFs against third-party tools: UFF 58 files we write are read by `pyuff` (ASCII and
binary) and files `pyuff` writes are read by `chatter frf` (ASCII and binary); the modal fit of a
synthetic tap test beside `pyEMA`'s (sdypy-EMA: LSCF poles + LSFD constants) on the same data.

`pytest -s tests/python/test_frf.py -k pyema` prints the comparison table of the docs."""
import subprocess

import numpy as np
import pytest
import pyuff

from conftest import ROOT

CHATTER = ROOT / "target" / "release" / "chatter"
MACHINE = ROOT / "studies" / "machine" / "examples" / "end_mill.toml"
TWO_MODES = ROOT / "studies" / "machine" / "examples" / "two_modes.toml"
# (frequency Hz, damping, stiffness N/m, direction 0 = x, 1 = y)
TRUTH = {"two modes": [(600.0, 0.03, 2e7, 0), (650.0, 0.035, 2.5e7, 1)],
         "end mill": [(600.0, 0.03, 2e7, 0), (650.0, 0.035, 2.5e7, 1), (1100.0, 0.02, 5e7, 0)]}


def chatter(*args):
    if not CHATTER.exists():
        pytest.fail(f"{CHATTER} is missing: build it with `cargo build --release -p chatter`")
    r = subprocess.run([str(CHATTER), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


def read_csv(path):
    """Our CSV: frequency, then real and imaginary columns per pair."""
    head = path.read_text().splitlines()
    header = next(line for line in head if line.startswith("frequency"))
    data = np.genfromtxt(path, delimiter=",", comments="#", skip_header=head.index(header) + 1)
    cols = header.split(",")
    out = {}
    for i, c in enumerate(cols[1:], start=1):
        pair, part = c.split()[0], c.split()[1]
        out.setdefault(pair, np.zeros(len(data), complex))
        out[pair] += data[:, i] * (1j if part == "imag" else 1)
    return data[:, 0], out


@pytest.mark.parametrize("binary", [False, True])
def test_pyuff_reads_what_we_write(tmp_path, binary):
    uff = tmp_path / "tap.uff"
    chatter("frf", "synth", "--machine", MACHINE, "--out", uff, *(["--binary"] if binary else []))
    csv = tmp_path / "tap.csv"
    chatter("frf", "convert", uff, "--out", csv)
    f, ours = read_csv(csv)
    sets = [s for s in pyuff.UFF(str(uff)).read_sets() if s["type"] == 58]
    assert len(sets) == 2, [s.get("id1") for s in sets]  # an uncoupled tool: xx and yy
    for s in sets:
        pair = "xy"[s["rsp_dir"] - 1] + "xy"[s["ref_dir"] - 1]
        assert s["binary"] == int(binary)
        np.testing.assert_allclose(s["x"], f, rtol=1e-5, atol=1e-9)
        np.testing.assert_allclose(s["data"], ours[pair], rtol=1e-10 if binary else 1e-11, atol=0)


@pytest.mark.parametrize("binary", [0, 1])
def test_we_read_what_pyuff_writes(tmp_path, binary):
    f = np.arange(0.0, 2001.0, 0.5)
    w = 2 * np.pi * f
    h = {(1, 1): 1 / (2e7 * (1 - (w / (2 * np.pi * 600)) ** 2 + 0.06j * w / (2 * np.pi * 600))),
         (2, 2): 1 / (2.5e7 * (1 - (w / (2 * np.pi * 650)) ** 2 + 0.07j * w / (2 * np.pi * 650)))}
    h[(1, 2)] = 0.1 * h[(1, 1)]
    path = tmp_path / "pyuff.uff"
    for (rsp, ref), data in h.items():
        d = pyuff.prepare_58(binary=binary, func_type=4, rsp_node=1, rsp_dir=rsp, ref_node=1, ref_dir=ref,
                             data=data, x=f, id1="tap test", rsp_ent_name="tool", ref_ent_name="tool",
                             abscissa_spacing=1, abscissa_spec_data_type=18, ordinate_spec_data_type=8,
                             orddenom_spec_data_type=13)
        pyuff.UFF(str(path))._write_set(d, "add")
    csv = tmp_path / "ours.csv"
    out = chatter("frf", "convert", path, "--out", csv)
    assert "4 FRFs" in out  # yx by reciprocity
    f2, ours = read_csv(csv)
    np.testing.assert_allclose(f2, f, rtol=1e-12)
    for (rsp, ref), data in h.items():
        pair = "xy"[rsp - 1] + "xy"[ref - 1]
        np.testing.assert_allclose(ours[pair], data, rtol=1e-10)
    np.testing.assert_allclose(ours["yx"], ours["xy"], rtol=0)


def test_the_fit_beside_pyema(tmp_path):
    from sdypy import EMA
    rows = []
    for name, machine in [("two modes", TWO_MODES), ("end mill", MACHINE)]:
        tap = tmp_path / f"{machine.stem}.csv"
        chatter("frf", "synth", "--machine", machine, "--out", tap, "--seed", "1")
        out = tmp_path / f"fit_{machine.stem}"
        chatter("frf", "fit", tap, "--out", out)
        ours = np.genfromtxt(out / "modes.csv", delimiter=",", names=True)
        f, frf = read_csv(tap)
        for (fn, zeta, k, axis) in TRUTH[name]:
            i = np.argmin(np.abs(ours["frequency_hz"] - fn) + 1e9 * (np.abs([ours["shape_x"], ours["shape_y"]][axis]) < 0.9))
            o = (ours["frequency_hz"][i], ours["damping"][i], ours["stiffness_n_per_m"][i])
            # pyEMA on the same FRF (the mode's driving point), same kind of band around the modes
            h = frf["xx" if axis == 0 else "yy"]
            modes_here = [m[0] for m in TRUTH[name] if m[3] == axis]
            m = EMA.Model(frf=h[None, :], freq=f, lower=200, upper=1.5 * max(modes_here) + 300, pol_order_high=40,
                          frf_form="receptance")
            m.get_poles(show_progress=False)
            m.select_closest_poles(modes_here)
            _, a = m.get_constants(whose_poles="own", FRF_ind="all")
            j = int(np.argmin(np.abs(np.asarray(m.nat_freq) - fn)))
            pf, pz = m.nat_freq[j], m.nat_xi[j]
            wn = 2 * np.pi * pf
            pk = wn ** 2 / (2 * wn * np.sqrt(1 - pz ** 2) * abs(a[0, j]))
            p = (pf, pz, pk)
            rows.append((name, fn, zeta, k, o, p))
            for got, who in [(o, "ours"), (p, "pyEMA")]:
                assert abs(got[0] / fn - 1) < 0.005, (name, who, got)
                assert abs(got[1] / zeta - 1) < 0.10, (name, who, got)
                assert abs(got[2] / k - 1) < 0.05, (name, who, got)
    print("\n| machine | true f (Hz), ζ, k (N/m) | ours f, ζ, k | pyEMA f, ζ, k |\n|---|---|---|---|")
    for name, fn, zeta, k, o, p in rows:
        print(f"| {name} | {fn:.0f}, {zeta}, {k:.3g} | {o[0]:.2f}, {o[1]:.4f}, {o[2]:.4g} | {p[0]:.2f}, {p[1]:.4f}, {p[2]:.4g} |")
