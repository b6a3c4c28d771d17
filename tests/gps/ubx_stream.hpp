// A NEO-6M's output split into what it is made of: NMEA sentences and UBX frames, each checked
// with its own checksum computed here apart from the model (NMEA XOR, UBX 8-bit Fletcher over
// class ... payload, u-blox 6 spec "UBX Checksum"), and the little-endian fields of a payload.
#pragma once

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "devices/serial_byte.h"

namespace sear::test {

struct UbxFrame {
  std::uint8_t cls = 0, id = 0;
  std::vector<std::uint8_t> payload;
  std::int64_t end_ns = 0;  // of its last byte
  std::uint32_t baud = 0;
};

struct Item {
  bool ubx = false;
  UbxFrame frame;     // if ubx
  std::string text;   // an NMEA sentence, '$' to LF
  std::int64_t end_ns = 0;
};

inline std::vector<std::uint8_t> ubx_bytes(std::uint8_t cls, std::uint8_t id, const std::vector<std::uint8_t>& p) {
  std::vector<std::uint8_t> f = {0xB5, 0x62, cls, id, static_cast<std::uint8_t>(p.size() & 0xFF),
                                 static_cast<std::uint8_t>(p.size() >> 8)};
  for (std::uint8_t v : p) f.push_back(v);
  std::uint8_t a = 0, b = 0;
  for (std::size_t i = 2; i < f.size(); ++i) {
    a = static_cast<std::uint8_t>(a + f[i]);
    b = static_cast<std::uint8_t>(b + a);
  }
  f.push_back(a);
  f.push_back(b);
  return f;
}

// Splits the stream; anything that is neither a whole sentence with a good checksum nor a whole
// UBX frame with a good checksum goes to `bad`. A trailing part cut by the end of the capture is
// left: *consumed tells where it starts.
inline std::vector<Item> split_stream(const std::vector<serial_byte>& bytes, std::vector<std::string>& bad,
                                      std::size_t* consumed = nullptr) {
  std::vector<Item> out;
  std::size_t i = 0;
  auto v = [&](std::size_t k) { return bytes[k].value; };
  while (i < bytes.size()) {
    if (v(i) == '$') {
      std::size_t e = i;
      while (e < bytes.size() && v(e) != '\n') ++e;
      if (e == bytes.size()) break;
      std::string s;
      for (std::size_t k = i; k <= e; ++k) s.push_back(static_cast<char>(v(k)));
      const std::size_t star = s.find('*');
      std::uint8_t x = 0;
      for (std::size_t k = 1; k < star && star != std::string::npos; ++k) x = static_cast<std::uint8_t>(x ^ s[k]);
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02X", x);
      if (star == std::string::npos || s.substr(star + 1, 2) != hex || s.size() > 82) bad.push_back(s);
      Item it;
      it.text = s;
      it.end_ns = bytes[e].end_ns;
      out.push_back(it);
      i = e + 1;
    } else if (v(i) == 0xB5 && (i + 1 == bytes.size() || v(i + 1) == 0x62)) {
      if (i + 6 > bytes.size()) break;
      const std::size_t len = v(i + 4) | static_cast<std::size_t>(v(i + 5)) << 8;
      if (i + len + 8 > bytes.size()) break;
      Item it;
      it.ubx = true;
      it.frame.cls = v(i + 2);
      it.frame.id = v(i + 3);
      for (std::size_t k = 0; k < len; ++k) it.frame.payload.push_back(v(i + 6 + k));
      it.frame.end_ns = it.end_ns = bytes[i + len + 7].end_ns;
      it.frame.baud = bytes[i].baud;
      const auto again = ubx_bytes(it.frame.cls, it.frame.id, it.frame.payload);
      if (again[len + 6] != v(i + len + 6) || again[len + 7] != v(i + len + 7)) bad.push_back("UBX checksum");
      out.push_back(it);
      i += len + 8;
    } else {
      bad.push_back("stray byte " + std::to_string(v(i)));
      ++i;
    }
  }
  if (consumed) *consumed = i;
  return out;
}

inline std::uint32_t le_u(const std::vector<std::uint8_t>& p, std::size_t at, int bytes) {
  std::uint32_t v = 0;
  for (int k = bytes - 1; k >= 0; --k) v = v << 8 | p.at(at + static_cast<std::size_t>(k));
  return v;
}
inline std::uint32_t u4(const std::vector<std::uint8_t>& p, std::size_t at) { return le_u(p, at, 4); }
inline std::uint16_t u2(const std::vector<std::uint8_t>& p, std::size_t at) {
  return static_cast<std::uint16_t>(le_u(p, at, 2));
}
inline std::int32_t i4(const std::vector<std::uint8_t>& p, std::size_t at) {
  return static_cast<std::int32_t>(le_u(p, at, 4));
}
inline std::int16_t i2(const std::vector<std::uint8_t>& p, std::size_t at) {
  return static_cast<std::int16_t>(le_u(p, at, 2));
}

// Comma-separated fields of a sentence's body ('$' and '*hh' left out).
inline std::vector<std::string> fields_of(const std::string& sentence) {
  const std::string body = sentence.substr(1, sentence.find('*') - 1);
  std::vector<std::string> f;
  std::stringstream ss(body);
  std::string item;
  while (std::getline(ss, item, ',')) f.push_back(item);
  if (!body.empty() && body.back() == ',') f.push_back("");
  return f;
}

}  // namespace sear::test
