// KINSOL behind solve::newton_krylov; see newton_krylov.hpp.
#include "asperity/core/solve/newton_krylov.hpp"

#include "asperity/core/common/validate.hpp"

#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_spgmr.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace asperity::solve {

namespace {

struct Callbacks {
  const Residual* residual;
  const JacobianTimes* jacobian_times;
  std::size_t n;
};

std::span<double> view(N_Vector v, std::size_t n) {
  return {N_VGetArrayPointer(v), n};
}

int kinsol_residual(N_Vector x, N_Vector f, void* data) {
  auto* cb = static_cast<Callbacks*>(data);
  (*cb->residual)(view(x, cb->n), view(f, cb->n));
  for (double v : view(f, cb->n)) {
    if (!std::isfinite(v)) return 1;  // recoverable: KINSOL shortens the step
  }
  return 0;
}

int kinsol_jtimes(N_Vector v, N_Vector jv, N_Vector x, sunbooleantype* /*new_x*/, void* data) {
  auto* cb = static_cast<Callbacks*>(data);
  (*cb->jacobian_times)(view(x, cb->n), view(v, cb->n), view(jv, cb->n));
  return 0;
}

// RAII for the SUNDIALS objects.
struct Kinsol {
  SUNContext ctx = nullptr;
  N_Vector x = nullptr, scale = nullptr;
  SUNLinearSolver ls = nullptr;
  void* mem = nullptr;
  ~Kinsol() {
    if (mem != nullptr) KINFree(&mem);
    if (ls != nullptr) SUNLinSolFree(ls);
    if (x != nullptr) N_VDestroy(x);
    if (scale != nullptr) N_VDestroy(scale);
    if (ctx != nullptr) SUNContext_Free(&ctx);
  }
};

void check(int flag, const char* what) {
  if (flag < 0)
    throw std::runtime_error(std::string("KINSOL: ") + what + " failed, flag " +
                             std::to_string(flag));
}

}  // namespace

void NewtonKrylovOptions::validate() const {
  require_positive("NewtonKrylovOptions.tolerance", tolerance);
  require_at_least("NewtonKrylovOptions.max_iterations", max_iterations, 1);
  require_at_least("NewtonKrylovOptions.krylov_dimension", krylov_dimension, 1);
}

NewtonKrylovResult newton_krylov(std::span<double> x, const Residual& residual,
                                 const JacobianTimes& jacobian_times,
                                 const NewtonKrylovOptions& options) {
  options.validate();
  const std::size_t n = x.size();
  Callbacks cb{&residual, &jacobian_times, n};
  Kinsol k;
  check(SUNContext_Create(nullptr, &k.ctx), "SUNContext_Create");
  k.x = N_VNew_Serial(static_cast<sunindextype>(n), k.ctx);
  k.scale = N_VNew_Serial(static_cast<sunindextype>(n), k.ctx);
  if (k.x == nullptr || k.scale == nullptr)
    throw std::runtime_error("KINSOL: cannot allocate vectors");
  std::copy(x.begin(), x.end(), N_VGetArrayPointer(k.x));
  N_VConst(1.0, k.scale);
  k.mem = KINCreate(k.ctx);
  if (k.mem == nullptr) throw std::runtime_error("KINSOL: KINCreate failed");
  check(KINInit(k.mem, kinsol_residual, k.x), "KINInit");
  check(KINSetUserData(k.mem, &cb), "KINSetUserData");
  // Failures are returned as a termination and handled by the caller, not printed.
  check(KINSetErrFile(k.mem, nullptr), "KINSetErrFile");
  check(KINSetFuncNormTol(k.mem, options.tolerance), "KINSetFuncNormTol");
  check(KINSetScaledStepTol(k.mem, 1e-15), "KINSetScaledStepTol");
  check(KINSetNumMaxIters(k.mem, options.max_iterations), "KINSetNumMaxIters");
  k.ls = SUNLinSol_SPGMR(k.x, SUN_PREC_NONE, options.krylov_dimension, k.ctx);
  if (k.ls == nullptr) throw std::runtime_error("KINSOL: cannot create GMRES");
  check(KINSetLinearSolver(k.mem, k.ls, nullptr), "KINSetLinearSolver");
  check(KINSetJacTimesVecFn(k.mem, kinsol_jtimes), "KINSetJacTimesVecFn");
  NewtonKrylovResult res;
  res.flag = KINSol(k.mem, k.x, options.line_search ? KIN_LINESEARCH : KIN_NONE, k.scale, k.scale);
  long nni = 0, nli = 0, nfe = 0;
  KINGetNumNonlinSolvIters(k.mem, &nni);
  KINGetNumLinIters(k.mem, &nli);
  KINGetNumFuncEvals(k.mem, &nfe);
  res.iterations = static_cast<int>(nni);
  res.linear_iterations = nli;
  res.function_evaluations = nfe;
  std::copy_n(N_VGetArrayPointer(k.x), n, x.begin());
  std::vector<double> f(n);
  residual(x, f);
  for (double v : f)
    res.residual = std::max(res.residual, std::abs(v));
  if (res.flag == KIN_SUCCESS || res.flag == KIN_INITIAL_GUESS_OK ||
      res.residual <= options.tolerance) {
    res.termination = Termination::converged;
  } else if (res.flag == KIN_MAXITER_REACHED) {
    res.termination = Termination::max_iterations;
  } else {
    res.termination = Termination::diverged;
  }
  return res;
}

}  // namespace asperity::solve
