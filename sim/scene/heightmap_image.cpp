#include "scene/heightmap_image.hpp"

#include <stb/stb_image.h>

#include <fstream>
#include <memory>

namespace sear {
namespace {

// stb_image 2.27 (Debian 12) returns 16-bit binary PGM samples in the wrong byte order: Netpbm
// stores them most significant byte first (upstream stb pull requests #1710, #1828). We ask
// the installed stb once, on a one-pixel image, so a fixed stb is left alone.
bool stb_swaps_16bit_pgm() {
  static const bool swaps = [] {
    const unsigned char probe[] = {'P', '5', ' ', '1', ' ', '1', ' ', '6', '5', '5', '3', '5', '\n', 0x01, 0x02};
    int w = 0, h = 0, c = 0;
    stbi_us* p = stbi_load_16_from_memory(probe, sizeof probe, &w, &h, &c, 1);
    const bool swapped = p && p[0] == 0x0201;
    stbi_image_free(p);
    return swapped;
  }();
  return swaps;
}

bool is_binary_pgm(const std::string& path) {
  char magic[2] = {};
  std::ifstream(path, std::ios::binary).read(magic, 2);
  return magic[0] == 'P' && magic[1] == '5';
}

}  // namespace

HeightmapImage load_heightmap_image(const std::string& path) {
  HeightmapImage out;
  int channels = 0;
  // 16-bit loading keeps the full depth of 16-bit PNG/PGM terrain and widens 8-bit files exactly.
  std::unique_ptr<stbi_us, void (*)(void*)> pixels(stbi_load_16(path.c_str(), &out.columns, &out.rows, &channels, 1),
                                                   stbi_image_free);
  if (!pixels) {
    out.error = std::string("cannot read heightmap image: ") + stbi_failure_reason();
    return out;
  }
  if (out.columns < 2 || out.rows < 2) {
    out.error = "heightmap image must be at least 2x2 pixels";
    return out;
  }
  const auto count = static_cast<std::size_t>(out.columns) * static_cast<std::size_t>(out.rows);
  out.levels.resize(count);
  const bool swap = is_binary_pgm(path) && stbi_is_16_bit(path.c_str()) && stb_swaps_16bit_pgm();
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned v = pixels.get()[i];
    out.levels[i] = (swap ? ((v & 0xffu) << 8 | v >> 8) : v) / 65535.0;
  }
  return out;
}

}  // namespace sear
