// libFuzzer target: NetCDF snapshot files (read_snapshots). The NetCDF library reads from a path,
// so each input is written to a file of this process first. Any input must either read back or
// throw std::invalid_argument naming the file; anything else is a bug.
//
// HDF5 1.10 (under netCDF-4) crashes or hangs on some damaged files (found at once by this
// target; known/hdf5_crash_in_nc_open.nc is one). That is outside asperity and cannot be fixed
// here, so each input is first read with the netCDF library alone in a child process, and inputs
// on which the library crashes or hangs there are skipped. Then read_snapshots runs on the input
// in this process, under the sanitizers. The child costs most of an execution: about 2 inputs a
// second (2026-12-01, beside a long run), against thousands for the other two targets.
#include <netcdf.h>
#include <sanitizer/common_interface_defs.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "asperity/apps/common/snapshot_io.hpp"

namespace {

const std::filesystem::path& input_file() {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("asperity_fuzz_snapshot_" + std::to_string(::getpid()) + ".nc");
  return path;
}

// Everything read_snapshots asks of the library, through the library alone: open, every
// variable's metadata and attributes (netCDF-4 loads them lazily), and the data of every
// variable that is not huge.
void walk_with_the_library(const std::filesystem::path& path) {
  int id = -1, nvars = 0;
  if (nc_open(path.c_str(), NC_NOWRITE, &id) != NC_NOERR) return;
  if (nc_inq_nvars(id, &nvars) == NC_NOERR) {
    for (int v = 0; v < nvars; ++v) {
      char name[NC_MAX_NAME + 1];
      nc_type type = NC_NAT;
      int ndims = 0, natts = 0, dims[NC_MAX_VAR_DIMS];
      if (nc_inq_var(id, v, name, &type, &ndims, dims, &natts) != NC_NOERR) continue;
      for (int a = 0; a < natts; ++a) {
        char att[NC_MAX_NAME + 1];
        std::size_t len = 0;
        if (nc_inq_attname(id, v, a, att) == NC_NOERR) nc_inq_att(id, v, att, &type, &len);
      }
      std::size_t count = 1;
      for (int k = 0; k < ndims && k < NC_MAX_VAR_DIMS; ++k) {
        std::size_t len = 0;
        nc_inq_dimlen(id, dims[k], &len);
        count = len == 0 || count > (std::size_t{1} << 24) / len ? 0 : count * len;
      }
      if (count == 0) continue;
      std::string buffer(count * 8, '\0');
      if (type == NC_CHAR) {
        nc_get_var_text(id, v, buffer.data());
      } else {
        nc_get_var_double(id, v, reinterpret_cast<double*>(buffer.data()));
      }
    }
  }
  nc_close(id);
}

// Whether the netCDF/HDF5 libraries survive reading the file (in a child process: a crash there
// is theirs). The fuzzer runs single-threaded, so fork() is safe.
bool library_survives_open(const std::filesystem::path& path) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The child's crash is the library's: no report, no crash file of the fuzzer, and a hang
    // (also seen) ends after 2 s.
    std::freopen("/dev/null", "w", stderr);
    __sanitizer_set_death_callback(nullptr);
    ::signal(SIGALRM, SIG_DFL);
    ::alarm(2);
    walk_with_the_library(path);
    std::_Exit(0);
  }
  int status = 0;
  if (pid < 0) std::abort();
  // The fuzzer's own timer (SIGALRM for -timeout) interrupts the wait.
  while (::waitpid(pid, &status, 0) != pid) {
    if (errno != EINTR) std::abort();
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(input_file(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  if (!library_survives_open(input_file())) return 0;
  try {
    const auto frames = asperity::app::read_snapshots(input_file());
    // Frames that were read are consistent: every field has one value per block site.
    for (const auto& f : frames) {
      const std::size_t n = f.block.shape.count();
      if (f.ux.size() != n || f.uy.size() != n || f.tau_max.size() != n ||
          f.in_contact.size() != n) {
        __builtin_trap();
      }
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
