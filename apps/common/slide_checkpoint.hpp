// Checkpoint files of contact_slide: a slide::SlideState (everything needed to continue a slide
// bit for bit) with the settings it belongs to, in one binary file.
//
// Format: CBOR (RFC 8949) of {format, version, byte_order, settings, state}; the large per-site
// fields are byte strings of native doubles (byte_order says which), the rest plain CBOR values
// (doubles exactly, NaN and infinities included). Written atomically like every output file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
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

// A checkpoint continued under other settings than it was written for (--adopt): a long run
// carried over to a new build, or given other numerical settings (a longer distance, another
// step rule). The slide goes on from the same state, so only settings that do not define the
// problem may differ: the build and slide.*, solver.* and fft.* items. The result is then no
// longer the bit-for-bit continuation of the first run, which the record beside it says.
struct CheckpointAdoption {
  std::string saved;    // the checkpoint's fingerprint
  std::string now;      // this run's
  std::string removed;  // the items only the checkpoint has, ", "-separated
  std::string added;    // the items only this run has
};
// How two fingerprints differ: the items only `saved` has, those only `now` has, and of both
// those that may not differ in an adoption (the problem: scene, model, outputs).
struct FingerprintDifference {
  std::vector<std::string> removed, added, fixed;
};
FingerprintDifference fingerprint_difference(const std::string& saved, const std::string& now);
// nullopt when the fingerprints are equal. Otherwise, with `adopt`, what differs if only
// adoptable items do; throws std::invalid_argument naming `file` and the differing items (and,
// with `adopt`, those that may not differ) if not.
std::optional<CheckpointAdoption> check_or_adopt_checkpoint(const SlideCheckpoint& checkpoint,
                                                            const std::string& fingerprint,
                                                            const std::filesystem::path& file,
                                                            bool adopt);
// Keeps the adopted file as <dir>/checkpoint.adopted.<n>.cbor (n = 1, 2, ...: a point may be
// carried over more than once) and appends an entry to the array in <dir>/adopted.json: the
// time, the state's Dx, steps and slip events, the kept file, the differing items and both
// settings. <dir> is the checkpoint's folder. Returns the line the tools print ("adopting the
// checkpoint ..."). Throws std::runtime_error naming the file it could not write.
std::string record_adoption(const std::filesystem::path& checkpoint_file,
                            const SlideCheckpoint& checkpoint, const CheckpointAdoption& adoption);

}  // namespace asperity::app
