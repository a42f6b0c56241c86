// The procedural patterns of simulator/surface.h, baked once into small periodic tiles and
// sampled per pixel (bilinear): cheaper than evaluating noise octaves per pixel, and the same
// on every machine (the tiles are computed from fixed hashes, no <random> distributions).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "simulator/surface.h"

namespace slt {

class TextureBank {
 public:
  static constexpr int kSize = 256;            // texels per tile side (a power of two)
  static constexpr double kTexelsPerScale = 8;  // texels per SurfaceTexture::scale_m

  TextureBank();

  // pattern(s / scale, t / scale) of docs/rendering.md, in [-1, 1]: (s, t) in units of the
  // texture's scale, shifted by the surface's seed.
  float Sample(TexturePattern pattern, double s, double t) const;

 private:
  std::array<std::vector<float>, 3> tiles_;  // indexed by TexturePattern
};

}  // namespace slt
