// Sweep scene, points and results table of friction_sweep; see sweep.hpp.
#include "sweep.hpp"
#include "asperity/core/common/line_fit.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <tuple>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/mpi_points.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/slide_checkpoint.hpp"
#include "asperity/apps/common/toml_reader.hpp"
#include "asperity/core/common/line_fit.hpp"
#include "asperity/core/contact/hertz.hpp"

namespace asperity::app {
namespace {

// Limits of contact.a in a slide scene (slide_io.cpp), applied to every point.
// The allowed contact radii: contact.a's range (interface::ContactScene::settings()).
const settings::Range& a_range() {
  static const settings::Range r =
      settings::find(interface::ContactScene::settings(), "contact.a")->range;
  return r;
}

// Shortest form that reads back to the same double: fingerprints compare exactly.
using settings::format_number;

// The allowed values of a contact setting (interface::ContactScene::settings()).
Range contact_range(const char* key) {
  return settings::find(interface::ContactScene::settings(), key)->range;
}

std::string element(const ValueList& list, std::size_t i) {
  return list.key + "[" + std::to_string(i) + "]";
}

bool close(double x, double y) {
  return std::abs(x - y) <= 1e-9 * std::max(std::abs(x), std::abs(y));
}

// Each value is checked by its row (SweepScene::settings(): finite, > 0); what a row cannot say
// is that its list must not be empty.
void check_list(const ValueList& list) {
  if (list.values.empty()) {
    throw std::invalid_argument(list.key + ": missing or empty: give at least one value");
  }
}

// A list row over a ValueList (`optional`: absent when empty), named by its key in messages.
template <class Ref>
settings::Setting<SweepScene> list_row(std::string key, Ref ref, std::string unit,
                                       std::string meaning, std::string flag,
                                       Range range = Range::positive()) {
  settings::Setting<SweepScene> s;
  static_cast<settings::Info&>(s) = {std::move(key),  settings::Kind::numbers, range,          {},
                                     std::move(unit), std::move(meaning),      std::move(flag)};
  s.get = [ref](const SweepScene& r) {
    const auto& list = ref(r);
    if constexpr (requires { list.has_value(); }) {
      return settings::Value(list ? list->values : std::vector<double>{});
    } else {
      return settings::Value(list.values);
    }
  };
  s.set = [ref, key = s.key](SweepScene& r, const settings::Value& v) {
    auto& list = ref(r);
    const auto& values = std::get<std::vector<double>>(v);
    if constexpr (requires { list.reset(); }) {
      if (values.empty()) {
        list.reset();
      } else {
        list = ValueList{values, key};
      }
    } else {
      list = ValueList{values, key};
    }
  };
  return s;
}

}  // namespace

const settings::Table<SweepScene>& SweepScene::settings() {
  static const settings::Table<SweepScene> table = [] {
    settings::Table<SweepScene> t = {
        list_row(
            "sweep.R", [](auto& s) -> auto& { return s.R; }, "d", "sphere radii", "--R"),
        list_row(
            "sweep.a", [](auto& s) -> auto& { return s.a; }, "d",
            "contact radii (exactly one of sweep.a and sweep.a_over_bcore0)", "--a"),
        list_row(
            "sweep.a_over_bcore0", [](auto& s) -> auto& { return s.a_over_bcore0; }, "",
            "targets of the control parameter a/b_core^0 (instead of sweep.a)", "--a-over-bcore0"),
        settings::neutral(settings::integer<SweepScene>(
            "sweep.jobs", [](auto& s) -> auto& { return s.jobs; }, Range::closed(0, 1024), "",
            "points run at once, on each MPI rank (0: hardware threads / fft.threads, a host's "
            "shared among its ranks)",
            "--jobs")),
        settings::choice<SweepScene>(
            "sweep.model", [](auto& s) -> auto& { return s.model; }, {"lfm", "explicit", "both"},
            "which models run the points: the lateral force model (sweep.csv), the explicit "
            "tip (sweep_explicit.csv) or both"),
        // The tip's lattice per point (issue 27), in the ranges of contact.tip_angle and
        // contact.tip_mismatch; absent: the scene's contact value for every point.
        list_row(
            "sweep.tip_angle", [](auto& s) -> auto& { return s.tip_angle; }, "degrees",
            "rotations of the tip's lattice (instead of contact.tip_angle)", "--tip-angles",
            contact_range("contact.tip_angle")),
        list_row(
            "sweep.tip_mismatch", [](auto& s) -> auto& { return s.tip_mismatch; }, "",
            "lattice mismatches of the tip (instead of contact.tip_mismatch)", "--tip-mismatches",
            contact_range("contact.tip_mismatch")),
    };
    settings::lift(
        t, explicit_model::ExplicitScene::settings(), "",
        [](auto& s) -> auto& { return s.potential; });
    return t;
  }();
  return table;
}

nlohmann::json SweepScene::settings_echo() const {
  nlohmann::json out = app::settings_echo(base, SlideScene::settings(), point_keys());
  out.update(app::settings_echo(*this, settings()));
  return out;
}

void SweepScene::validate() const {
  settings::validate(*this, settings());
  const auto& envelope = base.contact.envelope;
  if (runs_explicit() && envelope != "hertz") {
    throw std::invalid_argument("sweep.model = \"" + model + "\": allowed: \"lfm\" with " +
                                "contact.envelope = \"" + envelope +
                                "\" (the explicit model's interface is its tip, MODEL.md 4)");
  }
  // The adhesive envelope has no sphere: its points may go without radii.
  if (base.contact.carries_load() || !R.values.empty()) check_list(R);
  if (a && a_over_bcore0) {
    throw std::invalid_argument(a->key + " and " + a_over_bcore0->key +
                                ": give exactly one of them (contact radii or targets of "
                                "a/b_core^0)");
  }
  if (!a && !a_over_bcore0) {
    throw std::invalid_argument(
        "[sweep]: missing a or a_over_bcore0: give exactly one of them (contact radii (d) or "
        "targets of a/b_core^0)");
  }
  check_list(a ? *a : *a_over_bcore0);
}

std::vector<double> SweepScene::radii() const {
  if (!R.values.empty()) return R.values;
  return {interface::ContactScene{}.R};
}

int SweepScene::effective_jobs(int hardware_threads) const {
  if (jobs > 0) return jobs;
  // hardware_concurrency() may be 0 when unknown.
  return std::max(1, hardware_threads / base.options.fft.threads);
}

SweepScene read_sweep_scene(const std::string& path, bool check_slips) {
  auto r = SceneReader::from_file(path);
  // Each point sets a and R; a value given here would be silently replaced.
  for (const char* key : {"contact.a", "contact.R"}) {
    if (r.has(key)) {
      throw std::invalid_argument(path + ": " + key +
                                  ": not allowed in a sweep scene: the points take a and R from "
                                  "[sweep] (R, and a or a_over_bcore0)");
    }
  }
  SweepScene s;
  s.source = path;
  const bool tip_angle = r.has("contact.tip_angle");
  const bool tip_mismatch = r.has("contact.tip_mismatch");
  s.base = read_slide_scene(r, check_slips);
  r.read(SweepScene::settings(), s);
  r.reject_unknown();
  // A value the points would silently replace.
  for (const auto& [given, list, key] :
       {std::tuple{tip_angle, s.tip_angle.has_value(), "tip_angle"},
        std::tuple{tip_mismatch, s.tip_mismatch.has_value(), "tip_mismatch"}}) {
    if (given && list) {
      throw std::invalid_argument(path + ": contact." + key + " and sweep." + key +
                                  ": give one of them (one value for every point, or a list)");
    }
  }
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());  // named by the file, as the reader does
  }
  return s;
}

double contact_radius_for(const interface::ContactScene& c, double target) {
  return c.radius_for(target);
}

std::vector<interface::TipLattice> sweep_tips(const SweepScene& s) {
  const interface::TipLattice base = s.base.contact.tip;
  std::vector<interface::TipLattice> tips;
  for (double angle : s.tip_angle ? s.tip_angle->values : std::vector<double>{base.angle}) {
    for (double m : s.tip_mismatch ? s.tip_mismatch->values : std::vector<double>{base.mismatch})
      tips.push_back({.angle = angle, .mismatch = m});
  }
  return tips;
}

namespace {

// The order of sweep.csv: by tip (angle, then mismatch), R, then a.
bool point_before(const SweepPoint& p, const SweepPoint& q) {
  return std::tie(p.tip.angle, p.tip.mismatch, p.R, p.a) <
         std::tie(q.tip.angle, q.tip.mismatch, q.R, q.a);
}

// The points of one tip: each point's a and R, then every tip.
std::vector<SweepPoint> with_tips(const SweepScene& s, const std::vector<SweepPoint>& points) {
  std::vector<SweepPoint> out;
  for (const auto& tip : sweep_tips(s)) {
    for (SweepPoint p : points) {
      p.tip = tip;
      out.push_back(p);
    }
  }
  std::sort(out.begin(), out.end(), point_before);
  return out;
}

}  // namespace

std::vector<SweepPoint> sweep_points(const SweepScene& s) {
  s.validate();
  std::vector<SweepPoint> points;
  if (!s.runs_lfm()) return points;
  const std::vector<double> radii = s.radii();
  // Without a sphere (adhesive) a is bounded by its own range alone.
  const bool below_R = s.base.contact.carries_load();
  for (std::size_t j = 0; j < radii.size(); ++j) {
    interface::ContactScene c = s.base.contact;
    c.R = radii[j];
    const auto& list = s.a ? *s.a : *s.a_over_bcore0;
    for (std::size_t i = 0; i < list.values.size(); ++i) {
      const double v = list.values[i];
      const double a = s.a ? v : contact_radius_for(c, v);
      const double a_min = *a_range().lower, a_max = *a_range().upper;
      if (a_range().contains(a) && (!below_R || a < c.R)) {
        interface::ContactScene point = c;
        point.a = a;
        try {
          point.validate();
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument(element(s.R, j) + ": " + e.what());
        }
        points.push_back({a, c.R});
        continue;
      }
      const std::string with_R =
          !below_R ? std::string()
                   : " with R = " + format_number(c.R) + " d (" + element(s.R, j) + ")";
      const std::string and_R = below_R ? " and < R" : "";
      if (s.a) {
        throw std::invalid_argument(element(list, i) + " = " + format_number(v) + with_R +
                                    ": allowed: " + a_range().describe() + " d" + and_R);
      }
      // The same limits expressed in the target, which increases with a.
      const auto target_at = [&](double radius) {
        interface::ContactScene at = c;
        at.a = radius;
        return at.a_over_bcore0();
      };
      const bool capped = !below_R || a_max < c.R;
      char allowed[160];
      std::snprintf(allowed, sizeof allowed, "[%.6g, %.6g%s", target_at(a_min),
                    target_at(capped ? a_max : c.R), capped ? "]" : ")");
      throw std::invalid_argument(element(list, i) + " = " + format_number(v) + with_R +
                                  " needs a = " + format_number(a) + " d: allowed: " + allowed +
                                  " (a in " + a_range().describe() + " d" + and_R + ")");
    }
  }
  points = with_tips(s, points);
  std::set<std::string> folders;
  for (const auto& p : points) {
    if (!folders.insert(point_folder(p)).second) {
      throw std::invalid_argument("two points of the sweep share the folder points/" +
                                  point_folder(p) +
                                  " (equal to 6 significant digits): remove one from " +
                                  (s.a ? s.a->key : s.a_over_bcore0->key) + " or " + s.R.key);
    }
  }
  return points;
}

std::string point_folder(const SweepPoint& p, bool explicit_model) {
  char name[160];
  std::snprintf(name, sizeof name, "%sa%.6g_R%.6g", explicit_model ? "explicit_" : "", p.a, p.R);
  std::string folder = name;
  if (!p.tip.aligned()) {
    std::snprintf(name, sizeof name, "_angle%.6g_mismatch%.6g", p.tip.angle, p.tip.mismatch);
    folder += name;
  }
  return folder;
}

ExplicitSlideScene explicit_point_scene(const SweepScene& s, const SweepPoint& p) {
  ExplicitSlideScene e;
  e.slide = s.base;
  e.slide.contact.a = p.a;
  e.slide.contact.R = p.R;
  e.model = s.potential;
  e.slide.contact.tip = p.tip;
  e.model.R = p.R;
  e.model.material = s.base.contact.material;
  e.model.d = s.base.contact.d;
  e.model.tip = p.tip;
  return e;
}

std::vector<SweepPoint> explicit_sweep_points(const SweepScene& s) {
  s.validate();
  std::vector<SweepPoint> points;
  if (!s.runs_explicit()) return points;
  for (std::size_t j = 0; j < s.R.values.size(); ++j) {
    const double R = s.R.values[j];
    const auto& list = s.a ? *s.a : *s.a_over_bcore0;
    for (std::size_t i = 0; i < list.values.size(); ++i) {
      const double v = list.values[i];
      double a = v;
      if (!s.a) {
        // a = sqrt(x R d / (c alpha(a))): alpha of the potential at the central load of a.
        interface::ContactScene c = s.base.contact;
        c.R = R;
        c.alpha = 0.7;  // first guess; alpha_path gives 0.71-0.72 at sigma/d = 2^(-1/6)
        for (int round = 0; round < 3; ++round) {
          a = contact_radius_for(c, v);
          if (!(a >= *a_range().lower && a < 0.1 * R)) break;
          const double alpha = explicit_alpha(explicit_point_scene(s, {a, R})).alpha;
          if (!std::isfinite(alpha)) break;
          c.alpha = alpha;
        }
        a = contact_radius_for(c, v);
      }
      if (a_range().contains(a) && a < 0.1 * R) {
        try {
          explicit_point_scene(s, {a, R}).slide.contact.validate();
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument(element(s.R, j) + ": " + e.what());
        }
        points.push_back({a, R});
        continue;
      }
      const std::string with_R = " with R = " + format_number(R) + " d (" + element(s.R, j) + ")";
      throw std::invalid_argument(
          element(list, i) + " = " + format_number(v) + with_R +
          (s.a ? std::string() : " needs a = " + format_number(a) + " d, which") +
          " is outside the explicit model's range: a in " + a_range().describe() +
          " d and a/R < 0.1 (small "
          "slopes, MODEL.md 4): raise R");
    }
  }
  points = with_tips(s, points);
  for (const auto& p : points) {
    try {
      explicit_point_scene(s, p).model.validate();  // the tip's spacing against the cutoff
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(
          std::string(s.tip_mismatch ? "sweep.tip_mismatch" : "contact.tip_mismatch") + ": " +
          e.what());
    }
  }
  std::set<std::string> folders;
  for (const auto& p : points) {
    if (!folders.insert(point_folder(p, true)).second) {
      throw std::invalid_argument("two explicit points of the sweep share the folder points/" +
                                  point_folder(p, true) + " (equal to 6 significant digits)");
    }
  }
  return points;
}

// The settings that change a point's result (SlideScene::settings(); not a and R, which are the
// row's own columns, nor threads and output formats), exact, and the build: the code's own
// defaults are not all settings, so rows of another build are recomputed rather than trusted.
std::string settings_fingerprint(const SlideScene& scene) {
  return settings::fingerprint(
             scene, SlideScene::settings(), true,
             {"contact.a", "contact.R", "contact.tip_angle", "contact.tip_mismatch"}) +
         " code=" + app::provenance_string();
}

std::string explicit_settings_fingerprint(const SweepScene& s) {
  // contact.alpha is the LFM's: the explicit points take alpha from the potential.
  SlideScene base = s.base;
  base.contact.alpha = 0.0;
  return settings_fingerprint(base) + " model=explicit " +
         settings::fingerprint(s.potential, explicit_model::ExplicitScene::settings());
}

const std::vector<std::string>& sweep_columns() {
  static const std::vector<std::string> columns = {"a",
                                                   "R",
                                                   "alpha",
                                                   "nu",
                                                   "G",
                                                   "envelope",
                                                   "tau0",
                                                   "tip_angle",
                                                   "tip_mismatch",
                                                   "a_over_bcore0",
                                                   "lambda",
                                                   "mu",
                                                   "mu_over_alpha",
                                                   "tau_fric",
                                                   "tau_fric_over_tau0",
                                                   "friction_over_regime_one",
                                                   "area",
                                                   "mu_is_lower_bound",
                                                   "kinetic_over_alpha",
                                                   "kinetic_over_static",
                                                   "slip_events",
                                                   "distance",
                                                   "stop_reason",
                                                   "failed",
                                                   "steps",
                                                   "gf_applications",
                                                   "settings"};
  return columns;
}

namespace {

// sweep.csv without the columns issue 27 added: the envelopes' (G .. area) and the tip's
// lattice (tip_angle, tip_mismatch), which came on branches of their own.
std::vector<std::string> layout_without(bool envelopes, bool tip) {
  std::vector<std::string> old = sweep_columns();
  std::vector<const char*> drop;
  if (envelopes) {
    drop.insert(drop.end(), {"G", "envelope", "tau0", "tau_fric", "tau_fric_over_tau0",
                             "friction_over_regime_one", "area"});
  }
  if (tip) drop.insert(drop.end(), {"tip_angle", "tip_mismatch"});
  for (const char* c : drop)
    old.erase(std::find(old.begin(), old.end(), c));
  return old;
}

// Earlier layouts of sweep.csv: without the envelopes' or the tip's columns (or both), and
// before them with the wall times (since moved to summary.json).
bool is_earlier_layout(const std::vector<std::string>& columns) {
  for (const auto& [envelopes, tip] : {std::pair{true, true}, {true, false}, {false, true}}) {
    if (columns == layout_without(envelopes, tip)) return true;
  }
  std::vector<std::string> old = layout_without(true, true);
  old.insert(old.end() - 1, "wall_s");
  return columns == old;
}

// The envelope's friction over its Regime I value (SweepRow::relative_friction).
double relative_friction(const interface::ContactScene& c, const slide::SlideResult& r) {
  if (!c.uses_tau0()) return r.mu_over_alpha;
  if (!c.carries_load()) return r.tau_fric / c.tau0;
  return slide::friction_over_regime_one(c, r);
}

}  // namespace

namespace {
// The first cells of a row, in sweep_columns() order: the point's parameters (a .. lambda).
std::vector<CsvTable::Cell> parameter_cells(const interface::ContactScene& c) {
  return {c.a,    c.R,         c.alpha,        c.material.nu,     c.material.G, c.envelope,
          c.tau0, c.tip.angle, c.tip.mismatch, c.a_over_bcore0(), c.lambda()};
}
}  // namespace

SweepRow sweep_row(const SlideScene& scene, const slide::SlideResult& r,
                   const std::string& settings) {
  const auto& c = scene.contact;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SweepRow row{.point = {c.a, c.R},
               .envelope = c.envelope,
               .a_over_bcore0 = c.a_over_bcore0(),
               .mu_over_alpha = r.mu_over_alpha,
               .relative_friction = relative_friction(c, r),
               .kinetic_over_static = r.kinetic_over_static,
               .slip_events = r.slip_events,
               .mu_is_lower_bound = r.mu_is_lower_bound,
               .failed = r.failed,
               .stop_reason = r.stop_reason,
               .wall_s = r.wall_s};
  row.point.tip = c.tip;
  row.cells = parameter_cells(c);
  row.cells.insert(
      row.cells.end(),
      {r.mu, r.mu_over_alpha, r.tau_fric, c.uses_tau0() ? r.tau_fric / c.tau0 : nan,
       slide::friction_over_regime_one(c, r), r.area, static_cast<long long>(r.mu_is_lower_bound),
       c.carries_load() ? r.kinetic / c.alpha : nan, r.kinetic_over_static,
       static_cast<long long>(r.slip_events), r.distance, r.stop_reason,
       static_cast<long long>(r.failed), static_cast<long long>(r.steps),
       static_cast<long long>(r.gf_applications), settings});
  return row;
}

std::string encode_row(const SweepRow& r) {
  ByteWriter out;
  out.real(r.point.a).real(r.point.R).real(r.point.tip.angle).real(r.point.tip.mismatch);
  out.text(r.envelope).real(r.a_over_bcore0).real(r.mu_over_alpha).real(r.relative_friction);
  out.real(r.kinetic_over_static).integer(r.slip_events).integer(r.mu_is_lower_bound);
  out.integer(r.failed).text(r.stop_reason).real(r.wall_s);
  out.integer(static_cast<std::int64_t>(r.cells.size()));
  for (const auto& c : r.cells)
    out.cell(c);
  return out.bytes();
}

SweepRow decode_row(std::string_view bytes) {
  ByteReader in(bytes);
  SweepRow r;
  r.point.a = in.real();
  r.point.R = in.real();
  r.point.tip.angle = in.real();
  r.point.tip.mismatch = in.real();
  r.envelope = in.text();
  r.a_over_bcore0 = in.real();
  r.mu_over_alpha = in.real();
  r.relative_friction = in.real();
  r.kinetic_over_static = in.real();
  r.slip_events = static_cast<int>(in.integer());
  r.mu_is_lower_bound = in.integer() != 0;
  r.failed = in.integer() != 0;
  r.stop_reason = in.text();
  r.wall_s = in.real();
  const std::int64_t n = in.integer();
  if (n != static_cast<std::int64_t>(sweep_columns().size())) {
    throw std::runtime_error("a sweep row from another rank has " + std::to_string(n) +
                             " cells, not " + std::to_string(sweep_columns().size()));
  }
  for (std::int64_t i = 0; i < n; ++i)
    r.cells.push_back(in.cell());
  in.finish();
  return r;
}

SweepRow error_row(const SlideScene& scene, const std::string& message, double wall_s,
                   const std::string& settings) {
  const auto& c = scene.contact;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // One line per row keeps sweep.csv readable with line tools (gnuplot's messages have several).
  std::string reason = "error: " + message;
  for (std::size_t at; (at = reason.find('\n')) != std::string::npos;)
    reason.replace(at, 1, "; ");
  SweepRow row{.point = {c.a, c.R},
               .envelope = c.envelope,
               .a_over_bcore0 = c.a_over_bcore0(),
               .mu_over_alpha = nan,
               .relative_friction = nan,
               .kinetic_over_static = nan,
               .failed = true,
               .stop_reason = reason,
               .wall_s = wall_s};
  // In sweep_columns() order: the parameters, then no results.
  row.point.tip = c.tip;
  row.cells = parameter_cells(c);
  row.cells.insert(row.cells.end(), {nan, nan, nan, nan, nan, nan, 0LL, nan, nan, 0LL, nan, reason,
                                     1LL, 0LL, 0LL, settings});
  return row;
}

bool capped_lower_bound(bool mu_is_lower_bound, const std::string& stop_reason) {
  return mu_is_lower_bound &&
         (stop_reason == slide::kStopDistanceCap || stop_reason == slide::kStopSlipLimit);
}

namespace {

// The value of `key` among fingerprint items ("slide.max_slips=12"); NaN if none holds it.
double item_number(const std::vector<std::string>& items, const std::string& key) {
  const std::string prefix = key + "=";
  for (const auto& item : items) {
    if (!item.starts_with(prefix)) continue;
    double v = std::numeric_limits<double>::quiet_NaN();
    const char* first = item.data() + prefix.size();
    std::from_chars(first, item.data() + item.size(), v);
    return v;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Whether the settings of a row (`diff.removed`) raise, in these (`diff.added`), the limit that
// stopped it (stop_reason): a longer slide.max_distance for the cap (0, the default cap, is not
// compared), a larger or no slide.max_slips for the slip limit.
bool raises_limit(const FingerprintDifference& diff, const std::string& stop_reason) {
  const std::string key = stop_reason == slide::kStopDistanceCap ? "slide.max_distance"
                          : stop_reason == slide::kStopSlipLimit ? "slide.max_slips"
                                                                 : "";
  if (key.empty()) return false;
  const double then = item_number(diff.removed, key), now = item_number(diff.added, key);
  if (!(then > 0.0)) return false;
  if (key == "slide.max_slips" && now == 0.0) return true;  // no slip limit any more
  return now > then;
}

}  // namespace

ResumedRows resume_rows(const std::filesystem::path& csv, const std::vector<SweepPoint>& points,
                        const std::string& settings, bool adopt,
                        const std::function<bool(std::size_t)>& extendable) {
  ResumedRows out;
  out.rows.resize(points.size());
  out.extend.resize(points.size());
  if (!std::filesystem::exists(csv)) return out;
  const CsvTable t = CsvTable::read(csv);
  if (is_earlier_layout(t.columns())) {
    out.other_settings = t.rows();
    return out;
  }
  if (t.columns() != sweep_columns()) {
    std::string expected;
    for (const auto& name : sweep_columns())
      expected += (expected.empty() ? "" : ",") + name;
    throw std::invalid_argument(csv.string() +
                                ": not a sweep table of this friction_sweep (columns differ "
                                "from " +
                                expected + "): move it away or choose another --out");
  }
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double a = t.number(i, "a"), R = t.number(i, "R");
    const interface::TipLattice tip {
      .angle = t.number(i, "tip_angle"), .mismatch = t.number(i, "tip_mismatch")
    };
    // The tip's values are the scene's own, written exactly: they compare equal.
    const auto it = std::find_if(points.begin(), points.end(), [&](const SweepPoint& p) {
      return close(p.a, a) && close(p.R, R) && p.tip == tip;
    });
    if (it == points.end()) {
      ++out.not_requested;
      continue;
    }
    // A row of other settings is kept only when adopted (--adopt, adoptable items only).
    const std::string row_settings = t.text(i, "settings");
    const bool other = row_settings != settings;
    const FingerprintDifference diff =
        other ? fingerprint_difference(row_settings, settings) : FingerprintDifference{};
    if (other && !(adopt && diff.fixed.empty())) {
      ++out.other_settings;
      continue;
    }
    if (t.integer(i, "failed") != 0) {
      ++out.failed;
      continue;
    }
    const auto k = static_cast<std::size_t>(it - points.begin());
    if (other && extendable &&
        capped_lower_bound(t.integer(i, "mu_is_lower_bound") != 0, t.text(i, "stop_reason")) &&
        raises_limit(diff, t.text(i, "stop_reason")) && extendable(k)) {
      ++out.to_extend;
      out.extend[k] = true;
      continue;
    }
    auto& slot = out.rows[k];
    if (slot) continue;  // a repeated row (edited file): the first one stands
    const std::string envelope = t.text(i, "envelope");
    SweepRow row{
        .point = {a, R},
        .envelope = envelope,
        .a_over_bcore0 = t.number(i, "a_over_bcore0"),
        .mu_over_alpha = t.number(i, "mu_over_alpha"),
        .relative_friction = t.number(i, envelope == "hertz"      ? "mu_over_alpha"
                                         : envelope == "adhesive" ? "tau_fric_over_tau0"
                                                                  : "friction_over_regime_one"),
        .kinetic_over_static = t.number(i, "kinetic_over_static"),
        .slip_events = static_cast<int>(t.integer(i, "slip_events")),
        .mu_is_lower_bound = t.integer(i, "mu_is_lower_bound") != 0,
        .failed = false,
        .stop_reason = t.text(i, "stop_reason"),
        .wall_s = std::numeric_limits<double>::quiet_NaN()};
    row.point.tip = tip;
    // The stored text, not re-formatted numbers: a resumed table is byte-identical.
    for (std::size_t j = 0; j < t.columns().size(); ++j)
      row.cells.push_back(t.cell(i, j));
    slot = std::move(row);
    ++out.reused;
    if (other) ++out.adopted;
  }
  return out;
}

std::string relative_friction_name(const std::string& envelope) {
  if (envelope == "adhesive") return "tau_fric/tau0";
  if (envelope == "mixed") return "Fx/(alpha Fz + tau0 A)";
  return "mu/alpha";
}

double regime_two_slope(const std::string& envelope) {
  if (envelope == "adhesive") return -0.5;
  if (envelope == "mixed") return std::numeric_limits<double>::quiet_NaN();
  return -2.0 / 3.0;
}

nlohmann::json fit_slope(const std::vector<SweepRow>& rows, double lo, double hi,
                         const std::string& envelope) {
  std::vector<double> x, y;
  for (const auto& r : rows) {
    if (r.failed || r.mu_is_lower_bound || !(r.relative_friction > 0.0)) continue;
    if (r.a_over_bcore0 < lo || r.a_over_bcore0 > hi) continue;
    x.push_back(std::log(r.a_over_bcore0));
    y.push_back(std::log(r.relative_friction));
  }
  const double law_slope = regime_two_slope(envelope);
  nlohmann::json fit = {
      {"quantity",
       "log(" + relative_friction_name(envelope) + ") = log(prefactor) + slope log(a/b_core^0)"},
      {"window", {lo, hi}},
      {"points", x.size()},
      {"regime_ii_slope", std::isfinite(law_slope) ? nlohmann::json(law_slope) : nlohmann::json()}};
  const LineFit line = fit_line(x, y);
  // Points at a single a/b_core^0 (several R, one target) fix no slope.
  if (x.size() < 2 || !(line.sxx > 1e-12 * static_cast<double>(line.n))) {
    fit["slope"] = nullptr;
    fit["note"] = "needs points at 2 or more distinct a/b_core^0 in the window";
    return fit;
  }
  fit["slope"] = line.slope;
  fit["prefactor"] = std::exp(line.intercept);
  if (x.size() > 2) {
    fit["slope_stderr"] = std::sqrt(line.slope_variance());
  } else {
    fit["slope_stderr"] = nullptr;  // two points: the line passes through both
  }
  return fit;
}

nlohmann::json compare_models(const std::vector<SweepRow>& lfm, const std::vector<SweepRow>& expl,
                              double lo, double hi) {
  const auto usable = [](const SweepRow& r) {
    return !r.failed && !r.mu_is_lower_bound && r.mu_over_alpha > 0.0 && r.a_over_bcore0 > 0.0;
  };
  // Equal targets meet to round-off only (the explicit a solves for alpha(a)).
  constexpr double kSame = 1e-6;
  nlohmann::json points = nlohmann::json::array();
  double worst = 0.0;
  std::size_t compared = 0;
  for (const auto& e : expl) {
    if (!usable(e)) continue;
    // The LFM rows of this R nearest below and above in a/b_core^0.
    const SweepRow* below = nullptr;
    const SweepRow* above = nullptr;
    for (const auto& l : lfm) {
      if (!usable(l) || !close(l.point.R, e.point.R)) continue;
      if (l.a_over_bcore0 <= e.a_over_bcore0 * (1.0 + kSame) &&
          (!below || l.a_over_bcore0 > below->a_over_bcore0)) {
        below = &l;
      }
      if (l.a_over_bcore0 >= e.a_over_bcore0 * (1.0 - kSame) &&
          (!above || l.a_over_bcore0 < above->a_over_bcore0)) {
        above = &l;
      }
    }
    nlohmann::json p = {{"a", e.point.a},
                        {"R", e.point.R},
                        {"a_over_bcore0", e.a_over_bcore0},
                        {"explicit", e.mu_over_alpha}};
    if (!below || !above) {
      p["lfm"] = p["ratio"] = nullptr;
    } else {
      double lfm_mu = below->mu_over_alpha;
      if (above->a_over_bcore0 > below->a_over_bcore0 * (1.0 + kSame)) {
        const double t = std::log(e.a_over_bcore0 / below->a_over_bcore0) /
                         std::log(above->a_over_bcore0 / below->a_over_bcore0);
        lfm_mu = std::exp((1.0 - t) * std::log(below->mu_over_alpha) +
                          t * std::log(above->mu_over_alpha));
      }
      const double ratio = e.mu_over_alpha / lfm_mu;
      p["lfm"] = lfm_mu;
      p["ratio"] = ratio;
      if (e.a_over_bcore0 >= lo * (1.0 - kSame) && e.a_over_bcore0 <= hi * (1.0 + kSame)) {
        worst = std::max(worst, std::abs(ratio - 1.0));
        ++compared;
      }
    }
    points.push_back(std::move(p));
  }
  return {{"quantity",
           "explicit mu/alpha over the LFM's at the same R and a/b_core^0 (log-log "
           "interpolation between LFM rows)"},
          {"window", {lo, hi}},
          {"points", points},
          {"compared_in_window", compared},
          {"max_deviation_in_window", compared > 0 ? nlohmann::json(worst) : nlohmann::json()}};
}

}  // namespace asperity::app
