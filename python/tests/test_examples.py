"""The example scripts (examples/) reproduce the tools' numbers (issue 25)."""
import json
import os
import pathlib
import re
import subprocess
import sys

BIN = pathlib.Path(os.environ["ASPERITY_BIN"])
EXAMPLES = pathlib.Path(os.environ["ASPERITY_DATA"]).parent / "examples"


def test_force_traces_gives_contact_slides_mu(tmp_path):
    out = subprocess.run([sys.executable, EXAMPLES / "force_traces.py", "--out",
                          tmp_path / "traces.png"], cwd=tmp_path, check=True,
                         capture_output=True, text=True).stdout
    assert (tmp_path / "traces.png").stat().st_size > 10_000
    printed = dict(re.findall(r"^(Regime \w+): .*mu/alpha = (\S+),", out, re.M))
    assert set(printed) == {"Regime I", "Regime II", "Regime III"}
    # The Regime III scene as a scene file, slid by the tool: the same mu/alpha to the last bit.
    scene = tmp_path / "regime3.toml"
    scene.write_text("[contact]\na = 24\nR = 40\n[slide]\ndistance = 2.3\nmax_step = 0.05\n")
    subprocess.run([BIN / "contact_slide", scene, "--out", tmp_path / "tool"], check=True,
                   capture_output=True)
    tool = json.loads((tmp_path / "tool" / "summary.json").read_text())
    assert float(printed["Regime III"]) == tool["mu_over_alpha"]


def test_collapse_gives_contact_slides_mu(tmp_path):
    out = subprocess.run([sys.executable, EXAMPLES / "collapse.py", "--out",
                          tmp_path / "collapse.png"], cwd=tmp_path, check=True,
                         capture_output=True, text=True).stdout
    assert (tmp_path / "collapse.png").stat().st_size > 10_000
    points = re.findall(r"^R = (\S+) d, a = (\S+) d: .*mu/alpha = (\S+)$", out, re.M)
    assert len(points) == 8
    # Regime I at the smallest contacts, Regime II falling below 0.4 at a/b_core^0 = 10, and the
    # two radii on one curve (the collapse): within 1% at each target.
    mus = [float(m) for _, _, m in points]
    assert mus[0] > 0.95 and mus[3] < 0.4
    for lo, hi in zip(mus[:4], mus[4:]):
        assert abs(lo - hi) < 0.01 * hi
    R, a, mu = points[6]  # R = 535 d at a/b_core^0 = 3, slid by the tool
    subprocess.run([BIN / "contact_slide", "--a", a, "--R", R, "--out", tmp_path / "tool"],
                   check=True, capture_output=True)
    tool = json.loads((tmp_path / "tool" / "summary.json").read_text())
    assert float(mu) == tool["mu_over_alpha"]
