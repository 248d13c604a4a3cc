"""The whole-run tools from Python: each function runs the tool itself (the executables the
README's set-up builds into build/bin) with the given options and returns what it wrote:
summary.json as a dict, its CSV tables as NumPy record arrays, and the paths of its figures and
other files. The numbers are the tools' numbers by construction; the runs are resumable and
interruptible as on the command line (Ctrl-C stops the tool, which keeps what it finished:
the call waits for it and then raises KeyboardInterrupt with its message).

    import asperity.tools as t
    scan = t.peierls_scan(b_core=[2, 3, 4], theta=[0, 90], out="ps")
    scan.summary["fits"], scan.tables["peierls"]["tau_P_over_tau_max_pos"]
    fit = t.fit_scaling(["data/reference/sweep_R535.csv"], peierls="ps")
    lines = t.track_loops(["out/snapshots/paths.nc"], label="slip_001_path")

Options are the tools' flags without the dashes, underscores for dashes (b_core -> --b-core);
lists become comma-separated values, True a bare switch (--snapshots), False leaves it out; a
ToolResult or any path stands for its folder or file (peierls=scan).
The folder of the executables is ASPERITY_BIN if set, else the build's (asperity/_build.py).
"""

import csv
import json
import os
import pathlib
import signal
import subprocess
import tempfile

import numpy as np

__all__ = ["ToolResult", "run", "peierls_scan", "fit_scaling", "track_loops", "friction_sweep",
           "contact_slide", "bin_dir"]


def bin_dir():
    """Where the tools are: ASPERITY_BIN, else the bin folder of the build this package is in."""
    if os.environ.get("ASPERITY_BIN"):
        return pathlib.Path(os.environ["ASPERITY_BIN"])
    from . import _build
    return pathlib.Path(_build.BIN_DIR)


def read_table(path):
    """A CSV table the tools write, as a NumPy record array: numeric columns as float64, their
    empty cells NaN (a value the tool did not have: slips.csv's census of a rejected state, the
    cost columns of rows an earlier build wrote); a column with text, or only empty cells, as
    str."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return np.rec.fromarrays([], names=[])
    names, body = rows[0], rows[1:]
    columns = []
    for k in range(len(names)):
        values = [r[k] if k < len(r) else "" for r in body]
        column = np.array(values, dtype=str)
        if not values or any(v != "" for v in values):  # no rows: numeric, as before
            try:
                column = np.array([float(v) if v != "" else np.nan for v in values], dtype=float)
            except ValueError:
                pass  # text
        columns.append(column)
    return np.rec.fromarrays(columns, names=names)


class ToolResult:
    """What a tool wrote: `out` (its folder), `summary` (summary.json, or None), `tables`
    (name -> record array, one per CSV file in `out`), `files` (every file it wrote), `stdout`,
    `stderr` (its progress and warnings)."""

    def __init__(self, out, stdout, stderr=""):
        self.out = pathlib.Path(out)
        self.stdout = stdout
        self.stderr = stderr
        summary = self.out / "summary.json"
        self.summary = json.loads(summary.read_text()) if summary.exists() else None
        self.files = sorted(p for p in self.out.rglob("*") if p.is_file())
        self.tables = {p.stem: read_table(p) for p in sorted(self.out.glob("*.csv"))}

    @property
    def figures(self):
        return [p for p in self.files if p.suffix == ".png"]

    def json(self, name):
        """Another JSON file of the output (lines.json for track_loops)."""
        return json.loads((self.out / name).read_text())

    def __fspath__(self):
        """The output folder: a result stands for it where a path is expected (a peierls_scan
        result as fit_scaling's or track_loops' peierls=)."""
        return str(self.out)

    def __repr__(self):
        return f"ToolResult({self.out}, tables={list(self.tables)}, {len(self.files)} files)"


def _text(value):
    return os.fspath(value) if isinstance(value, os.PathLike) else str(value)


def _flags(options):
    argv = []
    for key, value in options.items():
        flag = "--" + key.replace("_", "-")
        # NumPy's booleans too (np.True_ is not True).
        if isinstance(value, np.bool_):
            value = bool(value)
        if value is None or value is False:
            continue
        if value is True:
            argv.append(flag)
        elif isinstance(value, (list, tuple, np.ndarray)):
            argv += [flag, ",".join(_text(v) for v in value)]
        else:
            argv += [flag, _text(value)]
    return argv


def run(tool, *arguments, out=None, **options):
    """Runs `tool` (an executable of the build) with positional `arguments` and `options` as
    flags, into `out` (a new temporary folder if None, kept), and returns its ToolResult.
    Raises RuntimeError with the tool's message when it fails."""
    exe = bin_dir() / tool
    if not exe.exists():
        raise FileNotFoundError(f"{exe}: not built (run scripts/setup.sh, or set ASPERITY_BIN)")
    if out is None:
        out = tempfile.mkdtemp(prefix=f"asperity_{tool}_")
    argv = [str(exe), *map(_text, arguments), *_flags(options), "--out", str(out)]
    # Its own process group: a terminal's Ctrl-C reaches the tool once, through _wait, not also
    # directly (a second SIGINT ends a tool at once, without its checkpoint).
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            process_group=0)
    stdout, stderr, interrupted = _wait(proc)
    if interrupted:
        raise KeyboardInterrupt(f"{tool} stopped (exit {proc.returncode}): {' '.join(argv)}\n"
                                f"{stderr.strip()}")
    if proc.returncode != 0:
        raise RuntimeError(f"{tool} failed (exit {proc.returncode}): {' '.join(argv)}\n"
                           f"{stderr.strip()}")
    return ToolResult(out, stdout, stderr)


def _wait(proc):
    """The tool's stdout and stderr once it has exited, and whether it was interrupted. Ctrl-C
    (KeyboardInterrupt, from a terminal or a notebook) is passed on as one SIGINT, and the tool
    is waited for while it stops cleanly (a checkpoint, the points in progress); a second
    Ctrl-C passes a second SIGINT, which ends the tool at once, as on the command line.
    (subprocess.run instead kills the tool 0.25 s after a KeyboardInterrupt.)"""
    interrupted = False
    while True:
        try:
            stdout, stderr = proc.communicate()
            return stdout, stderr, interrupted
        except KeyboardInterrupt:
            if proc.poll() is None:
                proc.send_signal(signal.SIGINT)
            interrupted = True


def peierls_scan(scene=None, out=None, **options):
    """Peierls stress of the periodic cell over core widths and angles (MODEL.md 6): peierls.csv
    as tables["peierls"], the fits per angle in summary["fits"]. scene: a scan scene file
    (default data/scenes/peierls_default.toml); options: b_core, theta, L, model, jobs, ..."""
    return run("peierls_scan", *([scene] if scene else []), out=out, **options)


def fit_scaling(sweeps, out=None, **options):
    """c0, the regime map and the Regime III comparison (MODEL.md 8) from friction_sweep tables:
    summary.json, tables["predictions"]. options: peierls (a peierls_scan folder or summary),
    k1, k2, f_P, window, bootstrap, seed, map_a, map_R; forecast_R and forecast_a (lists, d)
    add tables["forecast"], the prediction at contacts without data."""
    return run("fit_scaling", *[str(s) for s in sweeps], out=out, **options)


def track_loops(files, out=None, **options):
    """Dislocation lines and loops through the frames of snapshot files (MODEL.md 7):
    result.json("lines.json"), tables["events"], lines_NNNN.vtk. options: label, slip, peierls,
    profiles, front (the stress held all along each line, front_NNNN.csv), plot_every, ..."""
    return run("track_loops", *[str(f) for f in files], out=out, **options)


def friction_sweep(scene, out=None, **options):
    """mu/alpha over contact radii (a sweep scene): tables["sweep"], summary.json. options: the
    sweep's (a, R, a_over_bcore0, jobs, tip_angles, largest_slip, ...) and the slide scene's
    but a and R (alpha, tolerance, distance, max_slips, threads, slip_solver, ...), each
    overriding the scene's key (`friction_sweep --list-settings`, docs/settings.md)."""
    return run("friction_sweep", scene, out=out, **options)


def contact_slide(scene=None, out=None, **options):
    """One slide, as asperity.slide() runs it in-process, but writing the tool's files."""
    return run("contact_slide", *([scene] if scene else []), out=out, **options)
