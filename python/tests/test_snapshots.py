"""Snapshots as xarray Datasets (issue 25): slide() keeps the states and relaxation paths the
tools write, with the same values, layout, units and attributes as the tools' NetCDF files
(contact_slide on the same scene, read with xarray); find_lines() finds the lines track_loops
finds in the same frame."""
import csv
import json
import gc
import os
import pathlib
import subprocess
import weakref

import numpy as np
import pytest
import xarray as xr

import asperity

BIN = pathlib.Path(os.environ["ASPERITY_BIN"])
# Two slip events with their paths (a = 20 d, R = 535 d: 0.1 s), fields in double precision so
# the files hold the slide's own numbers.
SCENE = {"contact": {"a": 20, "R": 535}, "slide": {"path_frame_every": 5},
         "output": {"precision": "double", "path_frames": 1}}
TOML = """[contact]\na = 20.0\nR = 535.0\n[slide]\npath_frame_every = 5\n
[output]\nprecision = "double"\npath_frames = 1\n"""


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("snapshots")
    (tmp / "scene.toml").write_text(TOML)
    subprocess.run([BIN / "contact_slide", tmp / "scene.toml", "--out", tmp / "tool"],
                   check=True, capture_output=True)
    return asperity.slide(SCENE), tmp / "tool" / "snapshots"


def test_states_and_paths_are_kept(runs):
    result, _ = runs
    labels = set(result.snapshots)
    assert {"peak", "slip_001_before", "slip_001_after", "slip_002_before",
            "slip_002_after", "slip_001_path"} <= labels, labels
    path = result.snapshots["slip_001_path"]
    assert path.sizes["frame"] > 1
    assert np.all(np.diff(path["iteration"].values) > 0)


def test_each_field_is_held_once():
    # A one-frame state is the slide's own arrays (views, no copy); a path's frames are stacked
    # into one array, and the frames' own arrays are released once it is made, so that a long
    # path is not held twice (docs/python.md).
    result = asperity.slide(SCENE)
    path_fields = [weakref.ref(f["fields"]["tau_x"]) for f in result._frames
                   if f["label"] == "slip_001_path"]
    peak = [f["fields"]["tau_x"] for f in result._frames if f["label"] == "peak"][0]
    assert len(path_fields) > 1
    snapshots = result.snapshots
    assert np.shares_memory(snapshots["peak"]["tau_x"].values, peak)
    del peak
    gc.collect()
    assert all(ref() is None for ref in path_fields)
    assert snapshots["slip_001_path"]["tau_x"].values.flags["OWNDATA"]


def compare(ours, theirs, coordinates=True):
    assert ours["ux"].dims == theirs["ux"].dims == ("frame", "y", "x")
    if coordinates:  # paths.nc's are the first path's block (the frames carry their origins)
        np.testing.assert_array_equal(ours["x"].values, theirs["x"].values)
        np.testing.assert_array_equal(ours["y"].values, theirs["y"].values)
    for name, var in theirs.data_vars.items():
        assert name in ours, name
        if name == "label":
            assert list(ours[name].values) == [str(v) for v in var.values.astype(str)]
            continue
        # The same code, the same numbers: to the last bit.
        np.testing.assert_array_equal(ours[name].values, var.values, err_msg=name)
        assert ours[name].attrs["units"] == var.attrs["units"], name
        assert ours[name].attrs["long_name"] == var.attrs["long_name"], name
    for key in ("model", "a", "R", "alpha", "G", "nu", "a_over_bcore0", "tolerance"):
        assert ours.attrs[key] == theirs.attrs[key], key


@pytest.mark.parametrize("label", ["peak", "slip_001_before", "slip_002_after"])
def test_states_equal_the_tools_files(runs, label):
    result, files = runs
    with xr.open_dataset(files / f"{label}.nc") as theirs:
        compare(result.snapshots[label], theirs)


def test_paths_equal_the_tools_paths_file(runs):
    result, files = runs
    with xr.open_dataset(files / "paths.nc") as paths:
        labels = paths["label"].values.astype(str)
        for label in sorted(set(labels)):
            theirs = paths.isel(frame=np.flatnonzero(labels == label))
            theirs = theirs.assign_coords(frame=np.arange(theirs.sizes["frame"], dtype=np.int32))
            compare(result.snapshots[label], theirs, coordinates=False)


def test_without_snapshots_none_are_kept():
    result = asperity.slide(SCENE, snapshots=False)
    assert result.snapshots == {}
    assert result.summary["slip_events"] == 2


def test_find_lines_finds_what_track_loops_finds(runs, tmp_path):
    result, files = runs
    label = "slip_001_before"
    # The default, and the pieces at the contact edge left unjoined (join_distance 0).
    for options, flags in (({}, []), ({"join_distance": 0.0}, ["--join-distance", "0"])):
        ours = asperity.find_lines(result.snapshots[label], **options)
        out = tmp_path / str(len(flags))
        subprocess.run([BIN / "track_loops", files / f"{label}.nc", "--plot-every", "0",
                        "--out", out, *flags], check=True, capture_output=True)
        frame = json.loads((out / "lines.json").read_text())["frames"][0]
        theirs = frame["lines"]
        assert len(ours["lines"]) == len(theirs) > 0
        assert ours["joined_pieces"] == frame["joined_pieces"]
        key = lambda line: (line["kind"], round(line["length"], 9))  # ids are the tracker's
        for a, b in zip(sorted(ours["lines"], key=key), sorted(theirs, key=key)):
            for field in ("kind", "burgers_x", "length", "area", "screw_fraction", "location",
                          "points", "angle_deg", "slipped_area", "pieces"):
                assert a[field] == b[field], field


def test_front_stresses_measures_what_track_loops_front_measures(runs, tmp_path):
    # The stress held along the lines of one frame, from the frame in memory and from the
    # tool on the file the same slide wrote (double precision): the same points, the same
    # numbers.
    result, files = runs
    label = "slip_001_before"
    ours = asperity.front_stresses(result.snapshots[label])
    subprocess.run([BIN / "track_loops", files / f"{label}.nc", "--front", "--out", tmp_path],
                   check=True, capture_output=True)
    frame = json.loads((tmp_path / "lines.json").read_text())["frames"][0]
    assert frame["front"]["points"] == len(ours["x"]) > 0
    with open(tmp_path / frame["front"]["table"], newline="") as table:
        rows = list(csv.DictReader(table))
    for name in ("arc", "span", "x", "y", "angle_deg", "stress", "slip", "half_width", "bend",
                 "tau_max"):
        np.testing.assert_allclose(ours[name], [float(r[name]) for r in rows], rtol=1e-12,
                                   atol=1e-12, equal_nan=True, err_msg=name)
    assert list(ours["resolved"]) == [r["resolved"] == "1" for r in rows]
    assert list(ours["kind"]) == [r["kind"] for r in rows]
    # One point every 4 d of each line (a loop's closing point is its first).
    expected = sum(int(line["length"] // 4) + (line["kind"] != "loop") for line in ours["lines"])
    assert len(ours["x"]) == expected
    with pytest.raises(ValueError, match="span"):
        asperity.front_stresses(result.snapshots[label], span=0.0)
    with pytest.raises(TypeError, match="min_lenght"):
        asperity.front_stresses(result.snapshots[label], min_lenght=3.0)
    # The lines' options reach the lines: none shorter than min_length is sampled.
    fewer = asperity.front_stresses(result.snapshots[label], min_length=1e6)
    assert len(fewer["x"]) == 0 and fewer["lines"] == []


def test_front_options_are_the_tools_settings(runs, tmp_path):
    # The keywords are track_loops' settings (one table, docs/tracking.md "Settings"): the same
    # non-default values given as keywords and as the tool's flags give the same front, and the
    # tool echoes them in summary.json and lines.json.
    result, files = runs
    label = "slip_001_before"
    options = {"span": 16.0, "step": 2.0, "widths": 3.0, "max_half_width": 24.0,
               "stretches": 4.0, "min_length": 3.0}
    ours = asperity.front_stresses(result.snapshots[label], **options)
    flags = ["--front-span", "16", "--front-step", "2", "--front-widths", "3",
             "--front-max-half-width", "24", "--front-stretches", "4", "--min-length", "3"]
    subprocess.run([BIN / "track_loops", files / f"{label}.nc", "--front", "--out", tmp_path,
                    *flags], check=True, capture_output=True)
    summary = json.loads((tmp_path / "summary.json").read_text())["options"]
    frame = json.loads((tmp_path / "lines.json").read_text())["frames"][0]
    for key in ("span", "step", "widths", "max_half_width", "stretches"):
        assert summary["front." + key] == frame["front"][key] == options[key], key
    assert summary["lines.min_length"] == 3.0
    with open(tmp_path / frame["front"]["table"], newline="") as table:
        rows = list(csv.DictReader(table))
    assert len(rows) == len(ours["x"]) > 0
    np.testing.assert_allclose(ours["stress"], [float(r["stress"]) for r in rows], rtol=1e-12,
                               atol=1e-12, equal_nan=True)
    # A 2 d step on every line: a point every 2 d (a loop's closing point is its first).
    expected = sum(int(line["length"] // 2) + (line["kind"] != "loop") for line in ours["lines"])
    assert len(ours["x"]) == expected
    # Each front option reaches the measure: alone, each moves the stress somewhere, at a
    # value that binds here. This frame's two lines are 16 d long: their stretch is a sixth of
    # each, 2.7 d (span binds at 2 d, stretches at 12), and every window is cut at 1.0-1.6 d
    # by the other line, so max_half_width binds at 1 d and widths at no value (its row is
    # reached as the others are, through the table: tests/unit/test_tracking.cpp).
    base = asperity.front_stresses(result.snapshots[label], min_length=3.0, step=2.0)
    for key, value in (("span", 2.0), ("stretches", 12.0), ("max_half_width", 1.0)):
        one = asperity.front_stresses(result.snapshots[label], min_length=3.0, step=2.0,
                                      **{key: value})
        assert not np.array_equal(one["stress"], base["stress"], equal_nan=True), key


def test_profile_widths_reach_the_core_windows(runs, tmp_path):
    # track_loops --profiles' window around each core crossing is the setting profiles.widths
    # (tracking::CrossingOptions' table): at 0.02 local core widths it is 0.02 / tau_max d
    # either side (b_core = d G / tau_max), narrower than where this frame's cores are cut.
    _, files = runs
    tables = {}
    for widths in (None, "0.02"):
        out = tmp_path / str(widths)
        flags = [] if widths is None else ["--profile-widths", widths]
        subprocess.run([BIN / "track_loops", files / "slip_001_before.nc", "--profiles",
                        "--out", out, *flags], check=True, capture_output=True)
        with open(out / "cores_0000.csv", newline="") as table:
            tables[widths] = list(csv.DictReader(table))
        summary = json.loads((out / "summary.json").read_text())["options"]
        assert summary["profiles.widths"] == (4.0 if widths is None else 0.02)
    assert len(tables["0.02"]) == len(tables[None]) > 0
    for narrow, default in zip(tables["0.02"], tables[None]):
        assert float(narrow["half_width"]) == pytest.approx(0.02 / float(narrow["tau_max"]),
                                                            rel=1e-12)
        assert float(narrow["half_width"]) < float(default["half_width"])


def test_keywords_are_checked_as_the_settings_are(runs, tmp_path):
    result, files = runs
    label = "slip_001_before"
    frame = result.snapshots[label]
    base = asperity.find_lines(frame)
    # Values reach the options whatever their Python or NumPy type: the opposite slip sign
    # (the other side of each core is the slipped one) and a wider tangent window change the
    # lines, and the same values given as an int, its name, a NumPy scalar or an integral float
    # change them alike.
    flipped = asperity.find_lines(frame, slip_sign=1)
    assert flipped != base
    for same in ("1", "+1", np.int64(1), np.array(1)):
        assert asperity.find_lines(frame, slip_sign=same) == flipped, repr(same)
    wider = asperity.find_lines(frame, tangent_half_window=3)
    assert wider != base
    assert asperity.find_lines(frame, tangent_half_window=3.0) == wider
    assert asperity.find_lines(frame, tangent_half_window=np.uint8(3)) == wider
    longer = asperity.find_lines(frame, min_length=np.float32(30.0))
    assert longer != base and longer == asperity.find_lines(frame, min_length=30)
    # The tool reads "+1" as the sign "1" too, as it did before its flags came from the table.
    for sign in ("1", "+1"):
        subprocess.run([BIN / "track_loops", files / f"{label}.nc", "--plot-every", "0",
                        "--slip-sign", sign, "--out", tmp_path / sign], check=True,
                       capture_output=True)
    assert (json.loads((tmp_path / "1" / "lines.json").read_text())
            == json.loads((tmp_path / "+1" / "lines.json").read_text()))
    for bad, error, message in (({"slip_sign": 0}, ValueError, 'slip_sign = "0": allowed'),
                                ({"slip_sign": 1.0}, TypeError, "slip_sign"),
                                ({"slip_sign": np.True_}, TypeError, "slip_sign"),
                                ({"tangent_half_window": 1.5}, TypeError, "tangent_half_window"),
                                ({"tangent_half_window": np.array(1.5)}, TypeError,
                                 "tangent_half_window"),
                                ({"tangent_half_window": 1e300}, TypeError,
                                 "tangent_half_window"),
                                ({"tangent_half_window": 2**70}, ValueError,
                                 "tangent_half_window"),
                                ({"min_length": True}, TypeError, "min_length"),
                                ({"min_length": np.True_}, TypeError, "min_length"),
                                ({"min_length": np.array([2.0, 3.0])}, TypeError, "min_length"),
                                ({"min_length": "2"}, TypeError, "min_length"),
                                ({"screw_angle_deg": 90.0}, ValueError, "screw_angle_deg = 90"),
                                ({"centre_fraction": 2.0}, ValueError, "centre_fraction = 2"),
                                ({"span": 1.0}, TypeError, "unexpected keyword 'span'")):
        with pytest.raises(error, match=message):
            asperity.find_lines(frame, **bad)
    with pytest.raises(ValueError, match="stretches = 2: allowed: >= 3"):
        asperity.front_stresses(frame, stretches=2)


def test_every_keyword_is_a_setting_at_its_default(runs):
    # Each setting the functions take, from the table track_loops --list-settings prints, given
    # at its default: accepted, and the result is the one without it. Their help lists each
    # with that default.
    result, _ = runs
    frame = result.snapshots["slip_001_before"]
    table = subprocess.run([BIN / "track_loops", "--list-settings"], check=True,
                           capture_output=True, text=True).stdout
    rows = [line.split("|")[1:3] for line in table.splitlines()[2:]]
    settings = {key.strip(" `"): default.strip().strip('"') for key, default in rows}
    lines_keys = {k.partition(".")[2]: v for k, v in settings.items()
                  if k.startswith("lines.") or k == "track.centre_fraction"}
    front_keys = {k.partition(".")[2]: v for k, v in settings.items() if k.startswith("front.")}
    assert len(lines_keys) == 6 and len(front_keys) == 5

    def typed(text):
        return float(text) if "." in text or "e" in text else int(text)

    base_lines = asperity.find_lines(frame)
    base_front = asperity.front_stresses(frame)
    for name, default in lines_keys.items():
        assert asperity.find_lines(frame, **{name: typed(default)}) == base_lines, name
    for name, default in {**lines_keys, **front_keys}.items():
        front = asperity.front_stresses(frame, **{name: typed(default)})
        np.testing.assert_array_equal(front["stress"], base_front["stress"], err_msg=name)
    for doc, keys in ((asperity._asperity.find_lines.__doc__, lines_keys),
                      (asperity._asperity.front_stresses.__doc__, {**lines_keys, **front_keys})):
        for name, default in keys.items():
            assert f"  {name} = {default}: " in doc, name


def test_front_stresses_says_where_the_front_moved_by_a_later_state(runs):
    # Across the first slip: the contact sites whose registry index changed, recounted here,
    # each given to a point of the earlier front or counted elsewhere.
    result, _ = runs
    before, after = result.snapshots["slip_001_before"], result.snapshots["slip_001_after"]
    front = asperity.front_stresses(before, later=after)
    changed = ((np.round(before["sx"].values) != np.round(after["sx"].values))
               & (after["in_contact"].values != 0)).sum()
    assert front["moved"] == changed > 0
    assert front["moved_sites"].sum() + front["elsewhere"] == changed
    assert len(front["moved_sites"]) == len(front["x"])
    assert "moved" not in asperity.front_stresses(before)


def test_find_lines_joins_the_screw_lines_along_the_contact_edge():
    # Regime II, a = 60 d, R = 535 d (about 3 s): just before the first slip, cores run along the
    # top and bottom edges of the contact, where loops nucleate (MODEL.md 8; the seed's "two screw
    # lines at the top and bottom"). The marching squares cut each into a piece per row where
    # the jagged edge steps inward (4 lines and 10 stubs shorter than min_length measured with
    # join_distance = 0); joined (docs/tracking.md, step 3) they are two open screw lines, one
    # per edge, made of every piece, each at least as long as its pieces together.
    result = asperity.slide({"contact": {"a": 60, "R": 535}, "slide": {"max_slips": 1},
                             "output": {"precision": "double"}})
    frame = result.snapshots["slip_001_before"]
    cut = asperity.find_lines(frame, join_distance=0.0)
    joined = asperity.find_lines(frame)
    assert len(cut["lines"]) + cut["dropped_short"] > 2
    lines = joined["lines"]
    assert len(lines) == 2 and joined["dropped_short"] == 0
    assert sorted(line["centroid"][1] > 0 for line in lines) == [False, True]
    assert joined["joined_pieces"] == sum(line["pieces"] for line in lines)
    assert joined["joined_pieces"] == len(cut["lines"]) + cut["dropped_short"]
    radius = joined["contact_radius"]
    for line in lines:
        assert line["kind"] == "open" and line["pieces"] > 2 and line["interior_ends"] == 0
        assert line["screw_fraction"] > 0.9
        assert abs(line["centroid"][1]) > 0.9 * radius
        side = [p for p in cut["lines"] if (p["centroid"][1] > 0) == (line["centroid"][1] > 0)]
        assert line["length"] >= sum(p["length"] for p in side)


def test_find_lines_census_adds_up_its_lines(runs):
    # The census (slips.csv's columns) is the sum over the records: counts by kind, the loops'
    # areas and length-weighted screw fraction, the largest loop; no loop, no fraction (None).
    # The module's slide (Regime II) has open lines before its slips and none after; R = 40 d,
    # a = 24 d (Regime III, about 3 s) leaves one loop arrested around the centre after its first.
    result, _ = runs
    regime_three = asperity.slide({"contact": {"a": 24, "R": 40}, "slide": {"max_slips": 1},
                                   "output": {"precision": "double"}})
    frames = [result.snapshots[label] for label in ("slip_001_before", "slip_001_after", "start")]
    frames.append(regime_three.snapshots["slip_001_after"])
    loops_seen = 0
    for frame in frames:
        found = asperity.find_lines(frame)
        lines, census = found["lines"], found["census"]
        loops = [line for line in lines if line["kind"] == "loop"]
        assert census["lines"] == len(lines)
        assert census["loops"] == len(loops)
        assert census["open_lines"] == sum(line["kind"] == "open" for line in lines)
        assert census["wrapping_lines"] == sum(line["kind"] == "wrapping" for line in lines)
        assert census["loop_length"] == pytest.approx(sum(line["length"] for line in loops),
                                                      rel=1e-12)
        assert census["contact_sites"] == found["contact_sites"]
        assert census["loop_area"] == pytest.approx(sum(line["area"] for line in loops), rel=1e-12)
        assert census["open_length"] == pytest.approx(
            sum(line["length"] for line in lines if line["kind"] != "loop"), rel=1e-12)
        if loops:
            loops_seen += 1
            largest = max(loops, key=lambda line: line["area"])
            assert census["largest_loop_area"] == largest["area"]
            assert census["largest_loop_x_extent"] == pytest.approx(largest["x_extent"])
            assert census["largest_loop_y_extent"] == pytest.approx(largest["y_extent"])
            assert census["largest_loop_screw_fraction"] == largest["screw_fraction"]
            assert (census["largest_loop_cx"], census["largest_loop_cy"]) == tuple(
                largest["centroid"])
            length = sum(line["length"] for line in loops)
            assert census["loop_screw_fraction"] == pytest.approx(
                sum(line["screw_fraction"] * line["length"] for line in loops) / length)
        else:
            assert census["loop_screw_fraction"] is None
            assert census["largest_loop_area"] == 0.0
        # Distinct slipped domains: at most the sum over lines (a shared domain counts once),
        # at least the largest line's.
        areas = [line["slipped_area"] for line in lines]
        assert max(areas, default=0.0) <= census["slipped_area"] <= sum(areas)
    assert loops_seen == 1, "the Regime III slide must leave its arrested loop"


def test_find_lines_reads_a_tools_file_opened_with_xarray(runs):
    result, files = runs
    with xr.open_dataset(files / "slip_001_after.nc") as ds:
        from_file = asperity.find_lines(ds)
    assert from_file == asperity.find_lines(result.snapshots["slip_001_after"])


def test_find_lines_follows_a_rotated_tip(tmp_path):
    # A tip rotated by 2 degrees at a = 43 d (a/b_core^0 = 2.4 > 1): misfit dislocations exist in
    # the loaded state before any sliding (docs/tips.md); find_lines on the Python "start" state
    # finds what track_loops finds in the tool's start.nc, in the tip's frame.
    scene = {"contact": {"a": 43, "R": 535, "tip_angle": 2.0},
             "output": {"precision": "double"}, "slide": {"max_slips": 1}}
    result = asperity.slide(scene)
    start = result.snapshots["start"]
    assert start.attrs["tip_angle"] == 2.0
    ours = asperity.find_lines(start)["lines"]
    (tmp_path / "scene.toml").write_text(
        "[contact]\na = 43.0\nR = 535.0\ntip_angle = 2.0\n[output]\nprecision = \"double\"\n"
        "[slide]\nmax_slips = 1\n")
    subprocess.run([BIN / "contact_slide", tmp_path / "scene.toml", "--out", tmp_path / "o"],
                   check=True, capture_output=True)
    subprocess.run([BIN / "track_loops", tmp_path / "o" / "snapshots" / "start.nc",
                    "--plot-every", "0", "--out", tmp_path / "t"], check=True,
                   capture_output=True)
    theirs = json.loads((tmp_path / "t" / "lines.json").read_text())["frames"][0]["lines"]
    assert len(ours) == len(theirs) >= 2
    key = lambda line: (line["kind"], round(line["length"], 9))
    for a, b in zip(sorted(ours, key=key), sorted(theirs, key=key)):
        for field in ("kind", "burgers_x", "length", "points", "angle_deg"):
            assert a[field] == b[field], field
