// Extended XYZ snapshots; see xyz_io.hpp.
#include "asperity/apps/common/xyz_io.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/snapshot_io.hpp"

namespace asperity::app {

namespace {

// Shortest text that reads back to the value (std::to_chars), of the float the NetCDF file holds
// when the format is single precision: "to round-off" then means "bit for bit" against that
// file, and a 9-digit float text is shorter than a 17-digit double one.
void put_number(std::string& out, double v, bool single) {
  char buf[32];
  const auto r = single ? std::to_chars(buf, buf + sizeof buf, static_cast<float>(v))
                        : std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// ASE's and OVITO's comment-line parsers split on blanks and '=' and take '"' as a quote: a key
// must be a plain word, and a text value is quoted with its quotes and backslashes escaped.
bool plain_key(const std::string& key) {
  if (key.empty()) return false;
  for (const char c : key) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') q += '\\';
    q += (c == '\n' ? ' ' : c);
  }
  return q + "\"";
}

void check_sizes(const slide::Snapshot& s) {
  const std::size_t n = s.block.shape.count();
  for (const auto* f : {&s.ux, &s.uy, &s.sx, &s.sy, &s.tau_x, &s.tau_y, &s.tau_max, &s.pressure}) {
    if (f->size() != n) {
      throw std::invalid_argument("extended XYZ frame \"" + s.label + "\": a field has " +
                                  std::to_string(f->size()) + " values for " + std::to_string(n) +
                                  " block sites");
    }
  }
  if ((!s.uz.empty() && s.uz.size() != n) || (!s.in_contact.empty() && s.in_contact.size() != n)) {
    throw std::invalid_argument("extended XYZ frame \"" + s.label +
                                "\": uz or in_contact does not have one value per block site");
  }
}

// round(rho), rho = s / d in lattice units (d = 1 in the snapshots) or, under a tip out of
// registry, the registry coordinate along a tip axis (tip_lattice.hpp), as the slider counts slips.
long registry_index(double rho) {
  return std::lround(rho);
}

}  // namespace

std::string extended_xyz_frame(const slide::Snapshot& s, const nlohmann::json& attributes,
                               bool single) {
  check_sizes(s);
  const auto& blk = s.block;
  const int n0 = blk.shape.n0, n1 = blk.shape.n1;
  const bool has_uz = !s.uz.empty();
  std::string out = std::to_string(blk.shape.count()) + "\n";
  out += "Lattice=\"" + std::to_string(n0) + " 0 0 0 " + std::to_string(n1) + " 0 0 0 1\"";
  out += " Origin=\"";
  put_number(out, blk.origin0 - 0.5, false);
  out += ' ';
  put_number(out, blk.origin1 - 0.5, false);
  out += " -0.5\" pbc=\"F F F\"";
  out +=
      " Properties=species:S:1:pos:R:3:ux:R:1:uy:R:1:sx:R:1:sy:R:1:tau_x:R:1:tau_y:R:1:"
      "tau_max:R:1:pressure:R:1";
  if (has_uz) out += ":uz:R:1";
  out += ":in_contact:I:1:registry_x:I:1:registry_y:I:1";
  out += " label=" + quoted(s.label) + " iteration=" + std::to_string(s.iteration);
  for (const auto& [key, value] :
       {std::pair{"Dx", s.Dx}, {"Fx", s.Fx}, {"Fz", s.Fz}, {"energy", s.energy}}) {
    out += std::string(" ") + key + "=";
    put_number(out, value, false);  // per frame: double in the NetCDF file too
  }
  out += " origin_x=" + std::to_string(blk.origin0) + " origin_y=" + std::to_string(blk.origin1);
  out += " tip_angle=";
  put_number(out, s.tip.angle, false);
  out += " tip_mismatch=";
  put_number(out, s.tip.mismatch, false);
  const interface::TipFrame frame(s.tip, 1.0);
  if (attributes.is_object()) {
    for (const auto& [key, value] : attributes.items()) {
      if (!plain_key(key) || value.is_structured() || value.is_null()) continue;
      static constexpr std::string_view frame_keys[] = {
          "label",    "iteration", "Dx",     "Fx",  "Fz",         "energy",    "origin_x",
          "origin_y", "Lattice",   "Origin", "pbc", "Properties", "tip_angle", "tip_mismatch"};
      if (std::find(std::begin(frame_keys), std::end(frame_keys), key) != std::end(frame_keys))
        continue;
      out += " " + key + "=";
      if (value.is_string()) {
        out += quoted(value.get<std::string>());
      } else if (value.is_boolean()) {
        out += value.get<bool>() ? "T" : "F";
      } else if (value.is_number_integer()) {
        out += std::to_string(value.get<long long>());
      } else {
        put_number(out, value.get<double>(), false);
      }
    }
  }
  out += '\n';
  for (int i0 = 0; i0 < n0; ++i0) {
    for (int i1 = 0; i1 < n1; ++i1) {
      const std::size_t i = static_cast<std::size_t>(i0) * static_cast<std::size_t>(n1) +
                            static_cast<std::size_t>(i1);
      // The position is computed from the stored (rounded) displacement, so that pos - X is
      // the file's ux to round-off.
      const double ux = single ? static_cast<float>(s.ux[i]) : s.ux[i];
      const double uy = single ? static_cast<float>(s.uy[i]) : s.uy[i];
      out += "X ";
      put_number(out, blk.x(i0, 1.0) + ux, false);
      out += ' ';
      put_number(out, blk.y(i1, 1.0) + uy, false);
      out += ' ';
      if (has_uz) {
        put_number(out, s.uz[i], single);
      } else {
        out += '0';
      }
      for (const auto* f :
           {&s.ux, &s.uy, &s.sx, &s.sy, &s.tau_x, &s.tau_y, &s.tau_max, &s.pressure}) {
        out += ' ';
        put_number(out, (*f)[i], single);
      }
      if (has_uz) {
        out += ' ';
        put_number(out, s.uz[i], single);
      }
      const double sx = single ? static_cast<float>(s.sx[i]) : s.sx[i];
      const double sy = single ? static_cast<float>(s.sy[i]) : s.sy[i];
      // The registry coordinates in the tip's frame (s / d for the aligned tip).
      double rho1 = 0.0, rho2 = 0.0;
      frame.registry(sx, sy, rho1, rho2);
      out += ' ' + std::to_string(s.in_contact.empty() ? 1 : int{s.in_contact[i]});
      out +=
          ' ' + std::to_string(registry_index(rho1)) + ' ' + std::to_string(registry_index(rho2));
      out += '\n';
    }
  }
  return out;
}

void write_extended_xyz(const std::filesystem::path& xyz,
                        const std::vector<slide::Snapshot>& frames,
                        const nlohmann::json& attributes, bool single) {
  std::string text;
  for (const auto& f : frames)
    text += extended_xyz_frame(f, attributes, single);
  write_file_atomic(xyz, text);
}

std::size_t convert_snapshots_to_xyz(const std::filesystem::path& nc,
                                     const std::filesystem::path& xyz,
                                     const nlohmann::json& attributes, bool single) {
  const SnapshotAppender in = SnapshotAppender::open(nc);
  TemporaryFile tmp(xyz);
  {
    std::ofstream out(tmp.path(), std::ios::binary);
    for (std::size_t k = 0; k < in.frames(); ++k)
      out << extended_xyz_frame(in.read(k), attributes, single);
    out.flush();
    if (!out) throw std::runtime_error(xyz.string() + ": cannot write the extended XYZ frames");
  }
  tmp.commit();
  return in.frames();
}

}  // namespace asperity::app
