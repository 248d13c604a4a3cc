// Checkpoint files of contact_slide; see slide_checkpoint.hpp.
#include "asperity/apps/common/slide_checkpoint.hpp"

#include <bit>
#include <charconv>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"

namespace asperity::app {
namespace {

using nlohmann::json;
constexpr const char* kFormat = "asperity contact_slide checkpoint";
// 2: h, dFz_dh and u_z of the explicit model; 3: cycle replay; 4: contact-site areas and the
// friction measure (issue 27: envelopes without load).
constexpr int kVersion = 4;
const char* const kByteOrder = std::endian::native == std::endian::little ? "little" : "big";
// Sites of a block: far above any scene (a <= 4096 d gives 8200^2), far below overflow.
constexpr long long kMaxSites = 1LL << 28;

// Deepest nesting a checkpoint has is 6 (root, state, pending slip, its frames, a frame, its
// fields); the limit only
// has to stop a damaged file from nesting arrays thousands deep, which would overflow the
// stack in the recursive CBOR reader (found by fuzz_checkpoint).
constexpr std::size_t kMaxDepth = 32;

// Builds the document from the reader's SAX events (the public json_sax interface; the
// library's own DOM builder is an internal class whose signature changes between versions),
// and stops the reader (returns false) at the first container past kMaxDepth instead of
// recursing further.
class DepthLimitedDom {
 public:
  explicit DepthLimitedDom(json& root) : root_(root) {}
  bool null() { return add(json(nullptr)); }
  bool boolean(bool v) { return add(json(v)); }
  bool number_integer(json::number_integer_t v) { return add(json(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return add(json(v)); }
  bool number_float(json::number_float_t v, const json::string_t&) { return add(json(v)); }
  bool string(json::string_t& v) { return add(json(std::move(v))); }
  bool binary(json::binary_t& v) { return add(json(std::move(v))); }
  bool start_object(std::size_t) { return open(json::object()); }
  bool key(json::string_t& k) {
    key_ = std::move(k);
    return true;
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_array() { return close(); }
  template <class Exception>
  bool parse_error(std::size_t, const std::string&, const Exception& e) {
    throw e;
  }
  bool too_deep() const { return too_deep_; }

 private:
  // Places a value where the reader is: the root, the next element of an array, or the value
  // of the last key of an object. Returns where it went.
  json* place(json&& v) {
    if (stack_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    json& parent = *stack_.back();
    if (parent.is_array()) {
      parent.push_back(std::move(v));
      return &parent.back();
    }
    json& slot = parent[key_];
    slot = std::move(v);
    return &slot;
  }
  bool add(json&& v) {
    place(std::move(v));
    return true;
  }
  bool open(json&& container) {
    if (stack_.size() >= kMaxDepth) {
      too_deep_ = true;
      return false;
    }
    stack_.push_back(place(std::move(container)));
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }

  json& root_;
  std::vector<json*> stack_;  // open containers, innermost last
  json::string_t key_;
  bool too_deep_ = false;
};

// Shortest form that reads back to the same double: fingerprints compare exactly.
using settings::format_number;

// ---- writing ----

json bytes_of(const std::vector<double>& v) {
  std::vector<std::uint8_t> b(v.size() * sizeof(double));
  if (!v.empty()) std::memcpy(b.data(), v.data(), b.size());
  return json::binary(std::move(b));
}

json fields_json(const slide::SlideFields& s) {
  return {{"Dx", s.Dx},         {"shift", s.shift}, {"f", bytes_of(s.f)}, {"u", bytes_of(s.u)},
          {"Fx", s.Fx},         {"Fz", s.Fz},       {"energy", s.energy}, {"h", s.h},
          {"dFz_dh", s.dFz_dh}, {"area", s.area}};
}

json optional_fields(const std::optional<slide::SlideFields>& s) {
  return s ? fields_json(*s) : json(nullptr);
}

json minimize_json(const minimize::MinimizeResult& r) {
  return {{"termination", static_cast<int>(r.termination)},
          {"iterations", r.iterations},
          {"gf_applications", r.gf_applications},
          {"interface_evaluations", r.interface_evaluations},
          {"filter_applications", r.filter_applications},
          {"filtered", r.filtered},
          {"energy", r.energy},
          {"max_force", r.max_force},
          {"escapes", r.escapes},
          {"rejected_steps", r.rejected_steps},
          {"memory_resets", r.memory_resets},
          {"lowest_eigenvalue", r.lowest_eigenvalue},
          {"stability_checked", r.stability_checked}};
}

// A paused slip relaxation (slide::PendingSlip): the flow's pair and integrator state, the
// relaxation before it and the path frames so far (displacements only, as the slide holds them).
json pending_json(const std::optional<slide::PendingSlip>& p) {
  if (!p) return nullptr;
  const minimize::FlowPause& fl = p->flow;
  json frames = json::array();
  for (const slide::PathFrame& fr : p->frames)
    frames.push_back({{"iteration", fr.iteration}, {"fields", fields_json(fr.fields)}});
  return {{"Dx", p->Dx},
          // null: the step went to the flow first (SlideOptions::flow_first_after).
          {"fast", p->fast ? minimize_json(*p->fast) : json(nullptr)},
          {"flow",
           {{"iteration", fl.iteration},
            {"u", bytes_of(fl.u)},
            {"f", bytes_of(fl.f)},
            {"velocity_u", bytes_of(fl.velocity_u)},
            {"velocity_f", bytes_of(fl.velocity_f)},
            {"step", fl.step},
            {"radius", fl.radius},
            {"since_estimate", fl.since_estimate},
            {"power", bytes_of(fl.power)},
            {"done", minimize_json(fl.done)}}},
          {"frames", frames},
          {"frame_interval", p->frame_interval}};
}

json window_json(const std::vector<slide::SlideFields>& window) {
  json out = json::array();
  for (const auto& s : window)
    out.push_back(fields_json(s));
  return out;
}

json snapshot_json(const slide::Snapshot& s) {
  return {{"label", s.label},
          {"iteration", s.iteration},
          {"Dx", s.Dx},
          {"Fx", s.Fx},
          {"Fz", s.Fz},
          {"energy", s.energy},
          {"block", {s.block.shape.n0, s.block.shape.n1, s.block.origin0, s.block.origin1}},
          {"ux", bytes_of(s.ux)},
          {"uy", bytes_of(s.uy)},
          {"uz", bytes_of(s.uz)},
          {"sx", bytes_of(s.sx)},
          {"sy", bytes_of(s.sy)},
          {"tau_x", bytes_of(s.tau_x)},
          {"tau_y", bytes_of(s.tau_y)},
          {"tau_max", bytes_of(s.tau_max)},
          {"pressure", bytes_of(s.pressure)},
          {"in_contact", json::binary(s.in_contact)},
          {"tip", {s.tip.angle, s.tip.mismatch}},
          {"slipped_sites", s.slipped_sites},
          {"gf_applications", s.gf_applications},
          {"wall_s", s.wall_s}};
}

json result_json(const slide::SlideResult& r) {
  json trace = json::array();
  for (const auto& t : r.trace) {
    trace.push_back({t.Dx, t.Fx, t.Fz, t.energy, t.iterations, t.gf_applications, t.max_force,
                     t.slip, t.slipped_sites, t.replayed, t.area});
  }
  json snapshots = json::array();
  for (const auto& s : r.snapshots)
    snapshots.push_back(snapshot_json(s));
  return {{"trace", trace},
          {"measure", static_cast<int>(r.measure)},
          {"mu", r.mu},
          {"tau_fric", r.tau_fric},
          {"area", r.area},
          {"mu_over_alpha", r.mu_over_alpha},
          {"peak_Dx", r.peak_Dx},
          {"peak_precision", r.peak_precision},
          {"mu_is_lower_bound", r.mu_is_lower_bound},
          {"Fz", r.Fz},
          {"Fz_continuum", r.Fz_continuum},
          {"kinetic", r.kinetic},
          {"kinetic_over_static", r.kinetic_over_static},
          {"slip_events", r.slip_events},
          {"distance", r.distance},
          {"stop_reason", r.stop_reason},
          {"steps", r.steps},
          {"replayed_steps", r.replayed_steps},
          {"cycle_verified_at", r.cycle_verified_at},
          {"cycle_mismatch", r.cycle_mismatch},
          {"minimizations", r.minimizations},
          {"slip_relaxations", r.slip_relaxations},
          {"flow_first_steps", r.flow_first_steps},
          {"flow_first_stable", r.flow_first_stable},
          {"gf_applications", r.gf_applications},
          {"gradient_evaluations", r.gradient_evaluations},
          {"filter_applications", r.filter_applications},
          {"filtered", r.filtered},
          {"iterations", r.iterations},
          {"wall_s", r.wall_s},
          {"failed", r.failed},
          {"interrupted", r.interrupted},
          {"block", {r.block.n0, r.block.n1}},
          {"fft_grid", {r.fft_grid.n0, r.fft_grid.n1}},
          {"contact_sites", r.contact_sites},
          {"snapshots", snapshots}};
}

// ---- reading: every access checked, so that a damaged file throws rather than misbehaves ----

struct Bad : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

const json& at(const json& j, const char* key) {
  if (!j.is_object()) throw Bad(std::string("expected an object holding '") + key + "'");
  const auto it = j.find(key);
  if (it == j.end()) throw Bad(std::string("missing '") + key + "'");
  return *it;
}

double number(const json& j) {
  if (!j.is_number()) throw Bad("expected a number, got " + std::string(j.type_name()));
  return j.get<double>();
}
double number(const json& j, const char* key) {
  try {
    return number(at(j, key));
  } catch (const Bad& e) {
    throw Bad(std::string(key) + ": " + e.what());
  }
}

long long integer(const json& j, long long lo, long long hi, const char* key = "value") {
  long long v = 0;
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<long long>::max())) {
      throw Bad(std::string(key) + ": integer out of range");
    }
    v = static_cast<long long>(u);
  } else if (j.is_number_integer()) {
    v = j.get<long long>();
  } else {
    throw Bad(std::string(key) + ": expected an integer, got " + j.type_name());
  }
  if (v < lo || v > hi) throw Bad(std::string(key) + ": " + std::to_string(v) + " out of range");
  return v;
}
long long integer(const json& j, const char* key, long long lo, long long hi) {
  return integer(at(j, key), lo, hi, key);
}
int int_value(const json& j, const char* key) {
  return static_cast<int>(
      integer(j, key, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}
std::size_t count_value(const json& j, const char* key) {
  return static_cast<std::size_t>(integer(j, key, 0, std::numeric_limits<long long>::max()));
}
// A count held in an int (iterations, steps): 0 ... INT_MAX.
int int_count(const json& j, const char* key) {
  return static_cast<int>(integer(j, key, 0, std::numeric_limits<int>::max()));
}

bool boolean(const json& j, const char* key) {
  const json& v = at(j, key);
  if (!v.is_boolean()) throw Bad(std::string(key) + ": expected true or false");
  return v.get<bool>();
}

std::string text(const json& j, const char* key) {
  const json& v = at(j, key);
  if (!v.is_string()) throw Bad(std::string(key) + ": expected text");
  return v.get<std::string>();
}

const json& array(const json& j, const char* key, std::size_t size = 0) {
  const json& v = at(j, key);
  if (!v.is_array()) throw Bad(std::string(key) + ": expected an array");
  if (size > 0 && v.size() != size) {
    throw Bad(std::string(key) + ": expected " + std::to_string(size) + " elements");
  }
  return v;
}

std::vector<double> doubles(const json& j, const char* key) {
  const json& v = at(j, key);
  if (!v.is_binary()) throw Bad(std::string(key) + ": expected a byte string");
  const auto& b = v.get_binary();
  if (b.size() % sizeof(double) != 0) {
    throw Bad(std::string(key) + ": " + std::to_string(b.size()) +
              " bytes, not a whole number of doubles");
  }
  std::vector<double> out(b.size() / sizeof(double));
  if (!out.empty()) std::memcpy(out.data(), b.data(), b.size());
  return out;
}

slide::SlideFields fields_from(const json& j) {
  slide::SlideFields s;
  s.Dx = number(j, "Dx");
  s.shift = int_value(j, "shift");
  s.f = doubles(j, "f");
  s.u = doubles(j, "u");
  s.Fx = number(j, "Fx");
  s.Fz = number(j, "Fz");
  s.energy = number(j, "energy");
  s.h = number(j, "h");
  s.dFz_dh = number(j, "dFz_dh");
  s.area = number(j, "area");
  return s;
}

std::optional<slide::SlideFields> optional_fields_from(const json& j, const char* key) {
  const json& v = at(j, key);
  if (v.is_null()) return std::nullopt;
  return fields_from(v);
}

minimize::MinimizeResult minimize_from(const json& j) {
  minimize::MinimizeResult r;
  r.termination = static_cast<Termination>(
      integer(j, "termination", 0, static_cast<long long>(Termination::stalled)));
  r.iterations = int_count(j, "iterations");
  r.gf_applications = count_value(j, "gf_applications");
  r.interface_evaluations = count_value(j, "interface_evaluations");
  r.filter_applications = count_value(j, "filter_applications");
  r.filtered = boolean(j, "filtered");
  r.energy = number(j, "energy");
  r.max_force = number(j, "max_force");
  r.escapes = int_count(j, "escapes");
  r.rejected_steps = int_count(j, "rejected_steps");
  r.memory_resets = int_count(j, "memory_resets");
  r.lowest_eigenvalue = number(j, "lowest_eigenvalue");
  r.stability_checked = boolean(j, "stability_checked");
  return r;
}

// Sizes are checked where the pause is continued (slide(), minimize()), against the scene.
std::optional<slide::PendingSlip> pending_from(const json& s) {
  // Absent in checkpoints written before slip relaxations could pause.
  if (!s.contains("pending") || s["pending"].is_null()) return std::nullopt;
  const json& j = s["pending"];
  slide::PendingSlip p;
  p.Dx = number(j, "Dx");
  if (!at(j, "fast").is_null()) p.fast = minimize_from(at(j, "fast"));
  const json& fl = at(j, "flow");
  p.flow.iteration = int_count(fl, "iteration");
  p.flow.u = doubles(fl, "u");
  p.flow.f = doubles(fl, "f");
  p.flow.velocity_u = doubles(fl, "velocity_u");
  p.flow.velocity_f = doubles(fl, "velocity_f");
  p.flow.step = number(fl, "step");
  p.flow.radius = number(fl, "radius");
  p.flow.since_estimate = int_count(fl, "since_estimate");
  p.flow.power = doubles(fl, "power");
  p.flow.done = minimize_from(at(fl, "done"));
  for (const json& fr : array(j, "frames")) {
    p.frames.push_back(
        {.iteration = int_count(fr, "iteration"), .fields = fields_from(at(fr, "fields"))});
  }
  p.frame_interval = int_count(j, "frame_interval");
  return p;
}

Shape2 shape_from(const json& pair) {
  const long long n0 = integer(pair[0], 0, kMaxSites), n1 = integer(pair[1], 0, kMaxSites);
  if (n0 * n1 > kMaxSites) throw Bad("block of " + std::to_string(n0 * n1) + " sites");
  return {static_cast<int>(n0), static_cast<int>(n1)};
}

slide::Snapshot snapshot_from(const json& j) {
  slide::Snapshot s;
  s.label = text(j, "label");
  s.iteration = int_value(j, "iteration");
  s.Dx = number(j, "Dx");
  s.Fx = number(j, "Fx");
  s.Fz = number(j, "Fz");
  s.energy = number(j, "energy");
  const json& b = array(j, "block", 4);
  s.block.shape = shape_from(b);
  s.block.origin0 = static_cast<int>(integer(b[2], -kMaxSites, kMaxSites));
  s.block.origin1 = static_cast<int>(integer(b[3], -kMaxSites, kMaxSites));
  const std::size_t n = s.block.shape.count();
  const auto field = [&](const char* key, std::vector<double>& v) {
    v = doubles(j, key);
    if (v.size() != n) throw Bad(std::string(key) + ": size differs from the block's sites");
  };
  field("ux", s.ux);
  field("uy", s.uy);
  s.uz = doubles(j, "uz");  // explicit model only
  if (!s.uz.empty() && s.uz.size() != n) throw Bad("uz: size differs from the block's sites");
  field("sx", s.sx);
  field("sy", s.sy);
  field("tau_x", s.tau_x);
  field("tau_y", s.tau_y);
  field("tau_max", s.tau_max);
  field("pressure", s.pressure);
  const json& c = at(j, "in_contact");
  if (!c.is_binary() || c.get_binary().size() != n)
    throw Bad("in_contact: expected " + std::to_string(n) + " bytes");
  s.in_contact.assign(c.get_binary().begin(), c.get_binary().end());
  if (j.contains("tip")) {  // checkpoints written before the tip's lattice: aligned
    const json& t = array(j, "tip", 2);
    s.tip = {.angle = number(t[0]), .mismatch = number(t[1])};
  }
  // A slip's frame: its sites and the slide's cost when it was accepted (checkpoints written
  // before these were kept: 0, as for every other frame).
  if (j.contains("slipped_sites"))
    s.slipped_sites =
        static_cast<int>(integer(j, "slipped_sites", 0, std::numeric_limits<int>::max()));
  if (j.contains("gf_applications"))
    s.gf_applications = static_cast<std::size_t>(
        integer(j, "gf_applications", 0, std::numeric_limits<long long>::max()));
  if (j.contains("wall_s")) s.wall_s = number(j, "wall_s");
  return s;
}

slide::SlideResult result_from(const json& j) {
  slide::SlideResult r;
  for (const json& row : array(j, "trace")) {
    if (!row.is_array() || row.size() != 11) throw Bad("trace: rows of 11 values expected");
    r.trace.push_back(
        {.Dx = number(row[0]),
         .Fx = number(row[1]),
         .Fz = number(row[2]),
         .energy = number(row[3]),
         .iterations = static_cast<int>(integer(row[4], 0, std::numeric_limits<int>::max())),
         .gf_applications =
             static_cast<std::size_t>(integer(row[5], 0, std::numeric_limits<long long>::max())),
         .max_force = number(row[6]),
         .slip = row[7].is_boolean() ? row[7].get<bool>() : throw Bad("trace: slip"),
         .slipped_sites = static_cast<int>(integer(row[8], 0, std::numeric_limits<int>::max())),
         .replayed = row[9].is_boolean() ? row[9].get<bool>() : throw Bad("trace: replayed"),
         .area = number(row[10])});
  }
  r.measure = static_cast<slide::FrictionMeasure>(
      integer(j, "measure", 0, static_cast<long long>(slide::FrictionMeasure::area)));
  r.mu = number(j, "mu");
  r.tau_fric = number(j, "tau_fric");
  r.area = number(j, "area");
  r.mu_over_alpha = number(j, "mu_over_alpha");
  r.peak_Dx = number(j, "peak_Dx");
  r.peak_precision = number(j, "peak_precision");
  r.mu_is_lower_bound = boolean(j, "mu_is_lower_bound");
  r.Fz = number(j, "Fz");
  r.Fz_continuum = number(j, "Fz_continuum");
  r.kinetic = number(j, "kinetic");
  r.kinetic_over_static = number(j, "kinetic_over_static");
  r.slip_events = int_value(j, "slip_events");
  r.distance = number(j, "distance");
  r.stop_reason = text(j, "stop_reason");
  r.steps = int_value(j, "steps");
  r.replayed_steps = int_value(j, "replayed_steps");
  r.cycle_verified_at = number(j, "cycle_verified_at");
  r.cycle_mismatch = number(j, "cycle_mismatch");
  r.minimizations = int_value(j, "minimizations");
  // Absent in checkpoints written before the slip minimiser existed.
  if (j.contains("slip_relaxations")) r.slip_relaxations = int_value(j, "slip_relaxations");
  // Absent before flow_first_after (2026-11-29): none were made.
  if (j.contains("flow_first_steps")) r.flow_first_steps = int_value(j, "flow_first_steps");
  if (j.contains("flow_first_stable")) r.flow_first_stable = int_value(j, "flow_first_stable");
  r.gf_applications = count_value(j, "gf_applications");
  r.gradient_evaluations = count_value(j, "gradient_evaluations");
  // Absent in checkpoints written before the interface filter existed.
  if (j.contains("filter_applications")) {
    r.filter_applications = count_value(j, "filter_applications");
    r.filtered = boolean(j, "filtered");
  }
  r.iterations = integer(j, "iterations", 0, std::numeric_limits<long long>::max());
  r.wall_s = number(j, "wall_s");
  r.failed = boolean(j, "failed");
  r.interrupted = boolean(j, "interrupted");
  r.block = shape_from(array(j, "block", 2));
  r.fft_grid = shape_from(array(j, "fft_grid", 2));
  r.contact_sites = count_value(j, "contact_sites");
  for (const json& s : array(j, "snapshots"))
    r.snapshots.push_back(snapshot_from(s));
  return r;
}

// The items of a fingerprint, for naming those that differ.
std::set<std::string> items(const std::string& s) {
  std::set<std::string> out;
  std::istringstream in(s);
  for (std::string item; in >> item;)
    out.insert(item);
  return out;
}

}  // namespace

namespace {

// The items both models share: scene, slide, solver and FFT options, build.
// Every setting of the slide scene (SlideScene::settings(), exact values) and the build.
std::string common_fingerprint(const SlideScene& scene) {
  // Another build may round differently: its continuation would not be the same slide.
  return settings::fingerprint(scene, SlideScene::settings()) + " code=" + provenance_token();
}

}  // namespace

std::string slide_fingerprint(const SlideScene& scene) {
  return common_fingerprint(scene) + " model=lfm";
}

std::string explicit_slide_fingerprint(const ExplicitSlideScene& scene,
                                       const ExplicitAlpha& alpha) {
  const auto& m = scene.model;
  // alpha enters through contact.alpha (mu/alpha, tau_max of the snapshots); the tip follows
  // from R, the potential from G in eps/sigma^3 and sigma/d.
  return common_fingerprint(explicit_as_slide_scene(scene, alpha)) + " model=explicit " +
         settings::fingerprint(m, explicit_model::ExplicitScene::settings()) +
         " tip_R=" + format_number(m.R);
}

std::vector<std::uint8_t> encode_checkpoint(const SlideCheckpoint& checkpoint) {
  const slide::SlideState& st = checkpoint.state;
  const json state = {{"current", fields_json(st.current)},
                      {"previous", optional_fields(st.previous)},
                      {"earlier", optional_fields(st.earlier)},
                      {"peak", fields_json(st.peak)},
                      {"runner_up", optional_fields(st.runner_up)},
                      {"best", st.best},
                      {"runner_up_ratio", st.runner_up_ratio},
                      {"first_max_Dx", st.first_max_Dx},
                      {"slip_at", st.slip_at},
                      {"stepping_done", st.stepping_done},
                      {"window", window_json(st.window)},
                      {"window_rows", st.window_rows},
                      {"cycle_check_due", st.cycle_check_due},
                      {"partial", result_json(st.partial)},
                      {"pending", pending_json(st.pending)}};
  return json::to_cbor(json{{"format", kFormat},
                            {"version", kVersion},
                            {"byte_order", kByteOrder},
                            {"settings", checkpoint.settings},
                            {"state", state}});
}

SlideCheckpoint decode_checkpoint(std::span<const std::uint8_t> bytes, const std::string& source) {
  const std::string prefix = source + ": not a contact_slide checkpoint of this version: ";
  json j;
  try {
    DepthLimitedDom dom(j);
    if (!json::sax_parse(bytes.begin(), bytes.end(), &dom, json::input_format_t::cbor)) {
      const std::string why = dom.too_deep() ? "nested deeper than " + std::to_string(kMaxDepth)
                                             : "damaged or truncated";
      throw std::invalid_argument(prefix + why);
    }
  } catch (const json::exception& e) {
    throw std::invalid_argument(prefix + "damaged or truncated (" + e.what() + ")");
  }
  try {
    if (!j.is_object() || !j.contains("format") || j["format"] != kFormat) {
      throw Bad("no '" + std::string(kFormat) + "' header");
    }
    if (integer(j, "version", 0, 1000000) != kVersion) {
      throw Bad("version " + at(j, "version").dump() + ", this program reads " +
                std::to_string(kVersion));
    }
    if (text(j, "byte_order") != kByteOrder) throw Bad("written on a machine of other byte order");
    SlideCheckpoint c;
    c.settings = text(j, "settings");
    const json& s = at(j, "state");
    c.state.current = fields_from(at(s, "current"));
    c.state.previous = optional_fields_from(s, "previous");
    c.state.earlier = optional_fields_from(s, "earlier");
    c.state.peak = fields_from(at(s, "peak"));
    c.state.runner_up = optional_fields_from(s, "runner_up");
    c.state.best = number(s, "best");
    c.state.runner_up_ratio = number(s, "runner_up_ratio");
    c.state.first_max_Dx = number(s, "first_max_Dx");
    c.state.slip_at = number(s, "slip_at");
    c.state.stepping_done = boolean(s, "stepping_done");
    c.state.partial = result_from(at(s, "partial"));
    for (const json& w : array(s, "window"))
      c.state.window.push_back(fields_from(w));
    for (const json& row : array(s, "window_rows"))
      c.state.window_rows.push_back(
          static_cast<std::size_t>(integer(row, 0, std::numeric_limits<int>::max())));
    // Whether the window fits the trace is checked where every start state is (slide()).
    c.state.cycle_check_due = boolean(s, "cycle_check_due");
    c.state.pending = pending_from(s);
    return c;
  } catch (const Bad& e) {
    throw std::invalid_argument(prefix + e.what());
  } catch (const json::exception& e) {
    throw std::invalid_argument(prefix + e.what());
  }
}

void write_checkpoint(const std::filesystem::path& file, const SlideCheckpoint& checkpoint) {
  const std::vector<std::uint8_t> bytes = encode_checkpoint(checkpoint);
  write_file_atomic(file,
                    std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

SlideCheckpoint read_checkpoint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read checkpoint '" + file.string() + "'");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
  if (in.bad()) throw std::invalid_argument("cannot read checkpoint '" + file.string() + "'");
  return decode_checkpoint(bytes, file.string());
}

void check_checkpoint_settings(const SlideCheckpoint& checkpoint, const SlideScene& scene,
                               const std::filesystem::path& file) {
  check_checkpoint_settings(checkpoint, slide_fingerprint(scene), file);
}

void check_checkpoint_settings(const SlideCheckpoint& checkpoint, const std::string& now,
                               const std::filesystem::path& file) {
  check_or_adopt_checkpoint(checkpoint, now, file, false);
}

namespace {

// Items a checkpoint may be adopted across: the numerical settings of the slide, solver and FFT,
// and the build's words (the only items without '='; the build item's first word is "code=").
bool adoptable(const std::string& item) {
  return item.rfind("slide.", 0) == 0 || item.rfind("solver.", 0) == 0 ||
         item.rfind("fft.", 0) == 0 || item.rfind("code=", 0) == 0 ||
         item.find('=') == std::string::npos;
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& x : v)
    out += (out.empty() ? "" : ", ") + x;
  return out;
}

}  // namespace

FingerprintDifference fingerprint_difference(const std::string& saved_fingerprint,
                                             const std::string& now) {
  const auto saved = items(saved_fingerprint), wanted = items(now);
  FingerprintDifference d;
  for (const auto& item : saved) {
    if (wanted.contains(item)) continue;
    d.removed.push_back(item);
    if (!adoptable(item)) d.fixed.push_back(item);
  }
  for (const auto& item : wanted) {
    if (saved.contains(item)) continue;
    d.added.push_back(item);
    if (!adoptable(item)) d.fixed.push_back(item);
  }
  return d;
}

std::optional<CheckpointAdoption> check_or_adopt_checkpoint(const SlideCheckpoint& checkpoint,
                                                            const std::string& now,
                                                            const std::filesystem::path& file,
                                                            bool adopt) {
  if (checkpoint.settings == now) return std::nullopt;
  const auto [differ, instead, fixed] = fingerprint_difference(checkpoint.settings, now);
  if (adopt && fixed.empty()) {
    return CheckpointAdoption{.saved = checkpoint.settings,
                              .now = now,
                              .removed = joined(differ),
                              .added = joined(instead)};
  }
  if (adopt) {
    throw std::invalid_argument(
        file.string() + ": checkpoint of another problem: " + joined(fixed) +
        " differ (only the build and slide.*, solver.* and fft.* settings may differ when a "
        "checkpoint is adopted). Resume with the scene of the interrupted run, or remove the "
        "checkpoint to start over");
  }
  throw std::invalid_argument(file.string() + ": checkpoint of other settings: it has " +
                              joined(differ) + "; this run has " + joined(instead) +
                              ". Resume with the scene and flags of the interrupted run, adopt it "
                              "under these settings (--adopt: another build, slide.*, solver.* "
                              "or fft.* only), or remove the checkpoint to start over");
}

std::string record_adoption(const std::filesystem::path& checkpoint_file,
                            const SlideCheckpoint& checkpoint, const CheckpointAdoption& adoption) {
  namespace fs = std::filesystem;
  const fs::path dir = checkpoint_file.parent_path();
  const fs::path record = dir / "adopted.json";
  int n = 1;
  while (fs::exists(dir / ("checkpoint.adopted." + std::to_string(n) + ".cbor")))
    ++n;
  const fs::path kept = dir / ("checkpoint.adopted." + std::to_string(n) + ".cbor");
  // A second name for the file, made at once: the run's next checkpoint replaces
  // checkpoint.cbor by a rename, and the kept name still holds what was adopted. Neither a copy
  // of a checkpoint of hundreds of MB nor a window in which a kill leaves no checkpoint.
  std::error_code ec;
  fs::create_hard_link(checkpoint_file, kept, ec);
  if (ec) {
    throw std::runtime_error("cannot keep the adopted checkpoint as " + kept.string() + ": " +
                             ec.message());
  }
  json all = json::array();
  if (fs::exists(record)) {
    std::ifstream in(record);
    all = json::parse(in, nullptr, false);
    if (!all.is_array()) throw std::runtime_error(record.string() + ": not a JSON array");
  }
  const std::time_t t = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char when[32];
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &utc);
  const slide::SlideState& st = checkpoint.state;
  all.push_back({{"when", when},
                 {"Dx", st.current.Dx},
                 {"steps", st.partial.steps},
                 {"slip_events", st.partial.slip_events},
                 {"kept_as", kept.filename().string()},
                 {"removed", adoption.removed},
                 {"added", adoption.added},
                 {"saved_settings", adoption.saved},
                 {"settings", adoption.now}});
  write_json(record, all);
  return "adopting the checkpoint " + checkpoint_file.string() + " (kept as " +
         kept.filename().string() + ", recorded in " + record.string() + "): it has " +
         adoption.removed + "; this run has " + adoption.added;
}

}  // namespace asperity::app
