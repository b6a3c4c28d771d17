#include "scene/heightmap_image.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cctype>
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

// The maxval of a binary PGM (P5), or 0 for any other file. stb returns PGM samples as stored,
// without scaling them by maxval, so a 10-bit (maxval 1023) map would otherwise look nearly flat.
// Read by hand: stb does not report maxval, and libnetpbm exits the process on a malformed file.
unsigned pgm_maxval(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[2] = {};
  in.read(magic, 2);
  if (!in || magic[0] != 'P' || magic[1] != '5') return 0;
  unsigned fields[3] = {};
  for (unsigned& field : fields) {
    while (in && (std::isspace(in.peek()) || in.peek() == '#')) {
      if (in.get() == '#') in.ignore(1 << 16, '\n');  // a comment runs to the end of its line
    }
    if (!(in >> field)) return 0;
  }
  return fields[2];
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
  const unsigned maxval = pgm_maxval(path);
  const bool wide = maxval > 255;
  const bool swap = wide && stb_swaps_16bit_pgm();
  // stbi_load_16 widens 8-bit samples by 257 (0xff -> 0xffff); 16-bit PGM samples come as stored.
  const double full_scale = maxval == 0 ? 65535.0 : wide ? maxval : 257.0 * maxval;
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned v = pixels.get()[i];
    out.levels[i] = std::min(1.0, (swap ? ((v & 0xffu) << 8 | v >> 8) : v) / full_scale);
  }
  return out;
}

}  // namespace sear
