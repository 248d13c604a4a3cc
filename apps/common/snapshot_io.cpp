#include "asperity/apps/common/snapshot_io.hpp"

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

#include "asperity/apps/common/memory.hpp"
#include "asperity/apps/common/output_files.hpp"

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

// The variables that are neither kFields nor kScalars, described once for define() and
// snapshot_variables().
const SnapshotVariable kIteration{"iteration", "1",
                                  "minimiser iteration of a relaxation-path frame, else -1", false};
const SnapshotVariable kOriginX{"origin_x", "d", "lattice index along x of the block's first site",
                                false};
const SnapshotVariable kOriginY{"origin_y", "d", "lattice index along y of the block's first site",
                                false};
const SnapshotVariable kUz{"uz", "d", "displacement along z (explicit model)", true};
const SnapshotVariable kInContact{"in_contact", "1", "site in contact (1) or not (0)", true};

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

void put_text(const Writer& out, int id, int var, const std::string& name,
              const std::string& text) {
  out.check(nc_put_att_text(id, var, name.c_str(), text.size(), text.c_str()),
            "attribute '" + name + "'");
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
    if (!(f.tip == frames.front().tip)) invalid(frame + "tip lattice differs from frame 0's");
  }
}

// The tip's lattice of a file (global attributes tip_angle, tip_mismatch; absent in files
// written before them and by tools without a tip: aligned).
template <class Error>
interface::TipLattice read_tip(const Dataset<Error>& in, int id) {
  interface::TipLattice tip;
  const auto number = [&](const char* name, double& value) {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(id, NC_GLOBAL, name, &type, &length) != NC_NOERR) return;
    if (length != 1 || type == NC_CHAR)
      in.fail(std::string("attribute '") + name + "' is not a number");
    in.check(nc_get_att_double(id, NC_GLOBAL, name, &value),
             std::string("attribute '") + name + "'");
    if (!std::isfinite(value)) in.fail(std::string("attribute '") + name + "' is not finite");
  };
  number("tip_angle", tip.angle);
  number("tip_mismatch", tip.mismatch);
  return tip;
}

}  // namespace

// The files store fields as (frame, y, x), y slow, so that VTK's CF reader (ParaView) takes the
// file's last dimension, x, for its x axis; blocks hold sites x slow (Shape2). Files written
// before hold (frame, x, y): the readers take both, told apart by the dimensions of 'ux'.
// Tiled so that a large block (4096^2 sites: 128 MiB a field) does not miss the cache on
// every write: out[c * rows + r] = in[r * cols + c].
template <class T>
void transpose(const T* in, std::size_t rows, std::size_t cols, T* out) {
  constexpr std::size_t kTile = 32;
  for (std::size_t r0 = 0; r0 < rows; r0 += kTile) {
    for (std::size_t c0 = 0; c0 < cols; c0 += kTile) {
      const std::size_t r1 = std::min(rows, r0 + kTile), c1 = std::min(cols, c0 + kTile);
      for (std::size_t r = r0; r < r1; ++r) {
        for (std::size_t c = c0; c < c1; ++c)
          out[c * rows + r] = in[r * cols + c];
      }
    }
  }
}

// Reads the per-site fields of frame k (a block of n0 x n1 sites) into `frame`, from a file
// whose fields are (frame, y, x) (`y_major`) or (frame, x, y). Snapshots hold
// converged, finite states (a failed run saves its last good one): a non-finite value means a
// damaged file, which would otherwise pass as an empty frame.
template <class Error>
void read_fields(const Dataset<Error>& in, int id, const std::array<int, kFields.size()>& fields,
                 int in_contact, int uz, std::size_t k, std::size_t n0, std::size_t n1,
                 bool y_major, Snapshot& frame) {
  const auto finite = [&](const std::vector<double>& values, const char* name) {
    if (!std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); }))
      in.fail(std::string("non-finite values in '") + name + "' of frame " + std::to_string(k));
  };
  const std::size_t start[] = {k, 0, 0};
  const std::size_t count[] = {1, y_major ? n1 : n0, y_major ? n0 : n1};
  std::vector<double> file_order(y_major ? n0 * n1 : 0);
  const auto get = [&](int var, const char* name, std::vector<double>& values) {
    values.resize(n0 * n1);
    in.check(nc_get_vara_double(id, var, start, count, y_major ? file_order.data() : values.data()),
             std::string("reading '") + name + "'");
    if (y_major) transpose(file_order.data(), n1, n0, values.data());
    finite(values, name);
  };
  for (std::size_t f = 0; f < kFields.size(); ++f)
    get(fields[f], kFields[f].name, frame.*kFields[f].values);
  frame.in_contact.resize(n0 * n1);
  std::vector<unsigned char> contact_order(y_major ? n0 * n1 : 0);
  in.check(nc_get_vara_uchar(id, in_contact, start, count,
                             y_major ? contact_order.data() : frame.in_contact.data()),
           "reading 'in_contact'");
  if (y_major) transpose(contact_order.data(), n1, n0, frame.in_contact.data());
  if (uz >= 0) get(uz, "uz", frame.uz);
}

// Frames are written and read as whole chunks, once each: HDF5's cache of chunks (16 MiB per
// variable by default in netCDF 4.9, kept after they are written) would only hold memory, up to
// 160 MiB for the ten fields of a file being written (seen: 20 MB more per path written at
// a = 50 d). A cache smaller than a chunk makes HDF5 write and read chunks directly. (Not 0
// bytes: netCDF 4.9 takes 0 for "keep the default" when it creates the variable.)
void no_chunk_cache(const Writer& out, int id, int var, const std::string& name) {
  out.check(nc_set_var_chunk_cache(id, var, 1, 1, 1.0f), "chunk cache of '" + name + "'");
}

void SnapshotFormat::validate() const {
  if (deflate_level < 0 || deflate_level > 9) {
    throw std::invalid_argument("snapshot deflate level: got " + std::to_string(deflate_level) +
                                ", allowed: 0 (none) .. 9");
  }
}

// The variables of an open file, defined at the first frame (whose block shape and uz decide
// them) or looked up in an existing file.
struct SnapshotAppender::Layout {
  int frame_dim = -1, x_dim = -1, y_dim = -1, label_dim = -1;
  int label = -1, iteration = -1, origin_x = -1, origin_y = -1, in_contact = -1, uz = -1;
  int frame_index = -1;  // the frame coordinate (VTK's time axis); absent in older files
  std::array<int, kScalars.size()> scalars{};
  std::array<int, kFields.size()> fields{};
  std::size_t n0 = 0, n1 = 0, label_length = 0;
  bool y_major = true;  // fields (frame, y, x); false: an older file's (frame, x, y)
  // One frame's field in the file's order, reused by every write.
  std::vector<double> values;
  std::vector<unsigned char> flags;
};

namespace {
// Whether the field `var` of an open file is stored (frame, y, x) rather than (frame, x, y).
template <class Error>
bool fields_y_major(const Dataset<Error>& in, int id, int var, int y_dim) {
  std::array<int, NC_MAX_VAR_DIMS> dims{};
  int ndims = 0;
  in.check(nc_inq_var(id, var, nullptr, nullptr, &ndims, dims.data(), nullptr), "field layout");
  return ndims == 3 && dims[1] == y_dim;
}
}  // namespace

SnapshotAppender::SnapshotAppender(fs::path nc, nlohmann::json attributes, SnapshotFormat format,
                                   std::size_t label_length, std::size_t frames)
    : nc_(std::move(nc)),
      attributes_(std::move(attributes)),
      format_(format),
      label_length_(label_length),
      fixed_frames_(frames) {
  format_.validate();
  if (!attributes_.is_null() && !attributes_.is_object()) {
    throw std::invalid_argument("cannot write '" + nc_.string() +
                                "': attributes must be an object");
  }
}

SnapshotAppender SnapshotAppender::open(const fs::path& nc) {
  SnapshotAppender a(nc, nullptr, {}, 0);
  const Writer out("cannot append to '" + nc.string() + "': ");
  if (!fs::exists(nc)) out.fail("no such file");
  out.check(nc_open(nc.c_str(), NC_WRITE, &a.id_), "opening");
  a.layout_ = std::make_unique<Layout>();
  Layout& l = *a.layout_;
  const auto dim = [&](const char* name, int& d) {
    std::size_t length = 0;
    out.check(nc_inq_dimid(a.id_, name, &d), std::string("dimension '") + name + "'");
    out.check(nc_inq_dimlen(a.id_, d, &length), std::string("dimension '") + name + "'");
    return length;
  };
  a.frames_ = dim("frame", l.frame_dim);
  // A file written whole (write_snapshots) has a fixed frame dimension and takes no more.
  int unlimited = -1;
  out.check(nc_inq_unlimdim(a.id_, &unlimited), "dimensions");
  if (unlimited != l.frame_dim) a.fixed_frames_ = a.frames_;
  l.n0 = dim("x", l.x_dim);
  l.n1 = dim("y", l.y_dim);
  l.label_length = a.label_length_ = dim("label_length", l.label_dim);
  const auto var = [&](const char* name) {
    int v = -1;
    out.check(nc_inq_varid(a.id_, name, &v), std::string("variable '") + name + "'");
    return v;
  };
  l.label = var("label");
  l.iteration = var("iteration");
  l.origin_x = var("origin_x");
  l.origin_y = var("origin_y");
  l.in_contact = var("in_contact");
  for (std::size_t s = 0; s < kScalars.size(); ++s)
    l.scalars[s] = var(kScalars[s].name);
  for (std::size_t f = 0; f < kFields.size(); ++f)
    l.fields[f] = var(kFields[f].name);
  if (nc_inq_varid(a.id_, "uz", &l.uz) != NC_NOERR) l.uz = -1;
  if (nc_inq_varid(a.id_, "frame", &l.frame_index) != NC_NOERR) l.frame_index = -1;
  l.y_major = fields_y_major(out, a.id_, l.fields[0], l.y_dim);
  a.tip_ = read_tip(out, a.id_);
  for (const int v : l.fields)
    no_chunk_cache(out, a.id_, v, "field");
  no_chunk_cache(out, a.id_, l.in_contact, "in_contact");
  if (l.uz >= 0) no_chunk_cache(out, a.id_, l.uz, "uz");
  return a;
}

SnapshotAppender::SnapshotAppender(SnapshotAppender&& other) noexcept
    : nc_(std::move(other.nc_)),
      attributes_(std::move(other.attributes_)),
      format_(other.format_),
      label_length_(other.label_length_),
      fixed_frames_(other.fixed_frames_),
      id_(std::exchange(other.id_, -1)),
      frames_(other.frames_),
      layout_(std::move(other.layout_)),
      tip_(other.tip_) {}

SnapshotAppender::~SnapshotAppender() {
  if (id_ >= 0) nc_close(id_);
}

void SnapshotAppender::close() {
  if (id_ < 0) return;
  const Writer out("cannot write '" + nc_.string() + "': ");
  out.check(nc_close(std::exchange(id_, -1)), "closing");
}

void SnapshotAppender::define(const Snapshot& first) {
  const Writer out("cannot write '" + nc_.string() + "': ");
  out.check(nc_create(nc_.c_str(), NC_CLOBBER | NC_NETCDF4 | NC_CLASSIC_MODEL, &id_), "creating");
  layout_ = std::make_unique<Layout>();
  Layout& l = *layout_;
  l.n0 = static_cast<std::size_t>(first.block.shape.n0);
  l.n1 = static_cast<std::size_t>(first.block.shape.n1);
  l.label_length = label_length_ = std::max<std::size_t>(label_length_, first.label.size());
  const Writer& o = out;
  const auto dim = [&](const std::string& name, std::size_t length) {
    int d = -1;
    o.check(nc_def_dim(id_, name.c_str(), length, &d), "dimension '" + name + "'");
    return d;
  };
  const auto define = [&](const std::string& name, nc_type type, std::initializer_list<int> dims,
                          const std::string& units, const std::string& long_name) {
    int v = -1;
    o.check(nc_def_var(id_, name.c_str(), type, static_cast<int>(dims.size()), dims.begin(), &v),
            "variable '" + name + "'");
    put_text(o, id_, v, "units", units);
    put_text(o, id_, v, "long_name", long_name);
    return v;
  };
  // Per-frame numbers (iteration, origins, Dx, Fx, Fz, energy) and labels. In a file that
  // grows, chunks of 64 frames: netCDF's default for a variable along the unlimited dimension
  // alone is 512 to 1024 values (4-8 KiB), written whole at the first frame, 46 KiB of mostly
  // empty chunks in a one-frame file. In a file of a known number of frames (the states), no
  // chunks at all: each chunked variable also carries an HDF5 B-tree index of about 2.5 KiB
  // (h5stat), which in a one-frame state file is most of what is not its fields.
  const auto contiguous = [&](int v, const std::string& name) {
    o.check(nc_def_var_chunking(id_, v, NC_CONTIGUOUS, nullptr), "storing '" + name + "'");
  };
  const auto per_frame = [&](const std::string& name, nc_type type, const std::string& units,
                             const std::string& long_name) {
    const int v = define(name, type, {l.frame_dim}, units, long_name);
    if (fixed_frames_ > 0) {
      contiguous(v, name);
    } else {
      const std::size_t chunk[] = {64};
      o.check(nc_def_var_chunking(id_, v, NC_CHUNKED, chunk), "chunking '" + name + "'");
    }
    return v;
  };
  // Fields: one chunk per frame (a frame is written and read whole), compressed with the
  // shuffle filter, which groups the bytes of the values so that deflate finds their common
  // exponents: the sites off the contact are zeros, and tau_max and pressure change slowly.
  const auto field = [&](const std::string& name, nc_type type, const std::string& units,
                         const std::string& long_name) {
    const int v = define(name, type, {l.frame_dim, l.y_dim, l.x_dim}, units, long_name);
    const std::size_t chunk[] = {1, l.n1, l.n0};
    o.check(nc_def_var_chunking(id_, v, NC_CHUNKED, chunk), "chunking '" + name + "'");
    no_chunk_cache(o, id_, v, name);
    if (format_.deflate_level > 0) {
      o.check(nc_def_var_deflate(id_, v, 1, 1, format_.deflate_level),
              "compressing '" + name + "'");
    }
    return v;
  };
  l.frame_dim = dim("frame", fixed_frames_ > 0 ? fixed_frames_ : NC_UNLIMITED);
  l.y_dim = dim("y", l.n1);
  l.x_dim = dim("x", l.n0);
  l.label_dim = dim("label_length", l.label_length);
  // Coordinates as VTK's CF reader (ParaView's) takes them with its default settings (issue
  // 25): it reads axis "X"/"Y" as longitude/latitude (a grid on a sphere) and the unit "d" as
  // days (a time axis), so the sites' coordinates carry neither: units "1", in lattice
  // spacings. The frame index is the time axis (axis "T"): a field is then a 2D grid per frame,
  // and the per-frame numbers no longer decide which variables the reader loads.
  l.frame_index =
      per_frame("frame", NC_INT, "1", "frame index: the file's sequence of states, not a time");
  put_text(o, id_, l.frame_index, "axis", "T");
  const int x_var =
      define("x", NC_DOUBLE, {l.x_dim}, "1", "x of the first frame's sites, in lattice spacings d");
  const int y_var =
      define("y", NC_DOUBLE, {l.y_dim}, "1", "y of the first frame's sites, in lattice spacings d");
  l.label = define("label", NC_CHAR, {l.frame_dim, l.label_dim}, "1", "snapshot label");
  if (fixed_frames_ > 0) contiguous(l.label, "label");
  put_text(o, id_, l.label, "_Encoding", "utf-8");
  const auto per_frame_int = [&](const SnapshotVariable& v) {
    return per_frame(v.name, NC_INT, v.units, v.long_name);
  };
  l.iteration = per_frame_int(kIteration);
  l.origin_x = per_frame_int(kOriginX);
  l.origin_y = per_frame_int(kOriginY);
  for (std::size_t s = 0; s < kScalars.size(); ++s) {
    l.scalars[s] = per_frame(kScalars[s].name, NC_DOUBLE, kScalars[s].units, kScalars[s].long_name);
  }
  const nc_type value_type = format_.single_precision ? NC_FLOAT : NC_DOUBLE;
  for (std::size_t f = 0; f < kFields.size(); ++f)
    l.fields[f] = field(kFields[f].name, value_type, kFields[f].units, kFields[f].long_name);
  // The normal displacement exists in the explicit model only (the LFM has none).
  if (!first.uz.empty()) {
    l.uz = field(kUz.name, value_type, kUz.units, kUz.long_name);
  }
  l.in_contact = field(kInContact.name, NC_BYTE, kInContact.units, kInContact.long_name);

  if (attributes_.is_object()) {
    for (const auto& [key, value] : attributes_.items()) {
      if (value.is_boolean()) {
        const int flag = value.get<bool>() ? 1 : 0;
        o.check(nc_put_att_int(id_, NC_GLOBAL, key.c_str(), NC_INT, 1, &flag),
                "attribute '" + key + "'");
      } else if (value.is_number()) {
        const auto number = value.get<double>();
        o.check(nc_put_att_double(id_, NC_GLOBAL, key.c_str(), NC_DOUBLE, 1, &number),
                "attribute '" + key + "'");
      } else {
        put_text(o, id_, NC_GLOBAL, key,
                 value.is_string() ? value.get<std::string>() : value.dump());
      }
    }
  }
  // The tip's lattice, from the frames (all alike): the registry tracking follows
  // (interface/tip_lattice.hpp, docs/tracking.md). Written last among the numbers, so that
  // they replace entries of the same name.
  o.check(nc_put_att_double(id_, NC_GLOBAL, "tip_angle", NC_DOUBLE, 1, &first.tip.angle),
          "attribute 'tip_angle'");
  o.check(nc_put_att_double(id_, NC_GLOBAL, "tip_mismatch", NC_DOUBLE, 1, &first.tip.mismatch),
          "attribute 'tip_mismatch'");
  tip_ = first.tip;
  put_text(o, id_, NC_GLOBAL, "title", "asperity sliding snapshots");
  put_text(o, id_, NC_GLOBAL, "Conventions", "CF-1.8");
  put_text(o, id_, NC_GLOBAL, "comment",
           "x and y are the coordinates of the first frame's block; the block may follow the "
           "tip: site (i, j) of frame k is at ((origin_x[k] + i) d, (origin_y[k] + j) d)");
  put_text(o, id_, NC_GLOBAL, "label", first.label);
  put_text(o, id_, NC_GLOBAL, "field_precision", format_.single_precision ? "float32" : "float64");
  o.check(nc_enddef(id_), "ending definitions");

  std::vector<double> x(l.n0), y(l.n1);
  std::iota(x.begin(), x.end(), static_cast<double>(first.block.origin0));
  std::iota(y.begin(), y.end(), static_cast<double>(first.block.origin1));
  o.check(nc_put_var_double(id_, x_var, x.data()), "writing 'x'");
  o.check(nc_put_var_double(id_, y_var, y.data()), "writing 'y'");
}

void SnapshotAppender::append(const Snapshot& frame) {
  const std::string context = "cannot write '" + nc_.string() + "': ";
  if (!layout_) {
    validate({frame}, nullptr, context);
    define(frame);
  }
  Layout& l = *layout_;
  const Writer out(context);
  const auto invalid = [&](const std::string& problem) {
    throw std::invalid_argument(context + "frame " + std::to_string(frames_) + ": " + problem);
  };
  if (static_cast<std::size_t>(frame.block.shape.n0) != l.n0 ||
      static_cast<std::size_t>(frame.block.shape.n1) != l.n1) {
    invalid("block shape differs from the file's");
  }
  if (frame.label.size() > l.label_length) {
    invalid("label '" + frame.label + "' longer than the file's " + std::to_string(l.label_length) +
            " characters");
  }
  const std::size_t sites = l.n0 * l.n1;
  const auto sized = [&](const std::string& name, std::size_t size) {
    if (size != sites) {
      invalid("'" + name + "' has " + std::to_string(size) + " values, expected " +
              std::to_string(sites));
    }
  };
  for (const Field& f : kFields)
    sized(f.name, (frame.*f.values).size());
  sized("in_contact", frame.in_contact.size());
  // uz (explicit model only): in every frame of a file or in none.
  if (l.uz >= 0) sized("uz", frame.uz.size());
  if (l.uz < 0 && !frame.uz.empty()) invalid("'uz' given, but the file's frames have none");
  if (!(frame.tip == tip_)) invalid("tip lattice differs from the file's");

  if (fixed_frames_ > 0 && frames_ >= fixed_frames_) {
    invalid("the file holds " + std::to_string(fixed_frames_) + " frames");
  }
  const std::size_t k = frames_;
  const std::size_t at[] = {k, 0}, one_label[] = {1, l.label_length};
  std::string label(l.label_length, '\0');
  std::copy(frame.label.begin(), frame.label.end(), label.begin());
  out.check(nc_put_vara_text(id_, l.label, at, one_label, label.data()), "writing 'label'");
  const std::size_t one[] = {1};
  out.check(nc_put_vara_int(id_, l.iteration, at, one, &frame.iteration), "writing 'iteration'");
  out.check(nc_put_vara_int(id_, l.origin_x, at, one, &frame.block.origin0), "writing 'origin_x'");
  out.check(nc_put_vara_int(id_, l.origin_y, at, one, &frame.block.origin1), "writing 'origin_y'");
  for (std::size_t s = 0; s < kScalars.size(); ++s) {
    out.check(nc_put_vara_double(id_, l.scalars[s], at, one, &(frame.*kScalars[s].value)),
              std::string("writing '") + kScalars[s].name + "'");
  }
  if (l.frame_index >= 0) {
    const int index = static_cast<int>(k);
    out.check(nc_put_vara_int(id_, l.frame_index, at, one, &index), "writing 'frame'");
  }
  const std::size_t start[] = {k, 0, 0};
  const std::size_t count[] = {1, l.y_major ? l.n1 : l.n0, l.y_major ? l.n0 : l.n1};
  // In the file's order (transpose()); an older file's fields are appended as they are.
  const auto put = [&](int var, const std::vector<double>& values, const std::string& name) {
    const double* data = values.data();
    if (l.y_major) {
      l.values.resize(sites);
      transpose(values.data(), l.n0, l.n1, l.values.data());
      data = l.values.data();
    }
    out.check(nc_put_vara_double(id_, var, start, count, data), "writing '" + name + "'");
  };
  for (std::size_t f = 0; f < kFields.size(); ++f)
    put(l.fields[f], frame.*kFields[f].values, kFields[f].name);
  const unsigned char* flags = frame.in_contact.data();
  if (l.y_major) {
    l.flags.resize(sites);
    transpose(frame.in_contact.data(), l.n0, l.n1, l.flags.data());
    flags = l.flags.data();
  }
  out.check(nc_put_vara_uchar(id_, l.in_contact, start, count, flags), "writing 'in_contact'");
  if (l.uz >= 0) put(l.uz, frame.uz, "uz");
  ++frames_;
}

Snapshot SnapshotAppender::read(std::size_t k) const {
  // A file this run writes: a failure to read it back is an I/O error, not bad input.
  const Writer in("cannot read frame " + std::to_string(k) + " of '" + nc_.string() + "': ");
  if (!layout_ || k >= frames_) in.fail("no such frame");
  const Layout& l = *layout_;
  Snapshot frame;
  const std::size_t at[] = {k, 0}, one_label[] = {1, l.label_length}, one[] = {1};
  std::string label(l.label_length, '\0');
  in.check(nc_get_vara_text(id_, l.label, at, one_label, label.data()), "reading 'label'");
  frame.label.assign(label.c_str());
  int origin0 = 0, origin1 = 0;
  in.check(nc_get_vara_int(id_, l.iteration, at, one, &frame.iteration), "reading 'iteration'");
  in.check(nc_get_vara_int(id_, l.origin_x, at, one, &origin0), "reading 'origin_x'");
  in.check(nc_get_vara_int(id_, l.origin_y, at, one, &origin1), "reading 'origin_y'");
  frame.block = {{static_cast<int>(l.n0), static_cast<int>(l.n1)}, origin0, origin1};
  frame.tip = tip_;
  for (std::size_t s = 0; s < kScalars.size(); ++s) {
    in.check(nc_get_vara_double(id_, l.scalars[s], at, one, &(frame.*kScalars[s].value)),
             std::string("reading '") + kScalars[s].name + "'");
  }
  read_fields(in, id_, l.fields, l.in_contact, l.uz, k, l.n0, l.n1, l.y_major, frame);
  return frame;
}

void write_snapshots(const fs::path& nc, const std::vector<Snapshot>& frames,
                     const nlohmann::json& attributes, const SnapshotFormat& format) {
  const std::string context = "cannot write '" + nc.string() + "': ";
  validate(frames, attributes, context);
  std::size_t label_length = 1;
  for (const Snapshot& f : frames)
    label_length = std::max(label_length, f.label.size());
  // Named: HDF5 resolves the path it is given (realpath), which an unnamed file's /proc path
  // defeats. The write takes milliseconds; a kill within them leaves a hidden temporary, which
  // the next run removes (remove_stale_temporaries).
  TemporaryFile tmp(nc, TemporaryFile::Kind::named);
  {
    SnapshotAppender out(tmp.path(), attributes, format, label_length, frames.size());
    for (const Snapshot& f : frames)
      out.append(f);
    out.close();
  }
  tmp.commit();
}

namespace {

// read_snapshots into `frames`, or with `frames` null only its checks of the header:
// dimensions, sizes, the memory the frames need and every variable's presence and shape (no
// field is read). Returns the number of frames.
std::size_t read_file(const fs::path& nc, std::vector<Snapshot>* out,
                      const std::string& only_label = {}) {
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
  // The labels and scalars of every frame are read to select frames (a few bytes each); the
  // fields of the selected ones only.
  const auto check_memory = [&](std::size_t frames, const std::string& which) {
    check_fits_in_memory("'" + nc.string() + "'",
                         static_cast<double>(frames) *
                             (sites * 8.0 * fields_per_site + static_cast<double>(label_length) +
                              static_cast<double>(sizeof(Snapshot))),
                         std::to_string(frames) + " " + which + "frames of " + std::to_string(n0) +
                             " x " + std::to_string(n1) + " sites, as its header says");
  };
  if (only_label.empty()) check_memory(n, "");
  check_fits_in_memory("'" + nc.string() + "'",
                       static_cast<double>(n) * (static_cast<double>(label_length) +
                                                 static_cast<double>(sizeof(Snapshot))),
                       std::to_string(n) + " frame labels, as its header says");

  // Looks up a variable and checks its dimensions, so that reads cannot overrun the buffers.
  const auto var = [&](const std::string& name, const std::vector<int>& dims) {
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
  // Fields (frame, y, x), or (frame, x, y) in files written before (transpose()).
  int ux = -1;
  if (nc_inq_varid(in.id, "ux", &ux) != NC_NOERR) in.fail("variable 'ux' missing");
  const bool y_major = fields_y_major(in, in.id, ux, y_dim);
  const std::vector<int> field_dims = y_major ? std::vector<int>{frame_dim, y_dim, x_dim}
                                              : std::vector<int>{frame_dim, x_dim, y_dim};
  const interface::TipLattice tip = read_tip(in, in.id);
  if (out == nullptr) {
    var("label", {frame_dim, label_dim});
    for (const char* name : {"iteration", "origin_x", "origin_y"})
      var(name, {frame_dim});
    for (const Scalar& sc : kScalars)
      var(sc.name, {frame_dim});
    for (const Field& f : kFields)
      var(f.name, field_dims);
    var("in_contact", field_dims);
    return n;
  }
  const auto get_ints = [&](const std::string& name) {
    std::vector<int> values(n);
    in.check(nc_get_var_int(in.id, var(name, {frame_dim}), values.data()),
             "reading '" + name + "'");
    return values;
  };

  std::vector<Snapshot> frames(n);
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
    frames[k].tip = tip;
  }
  for (const Scalar& s : kScalars) {
    std::vector<double> values(n);
    in.check(nc_get_var_double(in.id, var(s.name, {frame_dim}), values.data()),
             std::string("reading '") + s.name + "'");
    for (std::size_t k = 0; k < n; ++k)
      frames[k].*s.value = values[k];
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(frames[k].Dx)) in.fail("non-finite 'Dx' in frame " + std::to_string(k));
  }
  std::vector<std::size_t> selected;
  for (std::size_t k = 0; k < n; ++k) {
    if (only_label.empty() || frames[k].label == only_label) selected.push_back(k);
  }
  if (!only_label.empty()) check_memory(selected.size(), "'" + only_label + "' ");
  std::array<int, kFields.size()> field_vars{};
  for (std::size_t f = 0; f < kFields.size(); ++f)
    field_vars[f] = var(kFields[f].name, field_dims);
  const int contact_var = var("in_contact", field_dims);
  int uz_var = -1;
  if (nc_inq_varid(in.id, "uz", &uz_var) == NC_NOERR) {
    uz_var = var("uz", field_dims);
  } else {
    uz_var = -1;
  }
  out->clear();
  out->reserve(selected.size());
  for (const std::size_t k : selected) {
    read_fields(in, in.id, field_vars, contact_var, uz_var, k, n0, n1, y_major, frames[k]);
    out->push_back(std::move(frames[k]));
  }
  return n;
}

}  // namespace

const std::vector<SnapshotVariable>& snapshot_variables() {
  static const std::vector<SnapshotVariable> all = [] {
    std::vector<SnapshotVariable> v;
    for (const Field& f : kFields)
      v.push_back({f.name, f.units, f.long_name, true});
    v.push_back(kUz);
    v.push_back(kInContact);
    for (const Scalar& sc : kScalars)
      v.push_back({sc.name, sc.units, sc.long_name, false});
    v.push_back(kIteration);
    v.push_back(kOriginX);
    v.push_back(kOriginY);
    return v;
  }();
  return all;
}

std::vector<Snapshot> read_snapshots(const fs::path& nc, const std::string& label) {
  std::vector<Snapshot> frames;
  read_file(nc, &frames, label);
  return frames;
}

std::size_t check_snapshot_file(const fs::path& nc) {
  return read_file(nc, nullptr);
}

}  // namespace asperity::app
