// Checkpoint files of contact_slide: a slide::SlideState (everything needed to continue a slide
// bit for bit) with the settings it belongs to, in one binary file.
//
// Format: CBOR (RFC 8949) of {format, version, byte_order, settings, state}; the large per-site
// fields are byte strings of native doubles (byte_order says which), the rest plain CBOR values
// (doubles exactly, NaN and infinities included). Written atomically like every output file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "asperity/apps/common/slide_io.hpp"
#include "asperity/core/slide/slider.hpp"

namespace asperity::app {

// Everything that changes the numbers of a slide: the scene (a, R, alpha, G, nu, d), every slide,
// solver and FFT option (FFT threads change the round-off) and the build. A checkpoint resumes
// only under the same fingerprint. Space-separated key=value items.
std::string slide_fingerprint(const SlideScene& scene);
// The same for a slide of the explicit model: its scene and the alpha of the potential it uses.
std::string explicit_slide_fingerprint(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha);

struct SlideCheckpoint {
  std::string settings;  // (explicit_)slide_fingerprint() of the scene it was written for
  slide::SlideState state;
};

std::vector<std::uint8_t> encode_checkpoint(const SlideCheckpoint& checkpoint);
// Throws std::invalid_argument starting with `source` if `bytes` is not a checkpoint of this
// format version (damaged, truncated, other file, other byte order).
SlideCheckpoint decode_checkpoint(std::span<const std::uint8_t> bytes, const std::string& source);

// Atomic write (temporary file, then rename); throws std::runtime_error naming the file.
void write_checkpoint(const std::filesystem::path& file, const SlideCheckpoint& checkpoint);
// Throws std::invalid_argument naming the file if it is missing, unreadable or not a checkpoint.
SlideCheckpoint read_checkpoint(const std::filesystem::path& file);

// Throws std::invalid_argument naming `file` and the differing settings if the checkpoint was
// written for other settings than `scene`'s.
void check_checkpoint_settings(const SlideCheckpoint& checkpoint, const SlideScene& scene,
                               const std::filesystem::path& file);
// The same against a fingerprint (explicit_slide_fingerprint).
void check_checkpoint_settings(const SlideCheckpoint& checkpoint, const std::string& fingerprint,
                               const std::filesystem::path& file);

}  // namespace asperity::app
