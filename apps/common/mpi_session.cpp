// MpiSession: see mpi_session.hpp.
#include "asperity/apps/common/mpi_session.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#ifdef ASPERITY_HAVE_MPI
#include <mpi.h>

#include "asperity/core/fft/fftw_mpi_engine.hpp"
#include "asperity/core/fft/mpi_comm.hpp"
#endif

namespace asperity::app {

// Open MPI's mpirun (OMPI_COMM_WORLD_SIZE), MPICH's and Intel's Hydra and Slurm's PMI-2
// (PMI_SIZE), PMIx launchers (PMIX_SIZE, or at least PMIX_RANK: srun --mpi=pmix, prterun).
int launcher_ranks() {
  for (const char* key : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    if (const char* v = std::getenv(key); v != nullptr && *v != '\0') {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  }
  return std::getenv("PMIX_RANK") != nullptr ? 1 : 0;
}

int launcher_local_ranks() {
  for (const char* key : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}) {
    if (const char* v = std::getenv(key); v != nullptr && std::atoi(v) > 0) return std::atoi(v);
  }
  return 1;
}

struct MpiSession::Impl {
  bool initialised = false;
#ifdef ASPERITY_HAVE_MPI
  std::unique_ptr<par::MpiComm> comm;
#endif
};

MpiSession::MpiSession(int& argc, char**& argv) : impl_(std::make_unique<Impl>()) {
  const int ranks = launcher_ranks();
#ifdef ASPERITY_HAVE_MPI
  if (ranks > 0) {
    // FFTW threads run inside each rank, called from the main thread only: FUNNELED.
    int provided = 0;
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
      throw std::runtime_error("MPI_Init_thread failed");
    impl_->initialised = true;
    impl_->comm = std::make_unique<par::MpiComm>(MPI_COMM_WORLD);
  }
#else
  (void)argc, (void)argv;
  if (ranks > 1) {
    throw std::invalid_argument(
        "started by mpirun on " + std::to_string(ranks) +
        " ranks, but this build has no MPI (configure with MPI and FFTW-MPI installed, "
        "ASPERITY_MPI=ON); run it without mpirun");
  }
#endif
}

MpiSession::~MpiSession() {
#ifdef ASPERITY_HAVE_MPI
  impl_->comm.reset();
  if (impl_->initialised) MPI_Finalize();
#endif
}

const par::Comm& MpiSession::comm() const {
#ifdef ASPERITY_HAVE_MPI
  if (impl_->comm) return *impl_->comm;
#endif
  return par::serial();
}

fft::EngineFactory MpiSession::engine() const {
#ifdef ASPERITY_HAVE_MPI
  if (impl_->comm && impl_->comm->distributed()) return fft::mpi_engine_factory(MPI_COMM_WORLD);
#endif
  return {};
}

int MpiSession::finish(int code) const {
#ifdef ASPERITY_HAVE_MPI
  if (code != 0 && impl_->comm && impl_->comm->distributed()) {
    std::fflush(nullptr);
    MPI_Abort(MPI_COMM_WORLD, code);
  }
#endif
  return code;
}

}  // namespace asperity::app
