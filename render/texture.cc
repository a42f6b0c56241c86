#include "render/texture.h"

#include <algorithm>
#include <cmath>

#include "common/random.h"

namespace slt {
namespace {

// Periodic value noise on a lattice of cells cell_x x cell_y texels (dividing kSize), values
// in [-1, 1] from a hash of the lattice point, smoothstep-interpolated.
void AddValueNoise(int cell_x, int cell_y, float amplitude, std::uint64_t key, std::vector<float>* tile) {
  constexpr int n = TextureBank::kSize;
  const int period_x = n / cell_x, period_y = n / cell_y;
  const auto lattice = [&](int i, int j) {
    const std::uint64_t h = MixSeed(key ^ MixSeed(static_cast<std::uint64_t>((i % period_x) * 131071 + (j % period_y))));
    return static_cast<float>(static_cast<double>(h >> 11) * 0x1.0p-52 - 1.0);
  };
  const auto smooth = [](float x) { return x * x * (3.0f - 2.0f * x); };
  for (int y = 0; y < n; ++y) {
    const int j = y / cell_y;
    const float fy = smooth(static_cast<float>(y % cell_y) / static_cast<float>(cell_y));
    for (int x = 0; x < n; ++x) {
      const int i = x / cell_x;
      const float fx = smooth(static_cast<float>(x % cell_x) / static_cast<float>(cell_x));
      const float top = lattice(i, j) + fx * (lattice(i + 1, j) - lattice(i, j));
      const float bottom = lattice(i, j + 1) + fx * (lattice(i + 1, j + 1) - lattice(i, j + 1));
      (*tile)[y * n + x] += amplitude * (top + fy * (bottom - top));
    }
  }
}

void NormalizeToUnit(std::vector<float>* tile) {
  float peak = 0.0f;
  for (float v : *tile) peak = std::max(peak, std::abs(v));
  if (peak > 0.0f) {
    for (float& v : *tile) v /= peak;
  }
}

}  // namespace

TextureBank::TextureBank() {
  for (std::vector<float>& tile : tiles_) tile.assign(kSize * kSize, 0.0f);
  // Mottled: three octaves, features of 4, 2 and 1 scale units.
  std::vector<float>& mottled = tiles_[static_cast<int>(TexturePattern::kMottled)];
  AddValueNoise(32, 32, 0.5f, HashName("mottled-1"), &mottled);
  AddValueNoise(16, 16, 0.3f, HashName("mottled-2"), &mottled);
  AddValueNoise(8, 8, 0.2f, HashName("mottled-3"), &mottled);
  NormalizeToUnit(&mottled);
  // Grain: streaks along s, 8 times longer than wide.
  std::vector<float>& grain = tiles_[static_cast<int>(TexturePattern::kGrain)];
  AddValueNoise(64, 8, 0.6f, HashName("grain-1"), &grain);
  AddValueNoise(32, 4, 0.4f, HashName("grain-2"), &grain);
  NormalizeToUnit(&grain);
}

float TextureBank::Sample(TexturePattern pattern, double s, double t) const {
  if (pattern == TexturePattern::kFlat) return 0.0f;
  const std::vector<float>& tile = tiles_[static_cast<int>(pattern)];
  const double x = s * kTexelsPerScale, y = t * kTexelsPerScale;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  // Two's complement wrap: the tile is periodic with period kSize.
  const int i = static_cast<int>(static_cast<long long>(x0) & (kSize - 1));
  const int j = static_cast<int>(static_cast<long long>(y0) & (kSize - 1));
  const int i1 = (i + 1) & (kSize - 1), j1 = (j + 1) & (kSize - 1);
  const float top = tile[j * kSize + i] + fx * (tile[j * kSize + i1] - tile[j * kSize + i]);
  const float bottom = tile[j1 * kSize + i] + fx * (tile[j1 * kSize + i1] - tile[j1 * kSize + i]);
  return top + fy * (bottom - top);
}

}  // namespace slt
