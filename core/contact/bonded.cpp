// Matrix-free conjugate gradients on the masked Green's function; see bonded.hpp.
#include "asperity/core/contact/bonded.hpp"

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <cmath>
#include <stdexcept>
#include <string>

namespace asperity::contact {
class MaskedGF;
}

namespace Eigen::internal {
template <>
struct traits<asperity::contact::MaskedGF> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace asperity::contact {

// The operator f_mask -> (G f)_mask, in the form Eigen's iterative solvers accept.
class MaskedGF : public Eigen::EigenBase<MaskedGF> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum {
    ColsAtCompileTime = Eigen::Dynamic,
    MaxColsAtCompileTime = Eigen::Dynamic,
    IsRowMajor = false
  };

  MaskedGF(elastic::FreeSurfaceGF& gf, std::vector<std::size_t> index)
      : gf_(gf), index_(std::move(index)), f_(gf.size(), 0.0), u_(gf.size(), 0.0) {}

  [[nodiscard]] Eigen::Index rows() const { return static_cast<Eigen::Index>(index_.size()); }
  [[nodiscard]] Eigen::Index cols() const { return rows(); }

  template <typename Rhs>
  Eigen::Product<MaskedGF, Rhs, Eigen::AliasFreeProduct> operator*(
      const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<MaskedGF, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

  template <typename In, typename Out>
  void apply_add(const In& x, Out& y, double alpha) const {
    for (std::size_t k = 0; k < index_.size(); ++k)
      f_[index_[k]] = x(static_cast<Eigen::Index>(k));
    gf_.apply(f_, u_);
    for (std::size_t k = 0; k < index_.size(); ++k) {
      y(static_cast<Eigen::Index>(k)) += alpha * u_[index_[k]];
    }
  }

 private:
  elastic::FreeSurfaceGF& gf_;
  std::vector<std::size_t> index_;
  mutable std::vector<double> f_, u_;
};

}  // namespace asperity::contact

namespace Eigen::internal {
template <typename Rhs>
struct generic_product_impl<asperity::contact::MaskedGF, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<asperity::contact::MaskedGF, Rhs,
                                generic_product_impl<asperity::contact::MaskedGF, Rhs>> {
  using Scalar = typename Product<asperity::contact::MaskedGF, Rhs>::Scalar;
  template <typename Dest>
  static void scaleAndAddTo(Dest& dst, const asperity::contact::MaskedGF& lhs, const Rhs& rhs,
                            const Scalar& alpha) {
    lhs.apply_add(rhs, dst, alpha);
  }
};
}  // namespace Eigen::internal

namespace asperity::contact {

const settings::Table<BondedOptions>& BondedOptions::settings() {
  using R = settings::Range;
  // A relative residual: 1 or more is met by f = 0.
  static const settings::Table<BondedOptions> table = {
      settings::number<BondedOptions>(
          "tolerance", [](auto& o) -> auto& { return o.tolerance; }, R::open(0.0, 1.0), "",
          "conjugate-gradient stop: relative residual |G f - u| / |u| on the bonded sites"),
      settings::integer<BondedOptions>(
          "max_iterations", [](auto& o) -> auto& { return o.max_iterations; }, R::closed(1, 1e9),
          "", "conjugate-gradient iteration cap (one GF application each)")};
  return table;
}

void BondedOptions::validate() const {
  settings::validate(*this, settings());
}

BondedResult solve_bonded(elastic::FreeSurfaceGF& gf, std::span<const std::uint8_t> mask,
                          std::span<const double> prescribed, const BondedOptions& options) {
  options.validate();
  const std::size_t sites = gf.region().count();
  if (mask.size() != sites || prescribed.size() != gf.size()) {
    throw std::invalid_argument("solve_bonded: mask has " + std::to_string(mask.size()) +
                                " entries and the prescribed field " +
                                std::to_string(prescribed.size()) + "; expected " +
                                std::to_string(sites) + " and " + std::to_string(gf.size()));
  }
  std::vector<std::size_t> index;
  for (std::size_t c = 0; c < static_cast<std::size_t>(gf.ncomp()); ++c) {
    for (std::size_t i = 0; i < sites; ++i) {
      if (mask[i] != 0) index.push_back(c * sites + i);
    }
  }
  if (index.empty()) throw std::invalid_argument("solve_bonded: the mask holds no site");

  const std::size_t applications_before = gf.applications();
  MaskedGF op(gf, index);
  Eigen::VectorXd b(static_cast<Eigen::Index>(index.size()));
  for (std::size_t k = 0; k < index.size(); ++k)
    b(static_cast<Eigen::Index>(k)) = prescribed[index[k]];
  // Jacobi preconditioning would need the diagonal, which is one constant per component here:
  // it only rescales, so the identity is as good.
  Eigen::ConjugateGradient<MaskedGF, Eigen::Lower | Eigen::Upper, Eigen::IdentityPreconditioner> cg;
  cg.setTolerance(options.tolerance);
  cg.setMaxIterations(options.max_iterations);
  cg.compute(op);
  const Eigen::VectorXd x = cg.solve(b);

  BondedResult res;
  res.iterations = static_cast<int>(cg.iterations());
  res.residual = cg.error();
  res.termination = cg.info() == Eigen::Success ? Termination::converged
                    : x.allFinite()             ? Termination::max_iterations
                                                : Termination::diverged;
  res.force.assign(gf.size(), 0.0);
  for (std::size_t k = 0; k < index.size(); ++k)
    res.force[index[k]] = x(static_cast<Eigen::Index>(k));
  res.displacement.assign(gf.size(), 0.0);
  gf.apply(res.force, res.displacement);
  res.energy = elastic::elastic_energy(res.force, res.displacement);
  res.gf_applications = gf.applications() - applications_before;
  return res;
}

}  // namespace asperity::contact
