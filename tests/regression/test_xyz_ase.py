"""The extended XYZ snapshots of a contact_slide run (output.xyz = true), read by ASE's
ase.io.read as a user would, against the NetCDF files beside them read by xarray: every .nc has
its .xyz, with the same frames, per-frame values and per-site fields (to the last bit of the
precision the files store), positions X + u, the registry index round(s) and the file's
attributes. Run by ctest through Debian's /usr/bin/python3 (python3-ase, python3-xarray,
python3-pytest). The folder comes from ASPERITY_SNAPSHOTS.
"""
import glob
import os

import ase.io
import numpy as np
import pytest
import xarray as xr

SNAPSHOTS = os.environ.get("ASPERITY_SNAPSHOTS", "")
FIELDS = ("ux", "uy", "sx", "sy", "tau_x", "tau_y", "tau_max", "pressure")
PER_FRAME = ("iteration", "Dx", "Fx", "Fz", "origin_x", "origin_y")
ATTRIBUTES = ("model", "a", "R", "alpha", "G", "nu", "tolerance")


def nc_files():
    files = sorted(glob.glob(os.path.join(SNAPSHOTS, "*.nc")))
    assert files, f"no snapshots in {SNAPSHOTS!r} (set ASPERITY_SNAPSHOTS)"
    return files


def test_every_snapshot_file_has_its_xyz():
    names = {os.path.splitext(f)[0] for f in nc_files()}
    xyz = {os.path.splitext(f)[0] for f in glob.glob(os.path.join(SNAPSHOTS, "*.xyz"))}
    assert names == xyz, (names ^ xyz)
    assert any(n.endswith("paths") for n in names), names  # a relaxation path is checked too
    assert any(n.endswith("_after") for n in names), names  # and a slip


def registry(s):
    """round(s) with halves away from zero, as std::lround in the writer."""
    return (np.sign(s) * np.floor(np.abs(s) + 0.5)).astype(int)


def sites(ds, name, k):
    """Frame k of field `name` in the order of the XYZ atoms: block sites, x slow (the .nc stores
    (frame, y, x), as VTK's CF reader takes a grid)."""
    return ds[name].transpose("frame", "x", "y").values[k].ravel()


@pytest.mark.parametrize("nc", nc_files(), ids=os.path.basename)
def test_ase_reads_the_same_frames(nc):
    frames = ase.io.read(os.path.splitext(nc)[0] + ".xyz", index=":", format="extxyz")
    with xr.open_dataset(nc) as ds:
        assert len(frames) == ds.sizes["frame"]
        n0, n1 = ds.sizes["x"], ds.sizes["y"]
        single = ds.attrs["field_precision"] == "float32"
        dtype = np.float32 if single else np.float64
        labels = ds["label"].values.astype(str)
        for k, atoms in enumerate(frames):
            assert len(atoms) == n0 * n1
            assert atoms.info["label"] == labels[k]
            for key in PER_FRAME:
                assert atoms.info[key] == ds[key].values[k], (key, atoms.info[key])
            # ASE hands `energy` to a calculator of the frame, not to info.
            assert atoms.get_potential_energy() == ds["energy"].values[k]
            for key in ATTRIBUTES:
                assert atoms.info[key] == ds.attrs[key], key
            assert not atoms.pbc.any()
            assert np.allclose(np.diag(atoms.cell), [n0, n1, 1.0])
            for name in FIELDS + (("uz",) if "uz" in ds else ()):
                want = sites(ds, name, k)
                got = atoms.arrays[name].astype(dtype)
                assert got.dtype == want.dtype
                assert np.array_equal(got, want), (name, np.abs(got - want).max())
            assert np.array_equal(atoms.arrays["in_contact"], sites(ds, "in_contact", k))
            for axis, s in (("x", "sx"), ("y", "sy")):
                want = registry(sites(ds, s, k).astype(np.float64))
                assert np.array_equal(atoms.arrays["registry_" + axis], want), axis
            # Positions: the site X = (origin + i) d plus the stored displacement.
            i0, i1 = np.meshgrid(np.arange(n0), np.arange(n1), indexing="ij")
            X = ds["origin_x"].values[k] + i0.ravel()
            Y = ds["origin_y"].values[k] + i1.ravel()
            ux = sites(ds, "ux", k).astype(np.float64)
            uy = sites(ds, "uy", k).astype(np.float64)
            pos = atoms.get_positions()
            assert np.allclose(pos[:, 0], X + ux, rtol=0, atol=1e-12)
            assert np.allclose(pos[:, 1], Y + uy, rtol=0, atol=1e-12)
            uz = sites(ds, "uz", k) if "uz" in ds else np.zeros(n0 * n1)
            assert np.array_equal(pos[:, 2].astype(dtype), uz.astype(dtype))
