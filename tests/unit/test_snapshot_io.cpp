// NetCDF snapshot files: round trip, metadata, invalid input and damaged files.
#include <netcdf.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "scratch.hpp"

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/apps/common/snapshot_sink.hpp"
#include "asperity/tracking/census.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"
#include "asperity/tracking/synthetic.hpp"

namespace asperity::app {
namespace {

using asperity::test_support::invalid_argument_message;

namespace fs = std::filesystem;
using slide::Snapshot;

// A 3 x 4 block whose values all differ between frames and sites, with a few special doubles.
Snapshot frame(int k, std::string label, int iteration, int origin0, int origin1) {
  Snapshot s;
  s.label = std::move(label);
  s.iteration = iteration;
  s.Dx = 0.1 * k + 1.0 / 3.0;
  s.Fx = -std::sqrt(2.0 + k);
  s.Fz = 1e300 * (k + 1);
  s.energy = std::nextafter(1.0 + k, 2.0 + k);
  s.block = {{3, 4}, origin0, origin1};
  const auto values = [&](double scale) {
    std::vector<double> v;
    for (std::size_t i = 0; i < s.block.shape.count(); ++i)
      v.push_back(scale * std::exp(0.37 * static_cast<double>(i) + k));
    return v;
  };
  s.ux = values(1.0);
  s.uy = values(-2.0);
  s.sx = values(3.0);
  s.sy = values(1e-310);  // subnormal
  s.tau_x = values(-0.5);
  s.tau_y = values(0.25);
  s.tau_max = values(7.0);
  s.pressure = values(11.0);
  s.ux[0] = -0.0;
  s.uy[1] = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < s.block.shape.count(); ++i)
    s.in_contact.push_back(static_cast<std::uint8_t>((i + static_cast<std::size_t>(k)) % 2));
  return s;
}

std::vector<Snapshot> frames() {
  return {frame(0, "peak", -1, -5, -6), frame(1, "slip_001_path", 17, -4, -6),
          frame(2, "x", 0, 10, 3)};
}

std::vector<std::uint64_t> bits(const std::vector<double>& v) {
  std::vector<std::uint64_t> b;
  for (double x : v)
    b.push_back(std::bit_cast<std::uint64_t>(x));
  return b;
}

class SnapshotIo : public asperity::test_support::ScratchDirTest {};

TEST_F(SnapshotIo, RoundTripIsBitIdentical) {
  const fs::path nc = dir_ / "snapshots.nc";
  const std::vector<Snapshot> written = frames();
  write_snapshots(nc, written, nlohmann::json::object());
  EXPECT_EQ(entries(), 1u);  // no temporary left
  const std::vector<Snapshot> read = read_snapshots(nc);
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t k = 0; k < read.size(); ++k) {
    const Snapshot &a = written[k], &b = read[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(b.label, a.label);
    EXPECT_EQ(b.iteration, a.iteration);
    EXPECT_EQ(b.block.shape, a.block.shape);
    EXPECT_EQ(b.block.origin0, a.block.origin0);
    EXPECT_EQ(b.block.origin1, a.block.origin1);
    EXPECT_EQ(bits({b.Dx, b.Fx, b.Fz, b.energy}), bits({a.Dx, a.Fx, a.Fz, a.energy}));
    for (auto field : {&Snapshot::ux, &Snapshot::uy, &Snapshot::sx, &Snapshot::sy, &Snapshot::tau_x,
                       &Snapshot::tau_y, &Snapshot::tau_max, &Snapshot::pressure})
      EXPECT_EQ(bits(b.*field), bits(a.*field));
    EXPECT_EQ(b.in_contact, a.in_contact);
  }
}

TEST_F(SnapshotIo, MetadataAndAttributes) {
  const fs::path nc = dir_ / "s.nc";
  write_snapshots(nc, frames(),
                  {{"alpha", 0.25}, {"scene", "default"}, {"adaptive", true}, {"n", {1, 2}}});
  int id = -1;
  ASSERT_EQ(nc_open(nc.c_str(), NC_NOWRITE, &id), NC_NOERR);
  const auto text = [&](int var, const char* name) {
    std::size_t length = 0;
    if (nc_inq_attlen(id, var, name, &length) != NC_NOERR) return std::string("<missing>");
    std::string s(length, '\0');
    EXPECT_EQ(nc_get_att_text(id, var, name, s.data()), NC_NOERR);
    return s;
  };
  EXPECT_EQ(text(NC_GLOBAL, "Conventions"), "CF-1.8");
  EXPECT_EQ(text(NC_GLOBAL, "label"), "peak");
  EXPECT_NE(text(NC_GLOBAL, "title"), "<missing>");
  EXPECT_EQ(text(NC_GLOBAL, "scene"), "default");
  EXPECT_EQ(text(NC_GLOBAL, "n"), "[1,2]");
  double alpha = 0.0;
  int adaptive = -1;
  EXPECT_EQ(nc_get_att_double(id, NC_GLOBAL, "alpha", &alpha), NC_NOERR);
  EXPECT_EQ(nc_get_att_int(id, NC_GLOBAL, "adaptive", &adaptive), NC_NOERR);
  EXPECT_EQ(alpha, 0.25);
  EXPECT_EQ(adaptive, 1);

  int nvars = 0, var = -1;
  ASSERT_EQ(nc_inq_nvars(id, &nvars), NC_NOERR);
  EXPECT_EQ(nvars, 20);
  for (int v = 0; v < nvars; ++v) {
    EXPECT_NE(text(v, "units"), "<missing>") << "variable " << v;
    EXPECT_NE(text(v, "long_name"), "<missing>") << "variable " << v;
  }
  ASSERT_EQ(nc_inq_varid(id, "Fx", &var), NC_NOERR);
  EXPECT_EQ(text(var, "units"), "G d^2");
  double x[3] = {}, y[4] = {};
  ASSERT_EQ(nc_inq_varid(id, "x", &var), NC_NOERR);
  ASSERT_EQ(nc_get_var_double(id, var, x), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(id, "y", &var), NC_NOERR);
  ASSERT_EQ(nc_get_var_double(id, var, y), NC_NOERR);
  EXPECT_EQ(x[0], -5.0);  // first frame's block
  EXPECT_EQ(x[2], -3.0);
  EXPECT_EQ(y[0], -6.0);
  EXPECT_EQ(y[3], -3.0);
  // As VTK's CF reader takes them (issue 25): x and y without axis "X"/"Y" (longitude and
  // latitude to VTK) and without unit "d" (days); the frame index is the time axis.
  EXPECT_EQ(text(var, "units"), "1");
  EXPECT_EQ(text(var, "axis"), "<missing>");
  ASSERT_EQ(nc_inq_varid(id, "frame", &var), NC_NOERR);
  EXPECT_EQ(text(var, "axis"), "T");
  int index[3] = {-1, -1, -1};
  ASSERT_EQ(nc_get_var_int(id, var, index), NC_NOERR);
  EXPECT_EQ(index[0], 0);
  EXPECT_EQ(index[2], 2);
  // Fields (frame, y, x): x varies fastest in the file, as VTK's x axis.
  int dims[3] = {}, ndims = 0, x_dim = -1, y_dim = -1;
  ASSERT_EQ(nc_inq_dimid(id, "x", &x_dim), NC_NOERR);
  ASSERT_EQ(nc_inq_dimid(id, "y", &y_dim), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(id, "tau_max", &var), NC_NOERR);
  ASSERT_EQ(nc_inq_var(id, var, nullptr, nullptr, &ndims, dims, nullptr), NC_NOERR);
  ASSERT_EQ(ndims, 3);
  EXPECT_EQ(dims[1], y_dim);
  EXPECT_EQ(dims[2], x_dim);
  const Snapshot first = frames()[1];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      const std::size_t at[] = {1, static_cast<std::size_t>(j), static_cast<std::size_t>(i)};
      double value = 0.0;
      ASSERT_EQ(nc_get_var1_double(id, var, at, &value), NC_NOERR);
      EXPECT_EQ(value, first.tau_max[first.block.shape.index(i, j)]) << i << ", " << j;
    }
  }
  nc_type type = NC_NAT;
  ASSERT_EQ(nc_inq_varid(id, "in_contact", &var), NC_NOERR);
  ASSERT_EQ(nc_inq_vartype(id, var, &type), NC_NOERR);
  EXPECT_EQ(type, NC_BYTE);
  EXPECT_EQ(nc_close(id), NC_NOERR);
}

// A copy of `from` in the layout of the files written before issue 25: fields (frame, x, y), no
// frame coordinate.
void write_xy_layout_copy(const fs::path& from, const fs::path& to) {
  int in = -1, out = -1, ndims = 0, nvars = 0, unlimited = -1;
  ASSERT_EQ(nc_open(from.c_str(), NC_NOWRITE, &in), NC_NOERR);
  ASSERT_EQ(nc_create(to.c_str(), NC_CLOBBER | NC_NETCDF4 | NC_CLASSIC_MODEL, &out), NC_NOERR);
  ASSERT_EQ(nc_inq(in, &ndims, &nvars, nullptr, &unlimited), NC_NOERR);
  std::vector<int> new_dim(static_cast<std::size_t>(ndims));
  for (const char* name : {"frame", "x", "y", "label_length"}) {
    int d = -1;
    std::size_t length = 0;
    ASSERT_EQ(nc_inq_dimid(in, name, &d), NC_NOERR);
    ASSERT_EQ(nc_inq_dimlen(in, d, &length), NC_NOERR);
    ASSERT_EQ(nc_def_dim(out, name, d == unlimited ? NC_UNLIMITED : length,
                         &new_dim[static_cast<std::size_t>(d)]),
              NC_NOERR);
  }
  std::vector<std::pair<int, int>> fields;  // (in, out) variables to transpose
  for (int v = 0; v < nvars; ++v) {
    char name[NC_MAX_NAME + 1] = {};
    nc_type type = NC_NAT;
    int vdims[NC_MAX_VAR_DIMS] = {}, nd = 0, natts = 0, w = -1;
    ASSERT_EQ(nc_inq_var(in, v, name, &type, &nd, vdims, &natts), NC_NOERR);
    if (std::string(name) == "frame") continue;
    int mapped[3] = {};
    for (int k = 0; k < nd; ++k)
      mapped[k] = new_dim[static_cast<std::size_t>(vdims[k])];
    if (nd == 3) std::swap(mapped[1], mapped[2]);
    ASSERT_EQ(nc_def_var(out, name, type, nd, mapped, &w), NC_NOERR);
    for (int a = 0; a < natts; ++a) {
      char att[NC_MAX_NAME + 1] = {};
      ASSERT_EQ(nc_inq_attname(in, v, a, att), NC_NOERR);
      ASSERT_EQ(nc_copy_att(in, v, att, out, w), NC_NOERR);
    }
    if (nd == 3) fields.emplace_back(v, w);
  }
  ASSERT_EQ(nc_enddef(out), NC_NOERR);
  for (int v = 0; v < nvars; ++v) {
    char name[NC_MAX_NAME + 1] = {};
    int nd = 0, w = -1, vdims[NC_MAX_VAR_DIMS] = {};
    ASSERT_EQ(nc_inq_var(in, v, name, nullptr, &nd, vdims, nullptr), NC_NOERR);
    if (nd == 3 || std::string(name) == "frame") continue;
    ASSERT_EQ(nc_inq_varid(out, name, &w), NC_NOERR);
    std::size_t start[2] = {}, count[2] = {};  // explicit: the copy's frame dimension is empty
    for (int k = 0; k < nd; ++k)
      ASSERT_EQ(nc_inq_dimlen(in, vdims[k], &count[k]), NC_NOERR);
    std::vector<char> bytes(1 << 16);  // every non-field variable of these files is smaller
    ASSERT_EQ(nc_get_var(in, v, bytes.data()), NC_NOERR);
    ASSERT_EQ(nc_put_vara(out, w, start, count, bytes.data()), NC_NOERR);
  }
  std::size_t n = 0, nx = 0, ny = 0;
  int d = -1;
  ASSERT_EQ(nc_inq_dimid(in, "frame", &d), NC_NOERR);
  ASSERT_EQ(nc_inq_dimlen(in, d, &n), NC_NOERR);
  ASSERT_EQ(nc_inq_dimid(in, "x", &d), NC_NOERR);
  ASSERT_EQ(nc_inq_dimlen(in, d, &nx), NC_NOERR);
  ASSERT_EQ(nc_inq_dimid(in, "y", &d), NC_NOERR);
  ASSERT_EQ(nc_inq_dimlen(in, d, &ny), NC_NOERR);
  for (const auto& [v, w] : fields) {
    std::vector<double> yx(n * nx * ny), xy(n * nx * ny);
    ASSERT_EQ(nc_get_var_double(in, v, yx.data()), NC_NOERR);
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t i = 0; i < nx; ++i) {
        for (std::size_t j = 0; j < ny; ++j)
          xy[(k * nx + i) * ny + j] = yx[(k * ny + j) * nx + i];
      }
    }
    const std::size_t start[3] = {}, count[3] = {n, nx, ny};
    ASSERT_EQ(nc_put_vara_double(out, w, start, count, xy.data()), NC_NOERR);
  }
  ASSERT_EQ(nc_close(out), NC_NOERR);
  ASSERT_EQ(nc_close(in), NC_NOERR);
}

// Files written before the (frame, y, x) layout (runs in flight, committed answers) still read,
// to the same frames, and an appender continues them in their own layout.
TEST_F(SnapshotIo, ReadsAndAppendsTheOlderXYLayout) {
  const fs::path now = dir_ / "now.nc", before = dir_ / "before.nc";
  const std::vector<Snapshot> written = frames();
  {
    SnapshotAppender out(now, nlohmann::json::object(), {}, 16);
    out.append(written[0]);
    out.append(written[1]);
    out.close();
  }
  write_xy_layout_copy(now, before);
  ASSERT_FALSE(HasFatalFailure());
  {  // the copy is in the older layout
    int id = -1, var = -1, x_dim = -1, dims[3] = {}, ndims = 0;
    ASSERT_EQ(nc_open(before.c_str(), NC_NOWRITE, &id), NC_NOERR);
    ASSERT_EQ(nc_inq_dimid(id, "x", &x_dim), NC_NOERR);
    ASSERT_EQ(nc_inq_varid(id, "ux", &var), NC_NOERR);
    ASSERT_EQ(nc_inq_var(id, var, nullptr, nullptr, &ndims, dims, nullptr), NC_NOERR);
    EXPECT_EQ(dims[1], x_dim);
    EXPECT_NE(nc_inq_varid(id, "frame", &var), NC_NOERR);
    nc_close(id);
  }
  {
    SnapshotAppender more = SnapshotAppender::open(before);
    EXPECT_EQ(bits(more.read(1).tau_y), bits(written[1].tau_y));
    more.append(written[2]);
    more.close();
  }
  const std::vector<Snapshot> read = read_snapshots(before);
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(check_snapshot_file(before), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(read[k].label, written[k].label);
    for (auto field : {&Snapshot::ux, &Snapshot::uy, &Snapshot::sx, &Snapshot::sy, &Snapshot::tau_x,
                       &Snapshot::tau_y, &Snapshot::tau_max, &Snapshot::pressure})
      EXPECT_EQ(bits(read[k].*field), bits(written[k].*field));
    EXPECT_EQ(read[k].in_contact, written[k].in_contact);
  }
}

// The tip's lattice (slide::Snapshot::tip) is the file's: global attributes tip_angle and
// tip_mismatch, read back into every frame; absent (files written before them): aligned. A
// frame of another tip does not go into the file.
TEST_F(SnapshotIo, TipLatticeIsAGlobalAttribute) {
  std::vector<Snapshot> rotated = frames();
  for (Snapshot& f : rotated)
    f.tip = {.angle = 2.5, .mismatch = -0.01};
  const fs::path nc = dir_ / "tip.nc";
  write_snapshots(nc, rotated, {{"tip_angle", "ignored: the frames' tip is written"}});
  for (const Snapshot& f : read_snapshots(nc)) {
    EXPECT_EQ(f.tip.angle, 2.5);
    EXPECT_EQ(f.tip.mismatch, -0.01);
  }
  SnapshotAppender more = SnapshotAppender::open(nc);
  EXPECT_EQ(more.read(0).tip.angle, 2.5);
  more.close();
  // A file without the attributes: drop them (as written before issue 27).
  int id = -1;
  ASSERT_EQ(nc_open(nc.c_str(), NC_WRITE, &id), NC_NOERR);
  ASSERT_EQ(nc_redef(id), NC_NOERR);
  ASSERT_EQ(nc_del_att(id, NC_GLOBAL, "tip_angle"), NC_NOERR);
  ASSERT_EQ(nc_del_att(id, NC_GLOBAL, "tip_mismatch"), NC_NOERR);
  ASSERT_EQ(nc_close(id), NC_NOERR);
  EXPECT_TRUE(read_snapshots(nc).front().tip.aligned());
  // Frames of two tips in one file.
  rotated[1].tip.angle = 3.0;
  EXPECT_NE(invalid_argument_message([&] {
              write_snapshots(dir_ / "two.nc", rotated, {});
            }).find("tip lattice differs"),
            std::string::npos);
  SnapshotAppender appender(dir_ / "grow.nc", {}, {});
  appender.append(rotated[0]);
  EXPECT_THROW(appender.append(rotated[1]), std::invalid_argument);
}

TEST_F(SnapshotIo, InvalidInputThrowsAndWritesNothing) {
  const fs::path nc = dir_ / "s.nc";
  EXPECT_THROW(write_snapshots(nc, {}, {}), std::invalid_argument);
  std::vector<Snapshot> f = frames();
  f[1].block.shape = {4, 3};
  EXPECT_NE(invalid_argument_message([&] { write_snapshots(nc, f, {}); }).find("frame 1"),
            std::string::npos);
  f = frames();
  f[2].pressure.pop_back();
  EXPECT_NE(invalid_argument_message([&] { write_snapshots(nc, f, {}); }).find("'pressure'"),
            std::string::npos);
  EXPECT_THROW(write_snapshots(nc, frames(), nlohmann::json::array()), std::invalid_argument);
  EXPECT_EQ(entries(), 0u);
  EXPECT_THROW(write_snapshots(dir_ / "missing" / "s.nc", frames(), {}), std::runtime_error);
}

TEST_F(SnapshotIo, DamagedFilesThrowInvalidArgument) {
  const fs::path nc = dir_ / "s.nc";
  EXPECT_NE(invalid_argument_message([&] { read_snapshots(nc); }).find(nc.string()),
            std::string::npos);

  write_snapshots(nc, frames(), {});
  fs::resize_file(nc, fs::file_size(nc) / 2);
  const std::string truncated = invalid_argument_message([&] { read_snapshots(nc); });
  EXPECT_NE(truncated.find(nc.string()), std::string::npos) << truncated;

  write_snapshots(nc, frames(), {});
  int id = -1;
  ASSERT_EQ(nc_open(nc.c_str(), NC_WRITE, &id), NC_NOERR);
  ASSERT_EQ(nc_redef(id), NC_NOERR);
  int var = -1;
  ASSERT_EQ(nc_inq_varid(id, "ux", &var), NC_NOERR);
  ASSERT_EQ(nc_rename_var(id, var, "ux_old"), NC_NOERR);
  ASSERT_EQ(nc_close(id), NC_NOERR);
  EXPECT_NE(invalid_argument_message([&] { read_snapshots(nc); }).find("variable 'ux' missing"),
            std::string::npos);

  // A non-finite field value (a damaged file) is named, not read as an empty frame.
  write_snapshots(nc, frames(), {});
  ASSERT_EQ(nc_open(nc.c_str(), NC_WRITE, &id), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(id, "tau_x", &var), NC_NOERR);
  const std::size_t at[] = {1, 2, 1};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ASSERT_EQ(nc_put_var1_double(id, var, at, &nan), NC_NOERR);
  ASSERT_EQ(nc_close(id), NC_NOERR);
  const std::string non_finite = invalid_argument_message([&] { read_snapshots(nc); });
  EXPECT_NE(non_finite.find("non-finite values in 'tau_x' of frame 1"), std::string::npos)
      << non_finite;
}

// The sizes in a file's header decide the reader's allocations. A classic-format snapshot
// (the fuzz seed tests/fuzz/corpus/snapshot/classic_3x2.nc, one frame) whose record count is
// patched to 2^31 - 1 claims far more data than its 1268 bytes: rejected before any allocation
// (it once ended in std::bad_alloc); patched to 0 it has no frames. A netCDF-4 file (compressed
// data may be smaller than its values) is checked against memory: with ASPERITY_MEMORY_GIB
// set to 1 MiB a 2 x 2 x 300 x 300 file is refused with the estimate.
TEST_F(SnapshotIo, HeaderSizesAreCheckedBeforeAllocation) {
  std::ifstream in(CLASSIC_SEED, std::ios::binary);
  ASSERT_TRUE(in.good()) << CLASSIC_SEED;
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  ASSERT_EQ(bytes.substr(0, 4), std::string("CDF\x01", 4));
  EXPECT_EQ(read_snapshots(CLASSIC_SEED).size(), 1u);
  EXPECT_EQ(check_snapshot_file(CLASSIC_SEED), 1u);
  const auto patched = [&](const std::string& numrecs) {
    const fs::path nc = dir_ / "patched.nc";
    std::ofstream(nc, std::ios::binary) << bytes.substr(0, 4) + numrecs + bytes.substr(8);
    return invalid_argument_message([&] { read_snapshots(nc); });
  };
  const std::string huge = patched(std::string("\x7f\xff\xff\xff", 4));
  EXPECT_NE(huge.find("2147483647 frames of 3 x 2 sites in a file of 1268 bytes"),
            std::string::npos)
      << huge;
  const std::string none = patched(std::string(4, '\0'));
  EXPECT_NE(none.find("no frames"), std::string::npos) << none;

  std::vector<Snapshot> big = frames();
  big.resize(2);
  for (auto& f : big) {
    f.block.shape = {300, 300};
    const std::size_t n = f.block.shape.count();
    for (auto* v : {&f.ux, &f.uy, &f.sx, &f.sy, &f.tau_x, &f.tau_y, &f.tau_max, &f.pressure})
      v->assign(n, 0.5);
    f.in_contact.assign(n, 1);
    f.uz.clear();
  }
  const fs::path nc = dir_ / "big.nc";
  write_snapshots(nc, big, {});
  ASSERT_EQ(::setenv("ASPERITY_MEMORY_GIB", "0.001", 1), 0);
  const std::string memory = invalid_argument_message([&] { check_snapshot_file(nc); });
  ::unsetenv("ASPERITY_MEMORY_GIB");
  EXPECT_NE(memory.find("GiB of memory (2 frames of 300 x 300 sites"), std::string::npos) << memory;
  EXPECT_EQ(read_snapshots(nc).size(), 2u);
}

TEST_F(SnapshotIo, NcdumpReadsTheHeader) {
  if (std::system("command -v ncdump > /dev/null 2>&1") != 0) GTEST_SKIP() << "no ncdump";
  const fs::path nc = dir_ / "s.nc";
  write_snapshots(nc, frames(), {{"alpha", 0.25}});
  const fs::path out = dir_ / "header.txt";
  ASSERT_EQ(std::system(("ncdump -h '" + nc.string() + "' > '" + out.string() + "' 2>&1").c_str()),
            0);
  std::ifstream in(out);
  const std::string header((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(header.find(":Conventions = \"CF-1.8\""), std::string::npos) << header;
  EXPECT_NE(header.find("double ux(frame, y, x)"), std::string::npos) << header;
}

// The paths file of a run grows frame by frame (SnapshotAppender): frames read back as written,
// bit for bit, also after the file was closed and opened again to append (a resumed run), and
// read_snapshots can select one label (the path of one slip).
TEST_F(SnapshotIo, AppenderGrowsTheFileFrameByFrame) {
  const fs::path nc = dir_ / "paths.nc";
  const std::vector<Snapshot> written = {frame(0, "slip_001_path", 5, -4, -6),
                                         frame(1, "slip_001_path", 10, -4, -6),
                                         frame(2, "slip_011_path", 5, 3, -6)};
  {
    SnapshotAppender out(nc, {{"a", 50.0}}, {});
    EXPECT_FALSE(fs::exists(nc));  // created at the first frame
    out.append(written[0]);
    out.append(written[1]);
    EXPECT_EQ(out.frames(), 2u);
    EXPECT_EQ(bits(out.read(1).ux), bits(written[1].ux));
    out.close();
  }
  {
    SnapshotAppender out = SnapshotAppender::open(nc);
    EXPECT_EQ(out.frames(), 2u);
    out.append(written[2]);
    // Another block shape cannot join the file.
    Snapshot other = frame(3, "slip_021_path", 5, 0, 0);
    other.block.shape = {4, 3};
    EXPECT_THROW(out.append(other), std::invalid_argument);
    EXPECT_EQ(out.frames(), 3u);
  }
  const std::vector<Snapshot> all = read_snapshots(nc);
  ASSERT_EQ(all.size(), 3u);
  for (std::size_t k = 0; k < all.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(all[k].label, written[k].label);
    EXPECT_EQ(all[k].iteration, written[k].iteration);
    EXPECT_EQ(all[k].block.origin0, written[k].block.origin0);
    EXPECT_EQ(bits({all[k].Dx, all[k].energy}), bits({written[k].Dx, written[k].energy}));
    EXPECT_EQ(bits(all[k].tau_x), bits(written[k].tau_x));
    EXPECT_EQ(all[k].in_contact, written[k].in_contact);
  }
  const std::vector<Snapshot> first = read_snapshots(nc, "slip_001_path");
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[1].iteration, 10);
  EXPECT_TRUE(read_snapshots(nc, "slip_999_path").empty());
  int id = -1;
  ASSERT_EQ(nc_open(nc.c_str(), NC_NOWRITE, &id), NC_NOERR);
  int frame_dim = -1, unlimited = -2;
  ASSERT_EQ(nc_inq_dimid(id, "frame", &frame_dim), NC_NOERR);
  ASSERT_EQ(nc_inq_unlimdim(id, &unlimited), NC_NOERR);
  EXPECT_EQ(unlimited, frame_dim);
  nc_close(id);
}

// float storage: every field comes back as the float nearest to what was written (the reader
// widens it to double); the scalars stay double. Deflate and shuffle leave the values alone and
// shrink a frame that is mostly zeros, as a block is off the contact.
TEST_F(SnapshotIo, SinglePrecisionAndCompression) {
  Snapshot f = frame(1, "peak", -1, 0, 0);
  f.sy = f.sx;  // no subnormals: they do not survive float
  f.uy[1] = 1.0;
  write_snapshots(dir_ / "float.nc", {f}, {}, {.single_precision = true, .deflate_level = 1});
  const Snapshot g = read_snapshots(dir_ / "float.nc").front();
  for (std::size_t i = 0; i < f.ux.size(); ++i) {
    EXPECT_EQ(g.ux[i], static_cast<double>(static_cast<float>(f.ux[i])));
    EXPECT_EQ(g.tau_max[i], static_cast<double>(static_cast<float>(f.tau_max[i])));
  }
  EXPECT_EQ(bits({g.Dx, g.Fz}), bits({f.Dx, f.Fz}));

  Snapshot big;
  big.label = "slip_001_before";
  big.block = {{200, 200}, -100, -100};
  const std::size_t n = big.block.shape.count();
  for (auto field : {&Snapshot::ux, &Snapshot::uy, &Snapshot::sx, &Snapshot::sy, &Snapshot::tau_x,
                     &Snapshot::tau_y, &Snapshot::tau_max, &Snapshot::pressure})
    (big.*field).assign(n, 0.0);
  big.in_contact.assign(n, 0);
  for (std::size_t i = 0; i < n / 10; ++i)
    big.ux[i] = std::sin(0.01 * static_cast<double>(i));
  write_snapshots(dir_ / "plain.nc", {big}, {}, {.deflate_level = 0});
  write_snapshots(dir_ / "deflated.nc", {big}, {}, {.deflate_level = 1});
  EXPECT_GT(fs::file_size(dir_ / "plain.nc"), 8u * 8u * n);
  EXPECT_LT(fs::file_size(dir_ / "deflated.nc"), fs::file_size(dir_ / "plain.nc") / 4);
  EXPECT_EQ(bits(read_snapshots(dir_ / "deflated.nc").front().ux), bits(big.ux));
  EXPECT_THROW(write_snapshots(dir_ / "bad.nc", {big}, {}, {.deflate_level = 10}),
               std::invalid_argument);
}

// A one-frame file (a state: peak, slip_NNN_before/after) is mostly its fields. Its frame
// dimension is fixed, so the per-frame numbers (iteration, origins, Dx, Fx, Fz, energy) and the
// label are stored whole, without chunks: each chunked variable carries an HDF5 B-tree index of
// about 2.5 KiB (h5stat), and netCDF's default chunks along an unlimited dimension alone are
// 512-1024 values (4-8 KiB), written whole at the first frame. Here a 3 x 4 block, with
// Debian 12's netCDF 4.9 and HDF5 1.10: 97 KB with an unlimited frame and default chunks, 70 KB
// with chunks of 64 frames, 50 KB now (what is left is mostly the fields' B-trees, 10 x 2.5 KiB,
// and headers). A path file, which grows, keeps the unlimited frame with chunks of 64 frames,
// and grows past a chunk with every per-frame number read back.
TEST_F(SnapshotIo, OneFrameFilesCarryNoEmptyChunks) {
  const fs::path nc = dir_ / "one.nc";
  write_snapshots(nc, {frame(0, "peak", -1, 0, 0)}, {});
  EXPECT_LT(fs::file_size(nc), 60000u);
  const std::vector<const char*> per_frame{"label", "iteration", "origin_x", "origin_y",
                                           "Dx",    "Fx",        "Fz",       "energy"};
  const auto storage = [&](const fs::path& file) {
    int id = -1, unlimited = -2;
    EXPECT_EQ(nc_open(file.c_str(), NC_NOWRITE, &id), NC_NOERR);
    EXPECT_EQ(nc_inq_unlimdim(id, &unlimited), NC_NOERR);
    std::vector<std::pair<int, std::size_t>> out;
    for (const char* name : per_frame) {
      int var = -1, how = -1;
      std::size_t chunk[2] = {0, 0};
      EXPECT_EQ(nc_inq_varid(id, name, &var), NC_NOERR) << name;
      EXPECT_EQ(nc_inq_var_chunking(id, var, &how, chunk), NC_NOERR) << name;
      out.emplace_back(how, chunk[0]);
    }
    nc_close(id);
    return std::pair{unlimited, out};
  };
  const auto [fixed_unlimited, fixed] = storage(nc);
  EXPECT_EQ(fixed_unlimited, -1);  // no unlimited dimension
  for (std::size_t v = 0; v < per_frame.size(); ++v)
    EXPECT_EQ(fixed[v].first, NC_CONTIGUOUS) << per_frame[v];
  EXPECT_EQ(read_snapshots(nc).front().label, "peak");

  const fs::path paths = dir_ / "paths.nc";
  std::vector<Snapshot> many;
  for (int k = 0; k < 130; ++k)
    many.push_back(frame(k % 7, "slip_001_path", k, k % 3, 0));
  {
    SnapshotAppender out(paths, {}, {});
    for (const Snapshot& f : many)
      out.append(f);
    out.close();
  }
  const auto [growing_unlimited, growing] = storage(paths);
  EXPECT_GE(growing_unlimited, 0);
  for (std::size_t v = 1; v < per_frame.size(); ++v) {  // the label: netCDF's own chunks
    EXPECT_EQ(growing[v].first, NC_CHUNKED) << per_frame[v];
    EXPECT_EQ(growing[v].second, 64u) << per_frame[v];
  }
  const std::vector<Snapshot> back = read_snapshots(paths);
  ASSERT_EQ(back.size(), many.size());
  for (std::size_t k = 0; k < many.size(); k += 43) {
    EXPECT_EQ(back[k].label, many[k].label);
    EXPECT_EQ(back[k].iteration, many[k].iteration);
    EXPECT_EQ(back[k].block.origin0, many[k].block.origin0);
    EXPECT_EQ(bits({back[k].Dx, back[k].Fx, back[k].Fz, back[k].energy}),
              bits({many[k].Dx, many[k].Fx, many[k].Fz, many[k].energy}));
  }

  // A file of a fixed number of frames takes no more.
  SnapshotAppender two(dir_ / "two.nc", {}, {}, 32, 2);
  two.append(frame(0, "a", -1, 0, 0));
  two.append(frame(1, "b", -1, 0, 0));
  EXPECT_NE(
      invalid_argument_message([&] { two.append(frame(2, "c", -1, 0, 0)); }).find("holds 2 frames"),
      std::string::npos);
  // Nor when it is opened again to append.
  SnapshotAppender again = SnapshotAppender::open(nc);
  EXPECT_NE(invalid_argument_message([&] {
              again.append(frame(1, "peak", -1, 0, 0));
            }).find("holds 1 frames"),
            std::string::npos);
}

// The tools' sink (snapshot_sink.hpp): states as their own files, paths in one growing
// paths.nc.partial (renamed at the end), replayed paths read back and moved on, and a resumed
// run that keeps the path frames up to its checkpoint, also from the source a killed resumption
// left, and starts over with a warning from a partial file it cannot read.
TEST_F(SnapshotIo, SinkWritesResumesAndReplays) {
  const fs::path dir = dir_ / "snapshots";
  const auto at = [](Snapshot f, double Dx) {
    f.Dx = Dx;
    return f;
  };
  const auto labels = [](const fs::path& nc) {
    std::vector<std::pair<std::string, double>> out;
    for (const Snapshot& f : read_snapshots(nc))
      out.emplace_back(f.label, f.Dx);
    return out;
  };
  {
    SnapshotSink sink(dir, {{"a", 3.0}}, {});
    EXPECT_EQ(sink.start(std::nullopt), "");
    sink.state(at(frame(0, "slip_001_before", -1, 0, 0), 1.0));
    sink.state(at(frame(1, "slip_001_after", -1, 0, 0), 1.0));
    for (int k = 0; k < 3; ++k)
      sink.path_frame(at(frame(k, "slip_001_path", 5 * (k + 1), 0, 0), 1.0));
    sink.state(at(frame(0, "slip_002_before", -1, 1, 0), 2.0));
    sink.replayed_path("slip_001_path", 1, 1.0, "slip_002_path");
    sink.replayed_path("slip_777_path", 1, 1.0, "slip_003_path");  // none kept: ignored
    sink.flush();
    EXPECT_TRUE(fs::exists(sink.partial_file()));
    EXPECT_FALSE(fs::exists(sink.paths_file()));
  }  // interrupted: the partial file stays for the resumption
  const fs::path partial = dir / "paths.nc.partial";
  const std::vector<std::pair<std::string, double>> six = {
      {"slip_001_path", 1.0}, {"slip_001_path", 1.0}, {"slip_001_path", 1.0},
      {"slip_002_path", 2.0}, {"slip_002_path", 2.0}, {"slip_002_path", 2.0}};
  EXPECT_EQ(labels(partial), six);
  const auto replayed = read_snapshots(partial, "slip_002_path");
  ASSERT_EQ(replayed.size(), 3u);
  EXPECT_EQ(replayed[2].block.origin0, 1);
  EXPECT_EQ(bits(replayed[2].ux), bits(frame(2, "x", 0, 0, 0).ux));
  EXPECT_EQ(read_snapshots(dir / "slip_001_before.nc").size(), 1u);
  {
    // Resumed from a checkpoint at Dx = 1.5: the replayed path (Dx = 2) is made again.
    SnapshotSink sink(dir, {{"a", 3.0}}, {});
    EXPECT_EQ(sink.start(1.5), "");
    sink.replayed_path("slip_001_path", 1, 1.0, "slip_002_path");
    sink.path_frame(at(frame(1, "slip_011_path", 5, 0, 0), 3.0));
    sink.finish();
    EXPECT_FALSE(fs::exists(partial));
  }
  std::vector<std::pair<std::string, double>> seven = six;
  seven.emplace_back("slip_011_path", 3.0);
  EXPECT_EQ(labels(dir / "paths.nc"), seven);
  for (const char* left : {"paths.nc.resumed", "paths.nc.copy", "paths.nc.partial"})
    EXPECT_FALSE(fs::exists(dir / left)) << left;
  {
    // A resumption killed during its copy left its source: the next one starts from it (a
    // failed run's paths.nc is the source otherwise; here it is stale and must not be used).
    fs::copy_file(dir / "paths.nc", dir / "paths.nc.resumed");
    write_snapshots(dir / "paths.nc", {at(frame(0, "slip_999_path", 5, 0, 0), 0.5)}, {});
    SnapshotSink sink(dir, {}, {});
    EXPECT_EQ(sink.start(2.5), "");
    sink.finish();
    EXPECT_EQ(labels(dir / "paths.nc"), six);
  }
  {
    // An unreadable partial file (a SIGKILL during a write): its paths are lost, said so.
    std::ofstream(partial) << "not a NetCDF file";
    SnapshotSink sink(dir, {}, {});
    const std::string warning = sink.start(2.5);
    EXPECT_NE(warning.find("lost"), std::string::npos) << warning;
    sink.path_frame(at(frame(1, "slip_011_path", 5, 0, 0), 3.0));
    sink.finish();
    EXPECT_EQ(labels(dir / "paths.nc"),
              (std::vector<std::pair<std::string, double>>{{"slip_011_path", 3.0}}));
  }
  {
    // A fresh run removes the paths of an earlier one; a frame with uz cannot join a file of
    // frames without.
    SnapshotSink sink(dir, {}, {});
    EXPECT_EQ(sink.start(std::nullopt), "");
    EXPECT_FALSE(fs::exists(dir / "paths.nc"));
    sink.path_frame(frame(1, "slip_001_path", 5, 0, 0));
    Snapshot with_uz = frame(2, "slip_001_path", 10, 0, 0);
    with_uz.uz = with_uz.ux;
    EXPECT_THROW(sink.path_frame(with_uz), std::invalid_argument);
  }
}

TEST_F(SnapshotIo, LargestSlipSinkKeepsTheLargestAndTheLatestSlipsPairs) {
  const fs::path dir = dir_ / "largest_slip";
  // The slide's cost when it accepted a slip (on its "after" state; made up here: 100 GF and
  // 0.5 s per unit of Dx).
  const auto cost = [](Snapshot& f) {
    if (f.label.ends_with("_after")) {
      f.gf_applications = static_cast<std::size_t>(100 * f.Dx);
      f.wall_s = 0.5 * f.Dx;
    }
  };
  const auto slip = [&](int k, std::string label, double Dx, int sites) {
    Snapshot f = frame(k, std::move(label), -1, 0, 0);
    f.Dx = Dx;
    f.slipped_sites = sites;
    cost(f);
    return f;
  };
  const auto label_of = [](const fs::path& nc) { return read_snapshots(nc).at(0).label; };
  // A state with one dislocation loop (tracking's synthetic field: a slipped disk of radius 5 d
  // on a 24 x 24 block in contact everywhere), so that its census has something to count. Its
  // cores are 1 d wide and tau_max is G (b_core = d), so that the window of the stress they hold
  // (4 b_core either side) fits within half the loop's width and holds most of each core's slip.
  const auto loop_state = [&](std::string label, double Dx, int sites) {
    tracking::SyntheticOptions o;
    o.block = LatticeBlock{.shape = {24, 24}, .origin0 = -12, .origin1 = -12};
    o.core_width = 1.0;
    o.tau_peak = 1.0;
    const tracking::SyntheticField field = tracking::synthetic_field(o, {{0.0, 0.0, 5.0, 5.0}});
    Snapshot f;
    f.label = std::move(label);
    f.Dx = Dx;
    f.Fx = 0.25;
    f.Fz = 1.0;
    f.block = field.block;
    const std::vector<double> zeros(field.sx.size(), 0.0);
    f.ux = f.uy = f.sy = f.tau_y = f.pressure = zeros;
    f.sx = field.sx;
    f.tau_x = field.tau_x;
    f.tau_max = field.tau_max;
    f.in_contact = field.in_contact;
    f.slipped_sites = sites;
    cost(f);
    return f;
  };
  {
    LargestSlipSink sink(dir, {{"a", 3.0}}, {});
    EXPECT_EQ(sink.start(std::nullopt), "");
    EXPECT_FALSE(sink.wants_paths());
    sink.state(slip(0, "slip_001_before", 1.0, 5));
    sink.state(slip(1, "slip_001_after", 1.0, 5));
    sink.state(slip(2, "slip_002_before", 2.0, 40));
    sink.state(loop_state("slip_002_after", 2.0, 40));
    // Slip 3 is slip 2 replayed a period on (the slide says so on its frames): as large as
    // slip 2, not larger, so the first of equals stays.
    Snapshot replay_before = slip(1, "slip_003_before", 3.0, 40);
    Snapshot replay_after = slip(2, "slip_003_after", 3.0, 40);
    replay_before.replay_of = replay_after.replay_of = 2;
    sink.state(replay_before);
    sink.state(replay_after);
    sink.state(slip(0, "slip_004_before", 4.0, 7));
    sink.state(slip(1, "slip_004_after", 4.0, 7));
    EXPECT_EQ(sink.largest_slipped_sites(), 40);
    EXPECT_EQ(label_of(sink.before_file()), "slip_002_before");
    EXPECT_EQ(label_of(sink.after_file()), "slip_002_after");
    // The frame's fields are the ones handed over, bit for bit.
    EXPECT_EQ(bits(read_snapshots(sink.before_file()).at(0).ux), bits(frame(2, "x", 0, 0, 0).ux));
    // The latest slip's pair, whatever its size.
    EXPECT_EQ(label_of(sink.latest_before_file()), "slip_004_before");
    EXPECT_EQ(label_of(sink.latest_after_file()), "slip_004_after");
    EXPECT_FALSE(fs::exists(dir / "peak.nc"));
    sink.state(slip(2, "peak", 2.0, 0));
    EXPECT_EQ(label_of(dir / "peak.nc"), "peak");
    // The two pairs, the peak, slips.csv and its two figures.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 8);
    EXPECT_TRUE(fs::exists(sink.friction_figure()));
    EXPECT_TRUE(fs::exists(sink.loops_figure()));
    // A row per slip in slips.csv: the slip's place (Fx before from its "before" state) and the
    // census of its "after" state, the same as tracking's on that frame.
    const CsvTable rows = CsvTable::read(sink.census_file());
    EXPECT_EQ(rows.columns(), LargestSlipSink::census_columns());
    ASSERT_EQ(rows.rows(), 4u);
    const std::vector<Snapshot> afters = {frame(1, "", -1, 0, 0), loop_state("", 2.0, 40),
                                          frame(2, "", -1, 0, 0), frame(1, "", -1, 0, 0)};
    const int befores[4] = {0, 2, 1, 0};  // frame() of each "before"
    const int sites[4] = {5, 40, 40, 7};
    for (std::size_t i = 0; i < 4; ++i) {
      const tracking::LineCensus c =
          tracking::census(tracking::find_lines(tracking::view_of(afters[i])));
      EXPECT_EQ(rows.integer(i, "slip"), static_cast<long long>(i + 1));
      EXPECT_EQ(rows.number(i, "Dx"), static_cast<double>(i + 1));
      EXPECT_EQ(rows.number(i, "Fx_before"), frame(befores[i], "x", -1, 0, 0).Fx);
      EXPECT_EQ(rows.number(i, "Fx_after"), afters[i].Fx);
      EXPECT_EQ(rows.integer(i, "slipped_sites"), sites[i]);
      EXPECT_EQ(rows.integer(i, "contact_sites"), static_cast<long long>(c.contact_sites));
      EXPECT_EQ(rows.integer(i, "lines"), c.lines);
      EXPECT_EQ(rows.integer(i, "loops"), c.loops);
      EXPECT_EQ(rows.number(i, "loop_area"), c.loop_area);
      const double cx = rows.number(i, "largest_loop_cx");  // NaN without a loop
      EXPECT_TRUE(cx == c.largest_loop_cx || (std::isnan(cx) && std::isnan(c.largest_loop_cx)))
          << cx;
      EXPECT_EQ(rows.number(i, "slipped_area"), c.slipped_area);
      EXPECT_EQ(rows.integer(i, "gf_applications"), static_cast<long long>(100 * (i + 1)));
      EXPECT_EQ(rows.number(i, "wall_s"), 0.5 * static_cast<double>(i + 1));
      EXPECT_EQ(rows.number(i, "Dx_before"), static_cast<double>(i + 1));  // the "before" frame's
      EXPECT_EQ(rows.integer(i, "replay_of"), i == 2 ? 2 : 0);
      // What the loops hold where they cross the profiles through the tip centre: tracking's.
      const auto held =
          tracking::loop_core_stress(afters[i], tracking::find_lines(tracking::view_of(afters[i])));
      const auto same = [](double a, double b) {
        return a == b || (std::isnan(a) && std::isnan(b));
      };
      EXPECT_TRUE(same(rows.number(i, "loop_stress_x"), held[0].stress)) << i;
      EXPECT_TRUE(same(rows.number(i, "loop_tau_max_x"), held[0].tau_max)) << i;
      EXPECT_TRUE(same(rows.number(i, "loop_stress_y"), held[1].stress)) << i;
      EXPECT_TRUE(same(rows.number(i, "loop_tau_max_y"), held[1].tau_max)) << i;
      // The loop's row: both ends and both sides resolved; the others have no loop.
      EXPECT_EQ(held[0].crossings, i == 1 ? 2 : 0) << i;
      EXPECT_EQ(held[1].crossings, i == 1 ? 2 : 0) << i;
      EXPECT_EQ(std::isfinite(rows.number(i, "loop_stress_x")), i == 1) << i;
    }
    // The cost columns, the step's start, the replay's source and the loops' held stress come
    // last, after the census.
    const std::vector<std::string>& columns = rows.columns();
    EXPECT_EQ(std::vector<std::string>(columns.end() - 8, columns.end()),
              (std::vector<std::string>{"gf_applications", "wall_s", "Dx_before", "replay_of",
                                        "loop_stress_x", "loop_tau_max_x", "loop_stress_y",
                                        "loop_tau_max_y"}));
    // The loop's row: one loop of about pi 5^2 d^2 (5 %, as tracking's analytic tests allow).
    EXPECT_EQ(rows.integer(1, "loops"), 1);
    EXPECT_NEAR(rows.number(1, "loop_area"), 25.0 * std::numbers::pi, 1.25 * std::numbers::pi);
    EXPECT_EQ(rows.integer(1, "contact_sites"), 24 * 24);
  }
  {
    // Resumed from a checkpoint taken after slip 2 (slips 3 and 4 were made after it and are
    // made again): their rows go, the states on disk stay until a slip replaces them.
    LargestSlipSink sink(dir, {}, {});
    EXPECT_EQ(sink.start(LargestSlipSink::Resume{{{1.0, 5}, {2.0, 40}}}), "");
    EXPECT_EQ(CsvTable::read(sink.census_file()).rows(), 2u);
    sink.state(slip(1, "slip_003_before", 3.0, 40));
    sink.state(slip(2, "slip_003_after", 3.0, 40));
    const CsvTable rows = CsvTable::read(sink.census_file());
    ASSERT_EQ(rows.rows(), 3u);
    EXPECT_EQ(rows.integer(2, "slip"), 3);
    EXPECT_EQ(rows.number(2, "Dx"), 3.0);
    sink.state(slip(0, "slip_004_before", 4.0, 7));
    sink.state(slip(1, "slip_004_after", 4.0, 7));
    EXPECT_EQ(CsvTable::read(sink.census_file()).rows(), 4u);
    EXPECT_EQ(CsvTable::read(sink.census_file()).integer(1, "loops"), 1);  // kept as it was
  }
  {
    // Resumed from a checkpoint whose slips reached 40 sites: a slip of 40 does not replace
    // the pair on disk, one of 41 does.
    LargestSlipSink sink(dir, {}, {});
    EXPECT_EQ(sink.start(LargestSlipSink::Resume{{{1.0, 5}, {2.0, 40}, {3.0, 40}, {4.0, 7}}}), "");
    EXPECT_FALSE(fs::exists(dir / "peak.nc"));
    sink.state(slip(0, "slip_005_before", 5.0, 40));
    sink.state(slip(1, "slip_005_after", 5.0, 40));
    EXPECT_EQ(label_of(sink.before_file()), "slip_002_before");
    EXPECT_EQ(label_of(sink.latest_after_file()), "slip_005_after");
    sink.state(slip(0, "slip_006_before", 6.0, 41));
    sink.state(slip(1, "slip_006_after", 6.0, 41));
    EXPECT_EQ(label_of(sink.before_file()), "slip_006_before");
    const CsvTable rows = CsvTable::read(sink.census_file());
    ASSERT_EQ(rows.rows(), 6u);
    for (std::size_t i = 0; i < rows.rows(); ++i)
      EXPECT_EQ(rows.integer(i, "slip"), static_cast<long long>(i + 1));
  }
  {
    // A table that is not this slide's (slip 2 at another Dx: say the point was started again
    // without --largest-slip, which leaves the sink's files alone) is set aside, not continued;
    // one that cannot be read likewise, beside the first.
    LargestSlipSink sink(dir, {}, {});
    std::string warning = sink.start(LargestSlipSink::Resume{{{1.0, 5}, {2.5, 40}}});
    EXPECT_NE(warning.find("is not of this slide (its row of slip 2"), std::string::npos)
        << warning;
    EXPECT_NE(warning.find("no rows for 2 of the 2 slips"), std::string::npos) << warning;
    EXPECT_EQ(CsvTable::read(dir / "slips.old.csv").rows(), 6u);
    EXPECT_EQ(CsvTable::read(sink.census_file()).rows(), 0u);
    write_file_atomic(sink.census_file(), "slip,Dx\n1,2,3\n");
    warning = sink.start(LargestSlipSink::Resume{{{1.0, 5}}});
    EXPECT_NE(warning.find("cannot be read"), std::string::npos) << warning;
    EXPECT_NE(warning.find("set aside as slips.old.1.csv"), std::string::npos) << warning;
    EXPECT_EQ(CsvTable::read(sink.census_file()).rows(), 0u);
    fs::remove(dir / "slips.old.csv");
    fs::remove(dir / "slips.old.1.csv");
  }
  {
    // A table of an earlier build, whose columns are the first of today's (before the cost
    // columns, Dx_before, replay_of and the loops' held stress): its rows are kept with the new
    // columns empty, but for Dx_before and replay_of, which the checkpoint's trace gives (0 for
    // a computed slip; -1 for a replayed one, whose source the trace does not give), and the
    // next slip's row is full. A table with a column today's do not have in its place is set
    // aside.
    std::vector<std::string> columns = LargestSlipSink::census_columns();
    columns.resize(columns.size() - 8);
    ASSERT_EQ(columns.back(), "slipped_area");
    CsvTable earlier(columns);
    for (int k = 1; k <= 2; ++k) {
      std::vector<CsvTable::Cell> row = {static_cast<long long>(k),
                                         static_cast<double>(k),
                                         0.5,
                                         0.25,
                                         1.0,
                                         static_cast<long long>(k == 1 ? 5 : 40)};
      row.resize(columns.size(), CsvTable::Cell(std::string()));
      earlier.add_row(std::move(row));
    }
    earlier.write(dir / "slips.csv");
    LargestSlipSink sink(dir, {}, {});
    EXPECT_EQ(sink.start(LargestSlipSink::Resume{{{1.0, 5, 0.75}, {2.0, 40, 1.5, true}}}), "");
    sink.state(slip(1, "slip_003_before", 3.0, 40));
    sink.state(slip(2, "slip_003_after", 3.0, 40));
    const CsvTable rows = CsvTable::read(sink.census_file());
    EXPECT_EQ(rows.columns(), LargestSlipSink::census_columns());
    ASSERT_EQ(rows.rows(), 3u);
    EXPECT_EQ(rows.integer(1, "slipped_sites"), 40);
    EXPECT_EQ(rows.text(1, "gf_applications"), "");
    EXPECT_EQ(rows.text(1, "wall_s"), "");
    EXPECT_EQ(rows.number(0, "Dx_before"), 0.75);
    EXPECT_EQ(rows.number(1, "Dx_before"), 1.5);
    EXPECT_EQ(rows.integer(0, "replay_of"), 0);
    EXPECT_EQ(rows.integer(1, "replay_of"), -1);
    EXPECT_EQ(rows.integer(2, "replay_of"), 0);
    EXPECT_EQ(rows.text(1, "loop_stress_x"), "");
    EXPECT_EQ(rows.text(1, "loop_tau_max_y"), "");
    EXPECT_EQ(rows.integer(2, "gf_applications"), 300);
    EXPECT_EQ(rows.number(2, "wall_s"), 1.5);
    columns.emplace_back("not_ours");
    CsvTable other(columns);
    other.write(dir / "slips.csv");
    const std::string warning = sink.start(LargestSlipSink::Resume{{{1.0, 5}}});
    EXPECT_NE(warning.find("has other columns"), std::string::npos) << warning;
    EXPECT_EQ(CsvTable::read(dir / "slips.old.csv").columns(), columns);
    fs::remove(dir / "slips.old.csv");
  }
  {
    // A checkpoint of a run that did not keep its largest slip, nor the rows of its slips: said
    // so; a fresh run clears.
    fs::remove(dir / "largest_slip_before.nc");
    fs::remove(dir / "slips.csv");
    LargestSlipSink sink(dir, {}, {});
    const std::string warning =
        sink.start(LargestSlipSink::Resume{{{1.0, 12}, {2.0, 3}, {3.0, 1}}});
    EXPECT_NE(warning.find("not kept"), std::string::npos) << warning;
    EXPECT_NE(warning.find("no rows for 3 of the 3 slips"), std::string::npos) << warning;
    EXPECT_EQ(sink.start(std::nullopt), "");
    EXPECT_FALSE(fs::exists(dir / "largest_slip_after.nc"));
    EXPECT_FALSE(fs::exists(dir / "latest_slip_after.nc"));
    EXPECT_FALSE(fs::exists(sink.census_file()));
    EXPECT_FALSE(fs::exists(sink.friction_figure()));
    EXPECT_FALSE(fs::exists(sink.loops_figure()));
  }
  {
    // A figure that cannot be written (here a directory holds its name) never stops the slide:
    // the table grows, and the other figure, which would be out of date, is not left behind.
    LargestSlipSink sink(dir, {{"a", 3.0}, {"alpha", 0.5}}, {});
    EXPECT_EQ(sink.start(std::nullopt), "");
    fs::create_directories(sink.friction_figure() / "in_the_way");
    sink.state(slip(0, "slip_001_before", 1.0, 5));
    EXPECT_NO_THROW(sink.state(loop_state("slip_001_after", 1.0, 5)));
    sink.state(slip(0, "slip_002_before", 2.0, 5));
    EXPECT_NO_THROW(sink.state(loop_state("slip_002_after", 2.0, 5)));
    EXPECT_EQ(CsvTable::read(sink.census_file()).rows(), 2u);
    EXPECT_FALSE(fs::exists(sink.loops_figure()));
    fs::remove_all(sink.friction_figure());
  }
}

}  // namespace
}  // namespace asperity::app
