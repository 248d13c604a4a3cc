"""The CF NetCDF snapshots read by VTK's CF reader (vtkNetCDFCFReader, the reader ParaView opens
.nc files with) with its default settings, against the same files read by xarray.

With the defaults (every variable ticked, spherical coordinates on) the reader must give a flat
Cartesian grid of the block's sites (x along VTK's x, y along VTK's y, in lattice spacings), one
time step per frame, and every per-site field as point data with the values of the file. Before
issue 25 it took x and y for longitude and latitude on a sphere and, the per-frame numbers coming
first, loaded none of the fields. Run by ctest through Debian's /usr/bin/python3 (python3-vtk9,
python3-xarray, python3-pytest); the folder comes from ASPERITY_SNAPSHOTS.
"""
import glob
import os

import numpy as np
import pytest
import xarray as xr
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as Pipeline
from vtkmodules.vtkIONetCDF import vtkNetCDFCFReader

SNAPSHOTS = os.environ.get("ASPERITY_SNAPSHOTS", "")
FIELDS = ("ux", "uy", "sx", "sy", "tau_x", "tau_y", "tau_max", "pressure", "in_contact")


def files():
    found = sorted(glob.glob(os.path.join(SNAPSHOTS, "*.nc")))
    assert any(f.endswith("paths.nc") for f in found), (SNAPSHOTS, found)
    return found


def reader_for(path):
    reader = vtkNetCDFCFReader()  # default settings throughout
    reader.SetFileName(path)
    reader.UpdateInformation()
    return reader


def frame(reader, time):
    reader.UpdateTimeStep(time)
    out = reader.GetOutput()
    data = out.GetPointData()
    return out, {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i))
                 for i in range(data.GetNumberOfArrays())}


@pytest.mark.parametrize("path", files(), ids=os.path.basename)
def test_default_settings_give_the_fields_on_a_cartesian_grid(path):
    reader = reader_for(path)
    with xr.open_dataset(path) as ds:
        nx, ny, n = ds.sizes["x"], ds.sizes["y"], ds.sizes["frame"]
        info = reader.GetOutputInformation(0)
        assert info.Has(Pipeline.TIME_STEPS()), "the frames are not VTK time steps"
        assert list(info.Get(Pipeline.TIME_STEPS())) == list(range(n))
        for k in sorted({0, n // 2, n - 1}):
            out, arrays = frame(reader, float(k))
            assert out.GetClassName() == "vtkImageData", out.GetClassName()
            assert out.GetDimensions() == (nx, ny, 1)
            # The sites' coordinates, flat: no sphere.
            x, y = ds["x"].values, ds["y"].values
            assert out.GetBounds() == pytest.approx((x[0], x[-1], y[0], y[-1], 0.0, 0.0))
            assert set(FIELDS) <= set(arrays), sorted(arrays)
            for name in FIELDS:
                # VTK's point order: x fastest, then y, as the file's (frame, y, x).
                expected = ds[name].values[k].astype(float)
                got = arrays[name].astype(float).reshape(ny, nx)
                np.testing.assert_array_equal(got, expected, err_msg=f"{name}, frame {k}")


def test_the_grid_is_the_block_x_along_x():
    """A site's value lands at its own (x, y): a field that is not symmetric in x and y
    (tau_x in a sliding contact, the tip displaced along x) read at the point VTK places at
    (x, y) equals the xarray value at x, y."""
    path = next(f for f in files() if f.endswith("paths.nc"))
    reader = reader_for(path)
    out, arrays = frame(reader, 0.0)
    with xr.open_dataset(path) as ds:
        ux = ds["ux"].isel(frame=0)
        xs, ys = ds["x"].values, ds["y"].values
        nonzero = np.argwhere(np.abs(ux.values) > 0)
        assert len(nonzero) > 0
        for j, i in nonzero[:: max(1, len(nonzero) // 20)]:
            point = out.FindPoint(float(xs[i]), float(ys[j]), 0.0)
            assert arrays["ux"][point] == ux.values[j, i]
            assert float(ux.sel(x=xs[i], y=ys[j])) == ux.values[j, i]
