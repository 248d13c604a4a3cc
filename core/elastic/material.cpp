#include "elastic/material.hpp"

#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

namespace asperity::elastic {

void Material::validate() const {
  if (!std::isfinite(G) || !(G > 0.0)) {
    throw std::invalid_argument("Material.G: got " + std::to_string(G) +
                                ", allowed: finite and > 0");
  }
  if (!std::isfinite(nu) || nu < 0.0 || nu > 0.5) {
    throw std::invalid_argument("Material.nu: got " + std::to_string(nu) +
                                ", allowed: 0 <= nu <= 0.5");
  }
}

int component_count(Components c) {
  switch (c) {
    case Components::in_plane:
      return 2;
    case Components::normal:
      return 1;
    case Components::full:
      return 3;
  }
  return 0;
}

int component_axis(Components c, int k) {
  assert(k >= 0 && k < component_count(c));
  return c == Components::normal ? 2 : k;
}

}  // namespace asperity::elastic
