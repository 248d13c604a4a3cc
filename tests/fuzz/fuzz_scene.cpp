// libFuzzer target: scene files. Any input must either give a scene that passes validation or
// throw std::invalid_argument (a clear message for the user); anything else (a crash, another
// exception, a sanitizer report, a hang) is a bug. The TOML parsing and typed-key checks of
// SceneReader, which every tool's scene goes through, and the slide scene's keys
// (contact_slide); the other tools' key tables live in their apps and are not fuzzed here.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "asperity/apps/common/slide_io.hpp"
#include "asperity/apps/common/toml_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    auto reader = asperity::app::SceneReader::from_string(text, "fuzz.toml");
    const asperity::app::SlideScene scene = asperity::app::read_slide_scene(reader);
    reader.reject_unknown();
    // What the tools do next with a scene that was read.
    scene.contact.validate();
    scene.options.validate();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
