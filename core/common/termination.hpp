// How an iterative solver stopped. Solvers return this rather than throwing.
#pragma once

#include <string>

namespace asperity {

enum class Termination {
  converged,       // tolerance reached
  max_iterations,  // iteration cap hit before the tolerance
  diverged,        // non-finite values or a growing residual
  unstable,        // converged onto a state that is not a minimum
  interrupted,     // stopped on request of the caller (e.g. a trial step that slipped)
  stalled,         // no further progress: the residual sits at its round-off floor above the
                   // tolerance
};

inline std::string to_string(Termination t) {
  switch (t) {
    case Termination::converged:
      return "converged";
    case Termination::max_iterations:
      return "max_iterations";
    case Termination::diverged:
      return "diverged";
    case Termination::unstable:
      return "unstable";
    case Termination::interrupted:
      return "interrupted";
    case Termination::stalled:
      return "stalled";
  }
  return "unknown";
}

}  // namespace asperity
