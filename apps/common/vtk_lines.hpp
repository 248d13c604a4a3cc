// Dislocation lines (track_loops) as VTK polylines, legacy ASCII (.vtk), which ParaView and
// VTK's vtkPolyDataReader open with no plug-in; lines.json stays the complete record.
//
// One file per frame (track_loops: lines_NNNN.vtk beside lines.json, NNNN its frame index): a
// polyline has no time of its own, ParaView opens a numbered series of files as a time series
// by itself, and a frame whose lines change in number and length needs no padding. (A
// multi-block file would need VTK's XML formats and a .pvd to carry the frames' times; the
// legacy files need neither.) A frame without lines is a file with no points, so that the
// series has no holes.
//
// Per polyline (a line of the frame, in lines.json order; a loop closed by repeating its first
// point at the end), per point:
//   angle_deg  angle between the line and b of the segment that starts at the point (the last
//              point of an open line: of the segment that ends there), folded into [0, 90]:
//              0 screw, 90 edge;
//   character  0 screw (angle < 30), 1 mixed, 2 edge (angle > 60): the classes of the figures;
//   line_id    the tracker's id, the same across frames (lines.json "id", events.csv);
//   kind       0 loop, 1 open, 2 wrapping (tracking::LineKind);
//   burgers    the Burgers vector (burgers_x, burgers_y, 0) in d (VECTORS): d_tip along the
//              tip's first axis per unit of lines.json's integer `burgers`, (d, 0) aligned;
// per cell (polyline): line_id, kind, burgers_x, burgers_y, length (d). Field data: frame,
// iteration, Dx.
// `character` and `line_id` are the active scalars of the points and cells (what ParaView colours
// by at first), `burgers` the active vectors; the others are FIELD arrays of the same sections,
// which vtkPolyDataReader reads with its defaults (it reads only the first SCALARS).
// Points in d at z = 0: the plane of the substrate sites, as the extended XYZ snapshots.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace asperity::app {

struct VtkPolyline {
  int id = 0;
  int kind = 0;                                           // 0 loop, 1 open, 2 wrapping
  bool closed = false;                                    // the last point joins the first (loops)
  double burgers_x = 0.0, burgers_y = 0.0, length = 0.0;  // b (d); length (d)
  std::vector<std::array<double, 2>> points;
  // Per segment: points[k] -> points[k + 1], and for a closed line also the closing one.
  std::vector<double> angle_deg;
};

struct VtkLinesFrame {
  int frame = 0, iteration = -1;
  double Dx = 0.0;
  std::string title;  // the file's header line (cut to 255 characters, one line)
  std::vector<VtkPolyline> lines;
};

// The character class of a segment at `angle_deg` (0 screw, 1 mixed, 2 edge).
int line_character(double angle_deg);

// The file's text. Throws std::invalid_argument if a line's segment angles do not match its
// points (points - 1 for an open line, points for a closed one) or a line has under 2 points.
std::string vtk_lines_text(const VtkLinesFrame& frame);

// Writes vtk_lines_text atomically. Throws as vtk_lines_text, std::runtime_error naming the file
// if writing fails.
void write_vtk_lines(const std::filesystem::path& vtk, const VtkLinesFrame& frame);

}  // namespace asperity::app
