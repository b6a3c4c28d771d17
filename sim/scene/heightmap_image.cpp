#include "scene/heightmap_image.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
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

// What a Netpbm header says. stb returns PGM samples as stored, without scaling them by maxval
// (a 10-bit map would look nearly flat), reads 16-bit colour PPM one byte short per sample, and
// fills a truncated file's missing samples with whatever memory held: we read the header ourselves
// and refuse what stb gets wrong. By hand: stb does not report these fields, and libnetpbm exits
// the process on a malformed file.
struct NetpbmHeader {
  bool is_netpbm = false;  // starts with 'P' and a digit
  bool is_binary_gray = false;  // P5
  bool header_complete = false;
  unsigned width = 0, height = 0, maxval = 0;
  std::streamoff data_offset = 0;
};

NetpbmHeader read_netpbm_header(std::ifstream& in) {
  NetpbmHeader h;
  char magic[2] = {};
  in.read(magic, 2);
  if (!in || magic[0] != 'P' || !std::isdigit(static_cast<unsigned char>(magic[1]))) return h;
  h.is_netpbm = true;
  h.is_binary_gray = magic[1] == '5';
  unsigned* fields[3] = {&h.width, &h.height, &h.maxval};
  for (unsigned* field : fields) {
    while (in && (std::isspace(in.peek()) || in.peek() == '#')) {
      if (in.get() != '#') continue;
      while (in && in.peek() != '\n' && in.peek() != '\r') in.get();  // a comment runs to the end of its line
    }
    if (!std::isdigit(in.peek()) || !(in >> *field)) return h;
  }
  h.data_offset = static_cast<std::streamoff>(in.tellg()) + 1;  // one whitespace byte ends the header
  h.header_complete = true;
  return h;
}

// Empty when the file is one stb reads correctly, else why not.
std::string netpbm_problem(const std::string& path, unsigned& maxval) {
  std::ifstream in(path, std::ios::binary);
  const NetpbmHeader h = read_netpbm_header(in);
  maxval = 0;
  if (!h.is_netpbm) return "";
  if (!h.is_binary_gray) return "only binary greyscale Netpbm images (PGM, P5) are read as heightmaps";
  if (!h.header_complete) return "malformed PGM header (expected 'P5 width height maxval')";
  if (h.maxval == 0 || h.maxval > 65535) return "PGM maxval must be 1..65535";
  const std::uintmax_t sample_bytes = h.maxval > 255 ? 2 : 1;
  const std::uintmax_t needed = static_cast<std::uintmax_t>(h.data_offset) + sample_bytes * h.width * h.height;
  in.seekg(0, std::ios::end);
  if (static_cast<std::uintmax_t>(in.tellg()) < needed) return "PGM file is shorter than its header says";
  maxval = h.maxval;
  return "";
}

}  // namespace

HeightmapImage load_heightmap_image(const std::string& path) {
  HeightmapImage out;
  int channels = 0;
  unsigned maxval = 0;
  out.error = netpbm_problem(path, maxval);
  if (!out.error.empty()) return out;
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
