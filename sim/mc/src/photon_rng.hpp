#pragma once

#include <cstdint>

#include <Random123/philox.h>

namespace tocd::sim::mc {

/// The random stream of one photon: Philox4x32-10 keyed by the run seed, counter
/// (photon index, block). Any photon's stream can be regenerated on its own, so results do
/// not depend on which thread ran which photon. Four 32-bit draws per block.
class PhotonRng {
 public:
  PhotonRng(std::uint64_t seed, std::uint64_t photon) noexcept {
    key_ = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    ctr_ = {{static_cast<std::uint32_t>(photon), static_cast<std::uint32_t>(photon >> 32), 0u, 0u}};
  }

  /// One raw 32-bit draw.
  [[gnu::always_inline]] std::uint32_t bits() noexcept {
    if (used_ == 4) {
      block_ = r123::Philox4x32()(ctr_, key_);
      ++ctr_.v[2];
      used_ = 0;
    }
    return block_.v[used_++];
  }

  /// Uniform in the open interval (0, 1): (k + 0.5) / 2^32, never 0 so log() is safe.
  [[gnu::always_inline]] double uniform() noexcept {
    return (static_cast<double>(bits()) + 0.5) * (1.0 / 4294967296.0);
  }

 private:
  r123::Philox4x32::ctr_type ctr_{};
  r123::Philox4x32::key_type key_{};
  r123::Philox4x32::ctr_type block_{};
  int used_ = 4;
};

}  // namespace tocd::sim::mc
