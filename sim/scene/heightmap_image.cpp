#include "scene/heightmap_image.hpp"

#include <stb/stb_image.h>

#include <memory>

namespace sear {

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
  for (std::size_t i = 0; i < count; ++i) out.levels[i] = pixels.get()[i] / 65535.0;
  return out;
}

}  // namespace sear
