"""asperity: friction of a crystalline sphere sliding on a crystalline flat, from Python.

The compiled core (asperity._asperity) runs the same code as the command-line tools; this
module turns its results into Python objects.

    import asperity
    scene = asperity.Scene({"contact": {"a": 30, "R": 535}})    # or Scene.from_toml(path)
    result = asperity.slide(scene, progress=print)
    result.mu_over_alpha, result.trace["Fx"], result.summary["gf_applications"]
    peak = result.snapshots["peak"]          # an xarray.Dataset, as snapshots/peak.nc
    asperity.find_lines(result.snapshots["slip_001_before"])["lines"]
    asperity.front_stresses(result.snapshots["slip_001_before"])["stress"]  # held along them
    asperity.slide({"contact": {"a": 10, "envelope": "adhesive", "tau0": 0.05}}).tau_fric

Scenes take the keys of a scene file (data/scenes/default.toml, docs/settings.md), as nested
dicts or dotted keys; a bad key or value raises ValueError naming the key, value and allowed
range. slide() releases the GIL while it runs and stops on Ctrl-C (KeyboardInterrupt).

Also here: the elastic half-space (FreeSurfaceGF, PeriodicSurfaceGF: u = G * f on NumPy arrays,
without copies), the scaling laws (regime_two_law, nucleation_condition, control_parameter,
predict, forecast, fit_regime_two), and asperity.tools, which runs the whole-run tools (peierls_scan,
fit_scaling, track_loops, friction_sweep) and returns what they write.
"""

import json
import pathlib

import numpy as np

from . import _asperity
from ._asperity import (FreeSurfaceGF, PeriodicSurfaceGF, control_parameter, fit_regime_two,
                        forecast, nucleation_condition, predict, regime_two_law)

__all__ = ["Scene", "SlideResult", "slide", "version", "find_lines", "front_stresses",
           "snapshot_dataset",
           "FreeSurfaceGF", "PeriodicSurfaceGF", "regime_two_law", "nucleation_condition",
           "control_parameter", "predict", "forecast", "fit_regime_two", "tools"]


def version():
    """The build's version and commit, as the tools print it."""
    return _asperity.version()


class Scene:
    """A validated slide scene: the keys of a scene file, with the tools' defaults and checks."""

    def __init__(self, settings=None):
        self._scene = _asperity.scene_from_dict(dict(settings or {}))

    @classmethod
    def from_toml(cls, path):
        """The scene of a TOML scene file, read as contact_slide reads it."""
        path = pathlib.Path(path)
        scene = cls.__new__(cls)
        scene._scene = _asperity.scene_from_toml(path.read_text(), str(path))
        return scene

    @property
    def settings(self):
        """Every setting, keyed as in a scene file ("contact.a", "solver.tolerance", ...)."""
        return json.loads(self._scene.settings_json())

    @property
    def snapshot_attributes(self):
        """The global attributes the tools give this scene's snapshot files."""
        return json.loads(self._scene.snapshot_attributes_json())

    def __repr__(self):
        s = self.settings
        return f"Scene(a={s['contact.a']} d, R={s['contact.R']} d, alpha={s['contact.alpha']})"


_VARIABLES = {v["name"]: v for v in _asperity.snapshot_variables()}


def snapshot_dataset(frames, attributes=None):
    """Frames of one label (dicts from the compiled core) as an xarray.Dataset in the layout of
    the tools' NetCDF files (apps/common/snapshot_io.hpp): fields (frame, y, x), coordinates x
    and y of the first frame's block in lattice spacings d, per-frame Dx, Fx, Fz, energy,
    iteration, origin_x, origin_y and label, units and long_name on every variable."""
    import xarray as xr

    first = frames[0]
    n0, n1 = first["fields"]["ux"].shape
    x = first["origin_x"] + np.arange(n0, dtype=float)
    y = first["origin_y"] + np.arange(n1, dtype=float)

    def attrs(name):
        v = _VARIABLES[name]
        return {"units": v["units"], "long_name": v["long_name"]}

    data = {}
    for name in first["fields"]:
        # (n0, n1) block-major -> (y, x): a view; one frame is not copied.
        planes = [f["fields"][name].T for f in frames]
        stacked = planes[0][np.newaxis] if len(planes) == 1 else np.stack(planes)
        data[name] = (("frame", "y", "x"), stacked, attrs(name))
    for name in ("Dx", "Fx", "Fz", "energy", "iteration", "origin_x", "origin_y"):
        values = np.array([f[name] for f in frames])
        data[name] = (("frame",), values, attrs(name))
    data["label"] = (("frame",), np.array([f["label"] for f in frames]),
                     {"units": "1", "long_name": "snapshot label"})
    coords = {
        "frame": (("frame",), np.arange(len(frames), dtype=np.int32),
                  {"units": "1", "axis": "T",
                   "long_name": "frame index: the file's sequence of states, not a time"}),
        "x": (("x",), x, {"units": "1",
                          "long_name": "x of the first frame's sites, in lattice spacings d"}),
        "y": (("y",), y, {"units": "1",
                          "long_name": "y of the first frame's sites, in lattice spacings d"}),
    }
    ds = xr.Dataset(data, coords=coords, attrs=dict(attributes or {}))
    ds.attrs["label"] = first["label"]
    # The tip's lattice, as the files carry it (alike in every frame of a file).
    ds.attrs["tip_angle"] = float(first.get("tip_angle", 0.0))
    ds.attrs["tip_mismatch"] = float(first.get("tip_mismatch", 0.0))
    return ds


class SlideResult:
    """A slide's result: what contact_slide writes to summary.json, its trace and snapshots."""

    def __init__(self, summary, columns, frames=(), attributes=None):
        self.summary = summary
        names = list(columns)
        self.trace = np.rec.fromarrays([columns[n] for n in names], names=names)
        self._frames = list(frames)
        self._attributes = attributes or {}
        self._snapshots = None

    @property
    def mu(self):
        """Static friction coefficient max Fx/Fz; None for the adhesive envelope (no load)."""
        return self.summary["mu"]

    @property
    def mu_over_alpha(self):
        return self.summary["mu_over_alpha"]

    @property
    def snapshots(self):
        """The snapshots as xarray Datasets keyed by label, as the tools' files: "start" (the
        first relaxed state), "peak", "slip_NNN_before", "slip_NNN_after" (one frame each) and "slip_NNN_path" (the frames of
        a slip's relaxation path, as the tools' paths.nc holds them under that label)."""
        if self._snapshots is None:
            groups = {}
            for f in self._frames:
                groups.setdefault(f["label"], []).append(f)
            # A path's frames are stacked into one array per field (a copy); once every label
            # is made the frames are dropped, so that the result holds each field once. Until
            # then they are kept, so that a failure leaves the result as it was.
            snapshots = {label: snapshot_dataset(frames, self._attributes)
                         for label, frames in groups.items()}
            self._frames = None
            self._snapshots = snapshots
        return self._snapshots

    @property
    def tau_fric(self):
        """Friction stress Fx/A at the peak (G), A the contact-site area (summary "contact_area")."""
        return self.summary["tau_fric"]

    def __repr__(self):
        if self.mu_over_alpha is not None:
            friction = f"mu/alpha={self.mu_over_alpha:.6g}"
        elif self.summary.get("tau_fric_over_tau0") is not None:
            friction = f"tau_fric/tau0={self.summary['tau_fric_over_tau0']:.6g}"
        else:
            friction = "no friction (failed)"
        return (f"SlideResult({friction}, "
                f"{len(self.trace)} rows, {self.summary.get('slip_events')} slip events)")


def slide(scene, progress=None, snapshots=True):
    """Slides `scene` (a Scene or a dict of settings) quasi-statically (MODEL.md 5).

    progress: None, or a callable taking a dict (phase, Dx, target_Dx, slip_events, steps,
    gf_applications, wall_s, iteration; measure, friction, peak_friction: the friction of the
    last accepted state and the largest so far, Fx/Fz with measure "load" or Fx/area in G with
    "area", NaN before the first state), called before every relaxation, after every accepted
    step and from inside long relaxations.
    snapshots: keep the states (peak, before and after each slip) and the relaxation paths the
    scene asks for (slide.path_frame_every) as result.snapshots; False keeps none (a long slide
    holds no frames in memory).
    """
    if not isinstance(scene, Scene):
        scene = Scene(scene)
    summary, columns, frames = _asperity.slide(scene._scene, progress, snapshots)
    return SlideResult(json.loads(summary), columns, frames, scene.snapshot_attributes)


def _frame(frame, index):
    """One frame of a snapshot Dataset (a state has no frame dimension)."""
    return frame.isel(frame=index) if "frame" in frame.dims else frame


def _block(ds, name):
    """The field in the tools' block order (x slow), contiguous."""
    return np.ascontiguousarray(ds[name].transpose("x", "y").values)


def _origin(ds):
    """The lattice index of the block's first site along x and y."""
    return (int(ds["origin_x"]) if "origin_x" in ds else int(ds["x"].values[0]),
            int(ds["origin_y"]) if "origin_y" in ds else int(ds["y"].values[0]))


def find_lines(frame, index=0, periodic=None, **options):
    """Dislocation lines in one snapshot frame (MODEL.md 7), as track_loops finds them.

    frame: an xarray Dataset in the snapshot layout (result.snapshots[...], or a tools' .nc
    opened with xarray); index: the frame in it. options: track_loops' lines.* settings and
    track.centre_fraction as keywords, unprefixed (min_length, join_distance: 0 leaves the
    pieces of one core cut by the contact's jagged edge unjoined, slip_sign, ...); their
    defaults, allowed values and meanings: help(asperity._asperity.find_lines), made from the
    one table track_loops --list-settings prints (docs/tracking.md, "Settings").
    Returns a dict: "lines" (the records of track_loops' lines.json, ids in frame order),
    "census" (what they add up to: loops, loop_area, loop_screw_fraction, the largest loop,
    slipped_area, ...; the columns of friction_sweep --largest-slip's slips.csv, None where
    there is no loop) and the frame's counts (contact_sites, contact_radius, core_crossings, ...).
    """
    ds = _frame(frame, index)
    origin_x, origin_y = _origin(ds)
    fields = {
        "origin_x": origin_x,
        "origin_y": origin_y,
        "tip_angle": float(frame.attrs.get("tip_angle", 0.0)),
        "tip_mismatch": float(frame.attrs.get("tip_mismatch", 0.0)),
        "periodic": bool(frame.attrs.get("periodic", False)) if periodic is None else periodic,
    }
    # A tip out of registry (the files' attributes): the registry along the tip's first axis
    # needs sy and tau_y too; the aligned tip's does not.
    if fields["tip_angle"] != 0.0 or fields["tip_mismatch"] != 0.0:
        fields.update(sy=_block(ds, "sy"), tau_y=_block(ds, "tau_y"))
    contact = _block(ds, "in_contact").astype(np.uint8) if "in_contact" in ds else None
    return _asperity.find_lines(_block(ds, "sx"), _block(ds, "tau_x"), _block(ds, "tau_max"),
                                contact, **fields, **options)


def front_stresses(frame, index=0, periodic=None, later=None, later_index=0, **options):
    """The stress held all along every line of one snapshot frame (MODEL.md 6, 7), as
    track_loops --front measures it (docs/tracking.md, "The stress held all along a line"):
    every `step` d of each line, the stress a stretch `span` d long holds, the Peierls-Nabarro
    force on it per Burgers vector (G), to compare with the local Peierls stress at its angle.

    frame: an xarray Dataset in the snapshot layout; index: the frame in it. options:
    track_loops' front.* settings as keywords, unprefixed (span, stretches, step, widths,
    max_half_width), and find_lines' options; their defaults, allowed values and meanings:
    help(asperity._asperity.front_stresses), from the table track_loops --list-settings
    prints. Returns a dict of NumPy columns, one row per point: line (index in
    "lines"), kind, arc, span, x, y (d), angle_deg (0 screw, 90 edge), stress (G), slip (d),
    resolved, half_width, bend (d), tau_max (G); and "lines", the lines as find_lines gives
    them. Under a tip out of registry nothing is measured (ValueError).

    later: a later state of the same contact (later_index: its frame): the result then also
    says where the front moved by then, as track_loops' front_moves_NNNN.csv: the contact
    sites whose registry index round(s_x) changed, given to the points whose stretch covers
    them ("moved_sites" per point), all of them ("moved") and those no point covers
    ("elsewhere").
    """
    ds = _frame(frame, index)
    if float(frame.attrs.get("tip_angle", 0.0)) != 0.0 or \
            float(frame.attrs.get("tip_mismatch", 0.0)) != 0.0:
        raise ValueError("front_stresses: under a tip out of registry the registry runs along "
                         "the tip's axis and the stress held is not measured (docs/tracking.md)")
    origin_x, origin_y = _origin(ds)
    fields = {
        "origin_x": origin_x,
        "origin_y": origin_y,
        "Dx": float(ds["Dx"]) if "Dx" in ds else 0.0,
        "periodic": bool(frame.attrs.get("periodic", False)) if periodic is None else periodic,
    }
    contact = _block(ds, "in_contact").astype(np.uint8) if "in_contact" in ds else None
    optional = {name: _block(ds, name) for name in ("uy", "tau_y") if name in ds}
    if "uy" not in ds and "sy" in ds:  # u_y = s_y - Y, as the tool takes it
        optional["uy"] = _block(ds, "sy") - ds["y"].values[None, :]
    if later is not None:
        ls = _frame(later, later_index)
        optional["later_sx"] = _block(ls, "sx")
        if "in_contact" in ls:
            optional["later_in_contact"] = _block(ls, "in_contact").astype(np.uint8)
        else:
            optional["later_tau_max"] = _block(ls, "tau_max")
        optional["later_origin_x"], optional["later_origin_y"] = _origin(ls)
    return _asperity.front_stresses(_block(ds, "sx"), _block(ds, "tau_x"), _block(ds, "tau_max"),
                                    contact, **optional, **fields, **options)


from . import tools  # noqa: E402  (the tools need the names above)
