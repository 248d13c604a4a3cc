"""The snapshots of a contact_slide run, read by xarray (NetCDF4 engine) as a user would.

Usage: read_snapshots_xarray.py <snapshots dir>. Checks that paths.nc (the relaxation paths of a
run, one file with an unlimited frame dimension, chunked and compressed) and a state file open,
with their units and labels, and that the fields agree with the state files where they must: the
last path frame of a slip is the converged state after it, to the force tolerance.
"""
import sys

import numpy as np
import xarray as xr

snapshots = sys.argv[1]
with xr.open_dataset(f"{snapshots}/paths.nc") as paths, xr.open_dataset(
    f"{snapshots}/slip_001_after.nc"
) as after, xr.open_dataset(f"{snapshots}/slip_001_before.nc") as before:
    n = paths.sizes["frame"]
    assert n > 5, n
    assert paths.encoding["unlimited_dims"] == {"frame"}, paths.encoding
    labels = [str(v) for v in paths["label"].values.astype(str)]
    assert set(labels) == {"slip_001_path"}, set(labels)
    for name in ("ux", "uy", "sx", "sy", "tau_x", "tau_y", "tau_max", "pressure", "in_contact"):
        assert paths[name].dims == ("frame", "x", "y"), (name, paths[name].dims)
        assert "units" in paths[name].attrs and "long_name" in paths[name].attrs, name
        assert paths[name].encoding.get("zlib") and paths[name].encoding.get("shuffle"), name
    assert paths["ux"].attrs["units"] == "d" and paths["tau_x"].attrs["units"] == "G"
    iterations = paths["iteration"].values
    assert np.all(np.diff(iterations) > 0), iterations
    # Every frame lies between the states before and after the slip, at the same tip position.
    assert np.allclose(paths["Dx"].values, float(after["Dx"].values[0]))
    ux = paths["ux"].values
    assert np.all(np.isfinite(ux))
    moved_first = np.abs(ux[0] - before["ux"].values[0]).max()
    left_last = np.abs(ux[-1] - after["ux"].values[0]).max()
    moved_whole = np.abs(after["ux"].values[0] - before["ux"].values[0]).max()
    # The slip moves sites by about d; the path goes from near the start to near the end.
    assert moved_whole > 0.5, moved_whole
    assert left_last < moved_whole and moved_first < moved_whole, (moved_first, left_last)
    print(
        f"paths.nc: {n} frames of slip_001_path (iterations {iterations[0]}..{iterations[-1]}); "
        f"largest site motion through the slip {moved_whole:.3f} d; first frame "
        f"{moved_first:.3f} d from the state before, last frame {left_last:.3f} d from the state after"
    )
