// Reads a grayscale heightmap image (PNG 8 or 16 bit, PGM, and whatever else stb_image reads).
#pragma once

#include <string>
#include <vector>

namespace sear {

struct HeightmapImage {
  int columns = 0;
  int rows = 0;
  std::vector<double> levels;  // 0 (black) .. 1 (white), row 0 first (the image's top, north)
  std::string error;           // empty on success
};

HeightmapImage load_heightmap_image(const std::string& path);

}  // namespace sear
