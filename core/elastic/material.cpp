#include "asperity/core/elastic/material.hpp"

#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

namespace asperity::elastic {

const settings::Table<Material>& Material::settings() {
  using R = settings::Range;
  static const settings::Table<Material> table = {
      settings::number<Material>(
          "G", [](auto& m) -> auto& { return m.G; }, R::positive(), "",
          "shear modulus of the substrate: the unit of stress"),
      settings::number<Material>(
          "nu", [](auto& m) -> auto& { return m.nu; }, R::closed(0.0, 0.5), "",
          "Poisson ratio of the substrate (negative ratios are not modelled)", "--nu")};
  return table;
}

void Material::validate() const {
  settings::validate(*this, settings());
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
