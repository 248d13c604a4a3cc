// Dislocation lines as legacy VTK polylines; see vtk_lines.hpp.
#include "asperity/apps/common/vtk_lines.hpp"

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "asperity/apps/common/output_files.hpp"

namespace asperity::app {

namespace {

// Shortest text that reads back to the same double: lines.json has the same digits.
void put(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// The segment angle that stands for point k of a line drawn with `n` points (a closed line's
// first point repeated at the end).
double point_angle(const VtkPolyline& l, std::size_t k) {
  return l.angle_deg[std::min(k, l.angle_deg.size() - 1)];
}

}  // namespace

int line_character(double angle_deg) {
  return angle_deg < 30.0 ? 0 : (angle_deg > 60.0 ? 2 : 1);
}

std::string vtk_lines_text(const VtkLinesFrame& f) {
  std::size_t n_points = 0;
  for (const auto& l : f.lines) {
    const std::size_t segments = l.closed ? l.points.size() : l.points.size() - 1;
    if (l.points.size() < 2 || l.angle_deg.size() != segments) {
      throw std::invalid_argument("VTK lines of frame " + std::to_string(f.frame) + ": line " +
                                  std::to_string(l.id) + " has " + std::to_string(l.points.size()) +
                                  " points and " + std::to_string(l.angle_deg.size()) +
                                  " segment angles");
    }
    n_points += l.points.size() + (l.closed ? 1 : 0);
  }
  std::string title = f.title.substr(0, 255);
  for (char& c : title)
    if (c == '\n' || c == '\r') c = ' ';
  std::string out = "# vtk DataFile Version 3.0\n" + title + "\nASCII\nDATASET POLYDATA\n";
  out += "FIELD FieldData 3\nframe 1 1 int\n" + std::to_string(f.frame) + "\niteration 1 1 int\n" +
         std::to_string(f.iteration) + "\nDx 1 1 double\n";
  put(out, f.Dx);
  out += "\nPOINTS " + std::to_string(n_points) + " double\n";
  for (const auto& l : f.lines) {
    const std::size_t n = l.points.size() + (l.closed ? 1 : 0);
    for (std::size_t k = 0; k < n; ++k) {
      const auto& p = l.points[k % l.points.size()];
      put(out, p[0]);
      out += ' ';
      put(out, p[1]);
      out += " 0\n";
    }
  }
  // Per point, in the order of POINTS.
  const auto per_point = [&](const std::string& header, auto value) {
    out += header;
    for (const auto& l : f.lines) {
      const std::size_t n = l.points.size() + (l.closed ? 1 : 0);
      for (std::size_t k = 0; k < n; ++k) {
        value(l, k);
        out += '\n';
      }
    }
  };
  if (!f.lines.empty()) {
    std::size_t size = 0;
    for (const auto& l : f.lines)
      size += l.points.size() + (l.closed ? 2 : 1);
    out += "LINES " + std::to_string(f.lines.size()) + " " + std::to_string(size) + "\n";
    std::size_t first = 0;
    for (const auto& l : f.lines) {
      const std::size_t n = l.points.size() + (l.closed ? 1 : 0);
      out += std::to_string(n);
      for (std::size_t k = 0; k < n; ++k)
        out += ' ' + std::to_string(first + k);
      out += '\n';
      first += n;
    }
    // One SCALARS and one VECTORS at most, the rest as FIELD arrays: vtkPolyDataReader with its
    // defaults reads only the first SCALARS of a section, and every FIELD array.
    const std::string cells = std::to_string(f.lines.size()), points = std::to_string(n_points);
    out += "CELL_DATA " + cells + "\nSCALARS line_id int 1\nLOOKUP_TABLE default\n";
    for (const auto& l : f.lines)
      out += std::to_string(l.id) + '\n';
    // Per cell, in the order of LINES: a FIELD array of doubles.
    const auto per_cell = [&](const std::string& name, auto value) {
      out += name + " 1 " + cells + " double\n";
      for (const auto& l : f.lines) {
        put(out, value(l));
        out += '\n';
      }
    };
    out += "FIELD FieldData 4\nkind 1 " + cells + " int\n";
    for (const auto& l : f.lines)
      out += std::to_string(l.kind) + '\n';
    per_cell("burgers_x", [](const VtkPolyline& l) { return l.burgers_x; });
    per_cell("burgers_y", [](const VtkPolyline& l) { return l.burgers_y; });
    per_cell("length", [](const VtkPolyline& l) { return l.length; });
    out += "POINT_DATA " + points + "\n";
    per_point("SCALARS character int 1\nLOOKUP_TABLE default\n",
              [&](const VtkPolyline& l, std::size_t k) {
                out += std::to_string(line_character(point_angle(l, k)));
              });
    per_point("VECTORS burgers double\n", [&](const VtkPolyline& l, std::size_t) {
      put(out, l.burgers_x);
      out += ' ';
      put(out, l.burgers_y);
      out += " 0";
    });
    out += "FIELD FieldData 3\n";
    per_point(("angle_deg 1 " + points + " double\n"),
              [&](const VtkPolyline& l, std::size_t k) { put(out, point_angle(l, k)); });
    per_point(("line_id 1 " + points + " int\n"),
              [&](const VtkPolyline& l, std::size_t) { out += std::to_string(l.id); });
    per_point(("kind 1 " + points + " int\n"),
              [&](const VtkPolyline& l, std::size_t) { out += std::to_string(l.kind); });
  }
  return out;
}

void write_vtk_lines(const std::filesystem::path& vtk, const VtkLinesFrame& frame) {
  write_file_atomic(vtk, vtk_lines_text(frame));
}

}  // namespace asperity::app
