"""The snapshots of a contact_slide run, read by xarray (NetCDF4 engine) as a user would.

Usage: read_snapshots_xarray.py <snapshots dir>. Checks that paths.nc (the relaxation paths of a
run, one file with an unlimited frame dimension, chunked and compressed) and the state files
open, with their units and labels, and that the path goes from the state before the slip to the
state after it: on the contact sites, the first frame is nearer the state before and the last
frame nearer the state after, and the distance to the state after shrinks along the path.
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
        assert paths[name].dims == ("frame", "y", "x"), (name, paths[name].dims)
        assert "units" in paths[name].attrs and "long_name" in paths[name].attrs, name
        assert paths[name].encoding.get("zlib") and paths[name].encoding.get("shuffle"), name
    assert paths["ux"].attrs["units"] == "d" and paths["tau_x"].attrs["units"] == "G"
    iterations = paths["iteration"].values
    assert np.all(np.diff(iterations) > 0), iterations
    # Every frame lies between the states before and after the slip, at the same tip position.
    assert np.allclose(paths["Dx"].values, float(after["Dx"].values[0]))
    # The contact sites (the frames' other sites keep the start state's displacement).
    contact = paths["in_contact"].values[-1].astype(bool)
    ux = paths["ux"].values[:, contact]
    assert np.all(np.isfinite(ux))
    u0, u1 = before["ux"].values[0][contact], after["ux"].values[0][contact]
    whole = np.abs(u1 - u0).mean()
    to_after = np.abs(ux - u1).mean(axis=1)  # per frame
    to_before = np.abs(ux - u0).mean(axis=1)
    assert whole > 0.1, whole  # a slip that swept the contact
    assert to_before[0] < to_after[0] and to_after[-1] < to_before[-1], (to_before, to_after)
    assert to_after[-1] < 0.1 * whole, (to_after[-1], whole)
    # Descent towards the state after: the distance falls along the path (5% slack for the
    # overshoot of a loop front between frames).
    assert np.all(np.diff(to_after) < 0.05 * whole), np.diff(to_after)
    print(
        f"paths.nc: {n} frames of slip_001_path (iterations {iterations[0]}..{iterations[-1]}); "
        f"mean motion of a contact site through the slip {whole:.3f} d; mean distance to the "
        f"state after {to_after[0]:.3f} d at the first frame, {to_after[-1]:.4f} d at the last"
    )
