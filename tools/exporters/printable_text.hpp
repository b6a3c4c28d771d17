// Bytes a firmware sent, as text that is always valid UTF-8: for logs, the viewer and the summary,
// where a firmware's "21\xb0C" or binary on a console would otherwise make the output unwritable.
#pragma once

#include <string>
#include <string_view>

namespace sear {

// Printable ASCII (and tab) as is, any other byte as \xNN.
inline void append_printable(std::string& out, unsigned char c) {
  if ((c >= 0x20 && c < 0x7F) || c == '\t') {
    out += static_cast<char>(c);
    return;
  }
  static const char digits[] = "0123456789ABCDEF";
  out += "\\x";
  out += digits[c >> 4];
  out += digits[c & 15];
}

// The same for a stretch of text, where line ends may be kept as they are (JSON escapes them).
inline std::string printable(std::string_view bytes, bool keep_line_ends) {
  std::string out;
  for (const char c : bytes) {
    if (keep_line_ends && (c == '\n' || c == '\r')) out += c;
    else append_printable(out, static_cast<unsigned char>(c));
  }
  return out;
}

}  // namespace sear
