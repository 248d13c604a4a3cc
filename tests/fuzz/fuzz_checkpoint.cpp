// libFuzzer target: contact_slide checkpoint files (decode_checkpoint). Any input must either
// decode or throw std::invalid_argument; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "asperity/apps/common/slide_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto c = asperity::app::decode_checkpoint({data, size}, "fuzz.cbor");
    (void)c;
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
