#include "asperity/core/common/shape.hpp"

#include <cmath>

namespace asperity {

LatticeBlock LatticeBlock::centred_disk(double radius_over_d) {
  if (!(radius_over_d >= 0.0) || !std::isfinite(radius_over_d)) {
    throw std::invalid_argument("LatticeBlock::centred_disk: radius must be finite and >= 0, got " +
                                std::to_string(radius_over_d));
  }
  const int half = static_cast<int>(std::floor(radius_over_d));
  return LatticeBlock{Shape2{2 * half + 1, 2 * half + 1}, -half, -half};
}

bool fft_smooth(int n) {
  for (int p : {2, 3, 5, 7}) {
    while (n % p == 0)
      n /= p;
  }
  return n == 1;
}

int next_fft_size(int minimum) {
  if (minimum <= 1) return 1;
  for (int n = minimum + minimum % 2;; n += 2) {
    if (fft_smooth(n)) return n;
  }
}

}  // namespace asperity
