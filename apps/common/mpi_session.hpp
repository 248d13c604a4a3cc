// A tool's processes (issue 26): one, or the ranks of an mpirun. MPI is initialised only when
// the tool was started by an MPI launcher (its environment says so) and the toolkit was built
// with MPI (ASPERITY_HAVE_MPI); a tool started on its own stays one process and never touches
// MPI. Built without MPI and started by mpirun on several ranks, the session refuses (each rank
// would run the whole job and write the same files).
#pragma once

#include <memory>

#include "asperity/core/common/comm.hpp"
#include "asperity/core/fft/fft_engine.hpp"

namespace asperity::app {

class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();  // MPI_Finalize, where MPI was initialised
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  // The processes of the run (MPI_COMM_WORLD, or the serial Comm).
  [[nodiscard]] const par::Comm& comm() const;
  [[nodiscard]] int rank() const { return comm().rank(); }
  [[nodiscard]] int size() const { return comm().size(); }
  [[nodiscard]] bool root() const { return comm().root(); }
  [[nodiscard]] bool distributed() const { return comm().distributed(); }
  // The FFT backend spreading a grid over comm() (fft::mpi_engine_factory); empty for one
  // process (the serial FFTW engine).
  [[nodiscard]] fft::EngineFactory engine() const;

  // The end of a tool's main with exit code `code`: a rank that failed while the others may be
  // waiting for it in a collective ends the whole run (MPI_Abort), so that no rank hangs.
  int finish(int code) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Whether an MPI launcher started this process as one of several ranks (by its environment:
// OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX... of OpenMPI, MPICH and PMIx launchers).
int launcher_ranks();
// The ranks the launcher started on this machine (OMPI_COMM_WORLD_LOCAL_SIZE, MPI_LOCALNRANKS);
// 1 without a launcher or when it does not say.
int launcher_local_ranks();

}  // namespace asperity::app
