"""The dislocation lines of a track_loops run as VTK polylines (lines_NNNN.vtk), read by VTK's
legacy reader (vtkPolyDataReader, the one ParaView uses for .vtk), against lines.json: a file per
frame, the same lines, points (a loop closed by its first point again), ids, kinds, Burgers
vectors and per-point angles and character classes. Run by ctest through Debian's
/usr/bin/python3 (python3-vtk9, python3-pytest). The folder comes from ASPERITY_TRACKS.
"""
import glob
import json
import os

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOLegacy import vtkPolyDataReader

TRACKS = os.environ.get("ASPERITY_TRACKS", "")
KINDS = {"loop": 0, "open": 1, "wrapping": 2}


def frames():
    with open(os.path.join(TRACKS, "lines.json")) as f:
        return json.load(f)["frames"]


def read(path):
    reader = vtkPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    assert reader.IsFilePolyData(), path
    return reader.GetOutput()


def character(angle):
    return np.where(angle < 30.0, 0, np.where(angle > 60.0, 2, 1))


def test_a_file_per_frame():
    files = sorted(glob.glob(os.path.join(TRACKS, "lines_*.vtk")))
    assert len(files) == len(frames()) > 5, (len(files), len(frames()))


def test_vtk_reads_the_lines_of_lines_json():
    total_lines = loops = 0
    for frame in frames():
        poly = read(os.path.join(TRACKS, f"lines_{frame['frame']:04d}.vtk"))
        lines = frame["lines"]
        assert poly.GetNumberOfCells() == len(lines), frame["frame"]
        field = poly.GetFieldData()
        assert vtk_to_numpy(field.GetArray("frame"))[0] == frame["frame"]
        assert vtk_to_numpy(field.GetArray("iteration"))[0] == frame["iteration"]
        assert vtk_to_numpy(field.GetArray("Dx"))[0] == frame["Dx"]
        if not lines:
            assert poly.GetNumberOfPoints() == 0
            continue
        points = vtk_to_numpy(poly.GetPoints().GetData())
        pd, cd = poly.GetPointData(), poly.GetCellData()
        angle = vtk_to_numpy(pd.GetArray("angle_deg"))
        char = vtk_to_numpy(pd.GetArray("character"))
        line_id = vtk_to_numpy(pd.GetArray("line_id"))
        burgers = vtk_to_numpy(pd.GetArray("burgers"))
        assert pd.GetVectors().GetName() == "burgers"
        for j, line in enumerate(lines):
            total_lines += 1
            cell = poly.GetCell(j)
            ids = [cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]
            want = np.array(line["points"], dtype=float)
            segments = np.array(line["angle_deg"], dtype=float)
            if line["kind"] == "loop":
                loops += 1
                want = np.vstack([want, want[:1]])  # closed: the first point again
            # Point k takes segment k (the one it starts); the last point the last segment (of
            # an open line the one ending there, of a loop the closing one).
            per_point = np.append(segments, segments[-1:])
            assert len(ids) == len(want), (frame["frame"], j)
            assert np.array_equal(points[ids, :2], want)
            assert np.all(points[ids, 2] == 0.0)
            assert np.array_equal(angle[ids], per_point)
            assert np.array_equal(char[ids], character(per_point))
            assert np.all(line_id[ids] == line["id"])
            assert np.all(burgers[ids] == [line["burgers_x"], line["burgers_y"], 0.0])
            assert vtk_to_numpy(cd.GetArray("line_id"))[j] == line["id"]
            assert vtk_to_numpy(cd.GetArray("kind"))[j] == KINDS[line["kind"]]
            assert vtk_to_numpy(cd.GetArray("burgers_x"))[j] == line["burgers_x"]
            assert vtk_to_numpy(cd.GetArray("burgers_y"))[j] == line["burgers_y"]
    # The slip the fixture tracks has lines, and loops among them: the check saw them.
    assert total_lines > 0 and loops > 0, (total_lines, loops)
