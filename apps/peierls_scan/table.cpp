// peierls.csv: one row per (b_core, angle), rewritten after every finished point, and read back
// by a later run with the same settings, which keeps its rows instead of recomputing them.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "asperity/apps/common/output_files.hpp"
#include "scan_io.hpp"

namespace asperity::app::peierls_scan {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string>& columns() {
  static const std::vector<std::string> c = {"b_core",
                                             "theta_deg",
                                             "m_x",
                                             "m_y",
                                             "L",
                                             "L_change",
                                             "L_converged",
                                             "model",
                                             "tau_P_over_tau_max_pos",
                                             "tau_P_over_tau_max_neg",
                                             "resolved_pos",
                                             "resolved_neg",
                                             "floor_over_tau_max",
                                             "core_width",
                                             "core_width_continuum",
                                             "rigid_pn_estimate",
                                             "iterations",
                                             "transforms",
                                             "undetermined",
                                             "failure",
                                             "wall_s",
                                             "settings"};
  return c;
}

std::vector<app::CsvTable::Cell> cells(const Row& r, const Scene& s) {
  // An unresolved threshold is an empty cell, never a number; its floor is in its own column.
  const auto tau = [](bool ok, double v) -> app::CsvTable::Cell {
    return ok ? app::CsvTable::Cell{v} : app::CsvTable::Cell{std::string()};
  };
  return {r.point.b_core,
          r.point.orientation.theta_deg,
          static_cast<long long>(r.point.orientation.mx),
          static_cast<long long>(r.point.orientation.my),
          static_cast<long long>(r.L),
          r.L_change,
          static_cast<long long>(r.L_converged),
          peierls::to_string(s.options.cell.model),
          tau(r.resolved_pos, r.tau_pos),
          tau(r.resolved_neg, r.tau_neg),
          static_cast<long long>(r.resolved_pos),
          static_cast<long long>(r.resolved_neg),
          r.floor,
          r.core_width,
          r.core_width_continuum,
          r.rigid,
          r.iterations,
          r.transforms,
          r.undetermined,
          r.failure,
          r.wall_s,
          r.settings};
}

}  // namespace

void write_table(const fs::path& csv, const std::vector<std::optional<Row>>& rows, const Scene& s) {
  app::CsvTable t(columns());
  for (const auto& r : rows) {
    if (r) t.add_row(cells(*r, s));
  }
  t.write(csv);
}

std::size_t resume(const fs::path& csv, const std::vector<peierls::ScanPoint>& points,
                   const std::string& settings, std::vector<std::optional<Row>>& rows) {
  if (!fs::exists(csv)) return 0;
  const app::CsvTable t = app::CsvTable::read(csv);
  // A table of an older version of the tool (other columns) is started over.
  for (const std::string& c : columns()) {
    if (std::find(t.columns().begin(), t.columns().end(), c) == t.columns().end()) {
      std::fprintf(stderr,
                   "peierls_scan: %s has no column '%s' (an older version): starting over\n",
                   csv.c_str(), c.c_str());
      return 0;
    }
  }
  std::size_t reused = 0;
  const auto number_or_nan = [&t](std::size_t i, const char* c) {
    const std::string text = t.text(i, c);
    return text.empty() ? NAN : t.number(i, c);
  };
  for (std::size_t i = 0; i < t.rows(); ++i) {
    // A failed point is computed again (it may have been an interrupted machine's fault).
    if (t.text(i, "settings") != settings || !t.text(i, "failure").empty()) continue;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const peierls::ScanPoint& p = points[k];
      if (rows[k] || t.number(i, "b_core") != p.b_core || t.integer(i, "m_x") != p.orientation.mx ||
          t.integer(i, "m_y") != p.orientation.my)
        continue;
      Row r;
      r.point = p;
      r.L = static_cast<int>(t.integer(i, "L"));
      r.L_change = number_or_nan(i, "L_change");
      r.L_converged = t.integer(i, "L_converged") != 0;
      r.resolved_pos = t.integer(i, "resolved_pos") != 0;
      r.resolved_neg = t.integer(i, "resolved_neg") != 0;
      r.tau_pos = number_or_nan(i, "tau_P_over_tau_max_pos");
      r.tau_neg = number_or_nan(i, "tau_P_over_tau_max_neg");
      r.floor = t.number(i, "floor_over_tau_max");
      r.core_width = t.number(i, "core_width");
      r.core_width_continuum = t.number(i, "core_width_continuum");
      r.rigid = t.number(i, "rigid_pn_estimate");
      r.iterations = t.integer(i, "iterations");
      r.transforms = t.integer(i, "transforms");
      r.undetermined = t.integer(i, "undetermined");
      r.wall_s = t.number(i, "wall_s");
      r.settings = settings;
      rows[k] = r;
      ++reused;
    }
  }
  return reused;
}

std::string encode_row(const Row& r) {
  app::ByteWriter out;
  out.integer(r.L).real(r.L_change).integer(r.L_converged);
  out.integer(r.resolved_pos).integer(r.resolved_neg).real(r.tau_pos).real(r.tau_neg);
  out.real(r.floor).real(r.core_width).real(r.core_width_continuum).real(r.rigid);
  out.integer(r.iterations).integer(r.transforms).integer(r.undetermined).text(r.failure);
  out.real(r.wall_s).text(r.settings);
  return out.bytes();
}

Row decode_row(const peierls::ScanPoint& point, std::string_view bytes) {
  app::ByteReader in(bytes);
  Row r;
  r.point = point;
  r.L = static_cast<int>(in.integer());
  r.L_change = in.real();
  r.L_converged = in.integer() != 0;
  r.resolved_pos = in.integer() != 0;
  r.resolved_neg = in.integer() != 0;
  r.tau_pos = in.real();
  r.tau_neg = in.real();
  r.floor = in.real();
  r.core_width = in.real();
  r.core_width_continuum = in.real();
  r.rigid = in.real();
  r.iterations = in.integer();
  r.transforms = in.integer();
  r.undetermined = in.integer();
  r.failure = in.text();
  r.wall_s = in.real();
  r.settings = in.text();
  in.finish();
  return r;
}

std::string point_name(const peierls::ScanPoint& p) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "b%g_m%d_%d", p.b_core, p.orientation.mx, p.orientation.my);
  return buf;
}

}  // namespace asperity::app::peierls_scan
