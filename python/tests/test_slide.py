"""The Python package against the tools (issue 25): same scenes, same numbers, same messages."""
import json
import os
import pathlib
import signal
import subprocess
import threading

import numpy as np
import pytest

import asperity

BIN = pathlib.Path(os.environ["ASPERITY_BIN"])
SMALL = {"contact": {"a": 12, "R": 125}}  # Regime I, about a second


def test_imports_from_any_folder(tmp_path):
    # The README's line: PYTHONPATH set, Debian's interpreter, any working directory.
    out = subprocess.run(["/usr/bin/python3", "-c", "import asperity; print(asperity.version())"],
                         cwd=tmp_path, check=True, capture_output=True, text=True).stdout
    assert out.startswith("asperity")


def test_scene_defaults_and_dotted_keys_are_the_tools():
    nested = asperity.Scene(SMALL).settings
    dotted = asperity.Scene({"contact.a": 12, "contact.R": 125}).settings
    assert nested == dotted
    assert nested["contact.a"] == 12 and nested["solver.tolerance"] == 1e-05


@pytest.mark.parametrize(
    "settings, words",
    [({"contact": {"a": -3}}, "contact.a = -3"),
     ({"contact": {"aa": 3}}, "unknown key"),
     ({"solver": {"method": "bfgs"}}, "solver.method"),
     ({"contact": {"a": 600}}, "contact.R")])
def test_bad_settings_raise_value_error_naming_the_key(settings, words):
    with pytest.raises(ValueError, match=words):
        asperity.Scene(settings)


def test_slide_gives_the_tools_numbers(tmp_path):
    result = asperity.slide(SMALL)
    subprocess.run([BIN / "contact_slide", "--a", "12", "--R", "125", "--out", tmp_path],
                   check=True, capture_output=True)
    tool = json.loads((tmp_path / "summary.json").read_text())
    assert result.mu == tool["mu"]  # the same code: bit for bit
    assert result.mu_over_alpha == tool["mu_over_alpha"]
    trace = np.genfromtxt(tmp_path / "trace.csv", delimiter=",", names=True)
    # Every column of trace.csv, in its order; the CSV keeps shortest round-trip numbers.
    assert result.trace.dtype.names == trace.dtype.names
    for name in trace.dtype.names:
        np.testing.assert_array_equal(result.trace[name].astype(float), trace[name], err_msg=name)
    assert result.trace["slip"].dtype == bool


def test_adhesive_envelope_reports_the_friction_stress(tmp_path):
    # The new keys come through the settings table (issue 27): no load, so mu is None and the
    # friction is the stress tau_fric = Fx/A, as contact_slide gives it.
    scene = {"contact": {"a": 10, "envelope": "adhesive", "tau0": 0.05}}
    result = asperity.slide(scene)
    subprocess.run([BIN / "contact_slide", "--a", "10", "--envelope", "adhesive", "--tau0", "0.05",
                    "--out", tmp_path], check=True, capture_output=True)
    tool = json.loads((tmp_path / "summary.json").read_text())
    assert result.mu is None and result.mu_over_alpha is None and "mu_note" in result.summary
    assert result.tau_fric == tool["tau_fric"]
    assert result.summary["tau_fric_over_tau0"] == tool["tau_fric_over_tau0"]
    assert 0 < result.summary["tau_fric_over_tau0"] <= 1
    assert result.summary["envelope"] == "adhesive" and result.summary["bcore0"] == 20
    assert np.all(result.trace["Fz"] == 0) and np.all(result.trace["area"] > 0)
    # Without load the progress reports the same measure: Fx/area, in G.
    seen = []
    asperity.slide(scene, progress=seen.append)
    friction = {float(t["Dx"]): float(t["Fx"]) / float(t["area"]) for t in result.trace}
    accepted = [r for r in seen if r["phase"] == "accepted"]
    assert accepted and all(r["measure"] == "area" for r in seen)
    assert all(r["friction"] == pytest.approx(friction[r["Dx"]], rel=1e-14) for r in accepted)
    with pytest.raises(ValueError, match="contact.tau0 = 0"):
        asperity.Scene({"contact": {"envelope": "adhesive"}})


def test_progress_is_called_and_phases_are_named():
    seen = []
    asperity.slide(SMALL, progress=seen.append)
    assert seen[0]["phase"] == "start"
    assert any(r["phase"] == "accepted" for r in seen)
    assert all(seen[i]["Dx"] <= seen[i + 1]["Dx"] for i in range(len(seen) - 1))


def test_progress_carries_the_friction_now_and_the_largest_so_far():
    # Each accepted state's report carries Fx/Fz of its trace row; the largest so far is the
    # running maximum of the rows (a later maximum counts only if it is higher by more than
    # 1e-6 relative, the slide's noise guard for a Regime I trace that repeats its maximum).
    seen = []
    result = asperity.slide(SMALL, progress=seen.append)
    assert seen[0]["phase"] == "start" and np.isnan(seen[0]["friction"])
    assert all(r["measure"] == "load" for r in seen)
    rows = {float(t["Dx"]): float(t["Fx"]) / float(t["Fz"]) for t in result.trace}
    accepted = [r for r in seen if r["phase"] == "accepted"]
    assert len(accepted) >= 5
    largest = rows[0.0]
    for r in accepted:
        assert r["friction"] == pytest.approx(rows[r["Dx"]], rel=1e-14)
        largest = max(largest, rows[r["Dx"]])
        assert largest * (1 - 1e-6) <= r["peak_friction"] <= largest
    assert accepted[-1]["peak_friction"] > accepted[0]["friction"]


def test_ctrl_c_stops_the_slide_with_keyboard_interrupt():
    # SIGINT while the slide runs in C++ without the GIL: the slide polls Python's handler and
    # stops where it stands, well before the uninterrupted slide's end (a = 43 d, R = 535 d:
    # about two seconds, 9 computed steps).
    scene = asperity.Scene({"contact": {"a": 43, "R": 535}})
    full = []
    asperity.slide(scene, progress=lambda r: full.append(r["phase"]))
    cut = []
    timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        asperity.slide(scene, progress=lambda r: cut.append(r["phase"]))
    timer.join()
    assert cut.count("accepted") < full.count("accepted")


def test_tip_lattice_keys_are_the_tools(tmp_path):
    # The tip's lattice out of registry (issue 27): rows of the same settings table, so a dict
    # takes them nested or dotted, and the slide is the tool's to the bit.
    scene = {"contact": {"a": 12, "R": 535, "tip_angle": 2.0, "tip_mismatch": 0.01}}
    dotted = {"contact.a": 12, "contact.R": 535, "contact.tip_angle": 2.0,
              "contact.tip_mismatch": 0.01}
    assert asperity.Scene(scene).settings == asperity.Scene(dotted).settings
    result = asperity.slide(scene)
    subprocess.run([BIN / "contact_slide", "--a", "12", "--R", "535", "--tip-angle", "2",
                    "--tip-mismatch", "0.01", "--out", tmp_path], check=True, capture_output=True)
    tool = json.loads((tmp_path / "summary.json").read_text())
    assert result.mu == tool["mu"]
    assert result.mu_over_alpha < 1.0  # Regime I out of registry
    with pytest.raises(ValueError, match="contact.tip_angle"):
        asperity.Scene({"contact": {"tip_angle": 60}})
