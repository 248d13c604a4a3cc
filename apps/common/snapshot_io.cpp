#include "common/snapshot_io.hpp"

#include <netcdf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/memory.hpp"
#include "common/output_files.hpp"

namespace asperity::app {
namespace {

namespace fs = std::filesystem;
using slide::Snapshot;

struct Field {
  const char* name;
  std::vector<double> Snapshot::*values;
  const char* units;
  const char* long_name;
};
const std::array<Field, 8> kFields{{
    {"ux", &Snapshot::ux, "d", "displacement along x"},
    {"uy", &Snapshot::uy, "d", "displacement along y"},
    {"sx", &Snapshot::sx, "d", "relative position along x, X + ux - Dx"},
    {"sy", &Snapshot::sy, "d", "relative position along y, Y + uy"},
    {"tau_x", &Snapshot::tau_x, "G", "local shear stress along x"},
    {"tau_y", &Snapshot::tau_y, "G", "local shear stress along y"},
    {"tau_max", &Snapshot::tau_max, "G", "local shear stress amplitude"},
    {"pressure", &Snapshot::pressure, "G", "Hertz pressure"},
}};

struct Scalar {
  const char* name;
  double Snapshot::*value;
  const char* units;
  const char* long_name;
};
const std::array<Scalar, 4> kScalars{{
    {"Dx", &Snapshot::Dx, "d", "tip displacement along x"},
    {"Fx", &Snapshot::Fx, "G d^2", "lateral force"},
    {"Fz", &Snapshot::Fz, "G d^2", "normal force"},
    {"energy", &Snapshot::energy, "G d^3", "total energy"},
}};

// An open netCDF dataset, closed on destruction. check() turns a netCDF error status into an
// Error whose message starts with `context` (which names the file).
template <class Error>
class Dataset {
 public:
  explicit Dataset(std::string context) : context_(std::move(context)) {}
  ~Dataset() {
    if (id >= 0) nc_close(id);
  }
  Dataset(const Dataset&) = delete;
  Dataset& operator=(const Dataset&) = delete;

  [[noreturn]] void fail(const std::string& problem) const { throw Error(context_ + problem); }
  void check(int status, const std::string& what) const {
    if (status != NC_NOERR) fail(what + ": " + nc_strerror(status));
  }
  void close() { check(nc_close(std::exchange(id, -1)), "closing"); }

  int id = -1;

 private:
  std::string context_;
};
using Writer = Dataset<std::runtime_error>;
using Reader = Dataset<std::invalid_argument>;

void put_text(const Writer& out, int var, const std::string& name, const std::string& text) {
  out.check(nc_put_att_text(out.id, var, name.c_str(), text.size(), text.c_str()),
            "attribute '" + name + "'");
}

int define(const Writer& out, const std::string& name, nc_type type,
           std::initializer_list<int> dims, const std::string& units,
           const std::string& long_name) {
  int var = -1;
  out.check(
      nc_def_var(out.id, name.c_str(), type, static_cast<int>(dims.size()), dims.begin(), &var),
      "variable '" + name + "'");
  put_text(out, var, "units", units);
  put_text(out, var, "long_name", long_name);
  return var;
}

int define_dim(const Writer& out, const std::string& name, std::size_t length) {
  int dim = -1;
  out.check(nc_def_dim(out.id, name.c_str(), length, &dim), "dimension '" + name + "'");
  return dim;
}

void validate(const std::vector<Snapshot>& frames, const nlohmann::json& attributes,
              const std::string& context) {
  const auto invalid = [&](const std::string& problem) {
    throw std::invalid_argument(context + problem);
  };
  if (frames.empty()) invalid("no frames");
  if (!attributes.is_null() && !attributes.is_object()) invalid("attributes must be an object");
  const Shape2 shape = frames.front().block.shape;
  if (shape.n0 <= 0 || shape.n1 <= 0) invalid("empty block");
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const Snapshot& f = frames[k];
    const std::string frame = "frame " + std::to_string(k) + ": ";
    if (f.block.shape != shape) invalid(frame + "block shape differs from frame 0's");
    const auto sized = [&](const std::string& name, std::size_t size) {
      if (size != shape.count()) {
        invalid(frame + "'" + name + "' has " + std::to_string(size) + " values, expected " +
                std::to_string(shape.count()));
      }
    };
    for (const Field& field : kFields)
      sized(field.name, (f.*field.values).size());
    sized("in_contact", f.in_contact.size());
    // uz (explicit model only): in every frame of a file or in none.
    if (!frames.front().uz.empty() || !f.uz.empty()) sized("uz", f.uz.size());
  }
}

}  // namespace

void write_snapshots(const fs::path& nc, const std::vector<Snapshot>& frames,
                     const nlohmann::json& attributes) {
  const std::string context = "cannot write '" + nc.string() + "': ";
  validate(frames, attributes, context);
  const Snapshot& first = frames.front();
  const std::size_t n = frames.size();
  const auto n0 = static_cast<std::size_t>(first.block.shape.n0);
  const auto n1 = static_cast<std::size_t>(first.block.shape.n1);
  std::size_t label_length = 1;
  for (const Snapshot& f : frames)
    label_length = std::max(label_length, f.label.size());

  // Named: HDF5 resolves the path it is given (realpath), which an unnamed file's /proc path
  // defeats. The write takes milliseconds; a kill within them leaves a hidden temporary, which
  // the next run removes (remove_stale_temporaries).
  TemporaryFile tmp(nc, TemporaryFile::Kind::named);
  Writer out(context);
  out.check(nc_create(tmp.path().c_str(), NC_CLOBBER | NC_NETCDF4 | NC_CLASSIC_MODEL, &out.id),
            "creating");
  const int frame_dim = define_dim(out, "frame", n);
  const int x_dim = define_dim(out, "x", n0);
  const int y_dim = define_dim(out, "y", n1);
  const int label_dim = define_dim(out, "label_length", label_length);

  const int x_var = define(out, "x", NC_DOUBLE, {x_dim}, "d", "x of the first frame's sites");
  put_text(out, x_var, "axis", "X");
  const int y_var = define(out, "y", NC_DOUBLE, {y_dim}, "d", "y of the first frame's sites");
  put_text(out, y_var, "axis", "Y");
  const int label_var =
      define(out, "label", NC_CHAR, {frame_dim, label_dim}, "1", "snapshot label");
  put_text(out, label_var, "_Encoding", "utf-8");
  const int iteration_var = define(out, "iteration", NC_INT, {frame_dim}, "1",
                                   "minimiser iteration of a relaxation-path frame, else -1");
  const int origin_x_var = define(out, "origin_x", NC_INT, {frame_dim}, "d",
                                  "lattice index along x of the block's first site");
  const int origin_y_var = define(out, "origin_y", NC_INT, {frame_dim}, "d",
                                  "lattice index along y of the block's first site");
  std::vector<int> scalar_vars, field_vars;
  for (const Scalar& s : kScalars)
    scalar_vars.push_back(define(out, s.name, NC_DOUBLE, {frame_dim}, s.units, s.long_name));
  for (const Field& f : kFields) {
    field_vars.push_back(
        define(out, f.name, NC_DOUBLE, {frame_dim, x_dim, y_dim}, f.units, f.long_name));
  }
  // The normal displacement exists in the explicit model only (the LFM has none).
  const bool has_uz = !first.uz.empty();
  const int uz_var = has_uz ? define(out, "uz", NC_DOUBLE, {frame_dim, x_dim, y_dim}, "d",
                                     "displacement along z (explicit model)")
                            : -1;
  const int contact_var = define(out, "in_contact", NC_BYTE, {frame_dim, x_dim, y_dim}, "1",
                                 "site in contact (1) or not (0)");

  for (const auto& [key, value] : attributes.items()) {
    if (value.is_boolean()) {
      const int flag = value.get<bool>() ? 1 : 0;
      out.check(nc_put_att_int(out.id, NC_GLOBAL, key.c_str(), NC_INT, 1, &flag),
                "attribute '" + key + "'");
    } else if (value.is_number()) {
      const auto number = value.get<double>();
      out.check(nc_put_att_double(out.id, NC_GLOBAL, key.c_str(), NC_DOUBLE, 1, &number),
                "attribute '" + key + "'");
    } else {
      put_text(out, NC_GLOBAL, key, value.is_string() ? value.get<std::string>() : value.dump());
    }
  }
  put_text(out, NC_GLOBAL, "title", "asperity sliding snapshots");
  put_text(out, NC_GLOBAL, "Conventions", "CF-1.8");
  put_text(out, NC_GLOBAL, "comment",
           "x and y are the coordinates of the first frame's block; the block may follow the "
           "tip: site (i, j) of frame k is at ((origin_x[k] + i) d, (origin_y[k] + j) d)");
  put_text(out, NC_GLOBAL, "label", first.label);
  out.check(nc_enddef(out.id), "ending definitions");

  std::vector<double> x(n0), y(n1);
  std::iota(x.begin(), x.end(), static_cast<double>(first.block.origin0));
  std::iota(y.begin(), y.end(), static_cast<double>(first.block.origin1));
  out.check(nc_put_var_double(out.id, x_var, x.data()), "writing 'x'");
  out.check(nc_put_var_double(out.id, y_var, y.data()), "writing 'y'");

  std::string labels(n * label_length, '\0');
  std::vector<int> iteration, origin_x, origin_y;
  for (std::size_t k = 0; k < n; ++k) {
    std::copy(frames[k].label.begin(), frames[k].label.end(), labels.data() + k * label_length);
    iteration.push_back(frames[k].iteration);
    origin_x.push_back(frames[k].block.origin0);
    origin_y.push_back(frames[k].block.origin1);
  }
  out.check(nc_put_var_text(out.id, label_var, labels.data()), "writing 'label'");
  out.check(nc_put_var_int(out.id, iteration_var, iteration.data()), "writing 'iteration'");
  out.check(nc_put_var_int(out.id, origin_x_var, origin_x.data()), "writing 'origin_x'");
  out.check(nc_put_var_int(out.id, origin_y_var, origin_y.data()), "writing 'origin_y'");
  for (std::size_t s = 0; s < kScalars.size(); ++s) {
    std::vector<double> values;
    for (const Snapshot& f : frames)
      values.push_back(f.*kScalars[s].value);
    out.check(nc_put_var_double(out.id, scalar_vars[s], values.data()),
              std::string("writing '") + kScalars[s].name + "'");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t start[] = {k, 0, 0}, count[] = {1, n0, n1};
    for (std::size_t v = 0; v < kFields.size(); ++v) {
      out.check(nc_put_vara_double(out.id, field_vars[v], start, count,
                                   (frames[k].*kFields[v].values).data()),
                std::string("writing '") + kFields[v].name + "'");
    }
    out.check(nc_put_vara_uchar(out.id, contact_var, start, count, frames[k].in_contact.data()),
              "writing 'in_contact'");
    if (has_uz) {
      out.check(nc_put_vara_double(out.id, uz_var, start, count, frames[k].uz.data()),
                "writing 'uz'");
    }
  }
  out.close();
  tmp.commit();
}

namespace {

// read_snapshots into `frames`, or with `frames` null only its checks of the header:
// dimensions, sizes, the memory the frames need and every variable's presence and shape (no
// field is read). Returns the number of frames.
std::size_t read_file(const fs::path& nc, std::vector<Snapshot>* out) {
  Reader in("cannot read '" + nc.string() + "': ");
  if (!fs::exists(nc)) in.fail("no such file");
  int id = -1;
  const int status = nc_open(nc.c_str(), NC_NOWRITE, &id);
  if (status == NC_ENOTNC || status == NC_EHDFERR) in.fail("not a NetCDF file, or truncated");
  in.check(status, "opening");
  in.id = id;

  const auto dim = [&](const std::string& name, int& d) {
    std::size_t length = 0;
    if (nc_inq_dimid(in.id, name.c_str(), &d) != NC_NOERR)
      in.fail("dimension '" + name + "' missing");
    in.check(nc_inq_dimlen(in.id, d, &length), "dimension '" + name + "'");
    return length;
  };
  int frame_dim = -1, x_dim = -1, y_dim = -1, label_dim = -1;
  const std::size_t n = dim("frame", frame_dim), n0 = dim("x", x_dim), n1 = dim("y", y_dim),
                    label_length = dim("label_length", label_dim);
  // The header's sizes decide every allocation below: a damaged or hostile header must not
  // turn into a crash. Blocks are indexed by int; the frames must fit in memory.
  constexpr std::size_t kMaxSide = 1 << 20, kMaxLabel = 1 << 16;
  if (n == 0) in.fail("no frames");
  if (n0 == 0 || n1 == 0 || n0 > kMaxSide || n1 > kMaxSide) {
    in.fail("block of " + std::to_string(n0) + " x " + std::to_string(n1) +
            " sites (each side must be 1 .. " + std::to_string(kMaxSide) + ")");
  }
  if (label_length > kMaxLabel) {
    in.fail("labels of " + std::to_string(label_length) + " characters (at most " +
            std::to_string(kMaxLabel) + ")");
  }
  const double fields_per_site = static_cast<double>(kFields.size()) + 2.0;  // + uz, in_contact
  const double sites = static_cast<double>(n0) * static_cast<double>(n1);
  // The classic formats store every value uncompressed: a header claiming more records than
  // the file holds is damaged (each record has at least the 8 fields and in_contact).
  int format = 0;
  in.check(nc_inq_format(in.id, &format), "format");
  if (format != NC_FORMAT_NETCDF4 && format != NC_FORMAT_NETCDF4_CLASSIC) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(nc, ec);
    const double record = sites * (8.0 * static_cast<double>(kFields.size()) + 1.0);
    if (!ec && static_cast<double>(n) * record > static_cast<double>(size)) {
      in.fail(std::to_string(n) + " frames of " + std::to_string(n0) + " x " + std::to_string(n1) +
              " sites in a file of " + std::to_string(size) +
              " bytes: the header claims more data than the file holds");
    }
  }
  check_fits_in_memory(
      "'" + nc.string() + "'",
      static_cast<double>(n) * (sites * 8.0 * fields_per_site + static_cast<double>(label_length) +
                                static_cast<double>(sizeof(Snapshot))),
      std::to_string(n) + " frames of " + std::to_string(n0) + " x " + std::to_string(n1) +
          " sites, as its header says");

  // Looks up a variable and checks its dimensions, so that reads cannot overrun the buffers.
  const auto var = [&](const std::string& name, std::initializer_list<int> dims) {
    int v = -1, ndims = -1;
    if (nc_inq_varid(in.id, name.c_str(), &v) != NC_NOERR)
      in.fail("variable '" + name + "' missing");
    std::array<int, NC_MAX_VAR_DIMS> ids{};
    in.check(nc_inq_var(in.id, v, nullptr, nullptr, &ndims, ids.data(), nullptr),
             "variable '" + name + "'");
    if (!std::equal(dims.begin(), dims.end(), ids.begin(), ids.begin() + ndims))
      in.fail("variable '" + name + "' has unexpected dimensions");
    return v;
  };
  if (out == nullptr) {
    var("label", {frame_dim, label_dim});
    for (const char* name : {"iteration", "origin_x", "origin_y"})
      var(name, {frame_dim});
    for (const Scalar& sc : kScalars)
      var(sc.name, {frame_dim});
    for (const Field& f : kFields)
      var(f.name, {frame_dim, x_dim, y_dim});
    var("in_contact", {frame_dim, x_dim, y_dim});
    return n;
  }
  const auto get_ints = [&](const std::string& name) {
    std::vector<int> values(n);
    in.check(nc_get_var_int(in.id, var(name, {frame_dim}), values.data()),
             "reading '" + name + "'");
    return values;
  };

  std::vector<Snapshot>& frames = *out;
  frames.assign(n, Snapshot{});
  std::string labels(n * label_length, '\0');
  in.check(nc_get_var_text(in.id, var("label", {frame_dim, label_dim}), labels.data()),
           "reading 'label'");
  const std::vector<int> iteration = get_ints("iteration");
  const std::vector<int> origin_x = get_ints("origin_x");
  const std::vector<int> origin_y = get_ints("origin_y");
  for (std::size_t k = 0; k < n; ++k) {
    const char* label = labels.data() + k * label_length;
    frames[k].label.assign(label, std::find(label, label + label_length, '\0'));
    frames[k].iteration = iteration[k];
    frames[k].block = {{static_cast<int>(n0), static_cast<int>(n1)}, origin_x[k], origin_y[k]};
  }
  for (const Scalar& s : kScalars) {
    std::vector<double> values(n);
    in.check(nc_get_var_double(in.id, var(s.name, {frame_dim}), values.data()),
             std::string("reading '") + s.name + "'");
    for (std::size_t k = 0; k < n; ++k)
      frames[k].*s.value = values[k];
  }
  // Snapshots hold converged, finite states (a failed run saves its last good one): a
  // non-finite value means a damaged file, which would otherwise pass as an empty frame.
  const auto finite = [&](const std::vector<double>& values, const char* name, std::size_t k) {
    if (!std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); }))
      in.fail(std::string("non-finite values in '") + name + "' of frame " + std::to_string(k));
  };
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(frames[k].Dx)) in.fail("non-finite 'Dx' in frame " + std::to_string(k));
  }
  const std::initializer_list<int> field_dims{frame_dim, x_dim, y_dim};
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t start[] = {k, 0, 0}, count[] = {1, n0, n1};
    for (const Field& f : kFields) {
      std::vector<double>& values = frames[k].*f.values;
      values.resize(n0 * n1);
      in.check(nc_get_vara_double(in.id, var(f.name, field_dims), start, count, values.data()),
               std::string("reading '") + f.name + "'");
      finite(values, f.name, k);
    }
    frames[k].in_contact.resize(n0 * n1);
    in.check(nc_get_vara_uchar(in.id, var("in_contact", field_dims), start, count,
                               frames[k].in_contact.data()),
             "reading 'in_contact'");
    if (int uz = -1; nc_inq_varid(in.id, "uz", &uz) == NC_NOERR) {
      frames[k].uz.resize(n0 * n1);
      in.check(nc_get_vara_double(in.id, var("uz", field_dims), start, count, frames[k].uz.data()),
               "reading 'uz'");
      finite(frames[k].uz, "uz", k);
    }
  }
  return n;
}

}  // namespace

std::vector<Snapshot> read_snapshots(const fs::path& nc) {
  std::vector<Snapshot> frames;
  read_file(nc, &frames);
  return frames;
}

std::size_t check_snapshot_file(const fs::path& nc) {
  return read_file(nc, nullptr);
}

}  // namespace asperity::app
