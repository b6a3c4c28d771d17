// The pieces every project-file reader uses: paths beside a file, materials, mesh files, names,
// encodings and the files that elements name.
#include <fmt/format.h>
#include <iconv.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/loader_parts.hpp"
#include "scene/xml_syntax.hpp"
#include "scene/mesh_loader.hpp"
#include "scene/value_ranges.hpp"

namespace sear {

std::string path_beside(const std::string& file, const std::string& relative) {
  const std::filesystem::path rel(relative);
  if (rel.is_absolute()) return rel.string();
  return (std::filesystem::path(file).parent_path() / rel).lexically_normal().string();
}

Material read_material_element(ElementReader& r) {
  Material m;
  m.name = r.required_text("name").value_or("");
  check_label(r, "name", m.name);
  m.friction = r.number("friction", m.friction, ranges::kFriction);
  m.bounce = r.number("bounce", m.bounce, ranges::kBounce);
  r.finish();
  return m;
}

bool check_readable_file(ElementReader& r, const std::string& what, const std::string& relative,
                         const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    r.error(fmt::format("<{}> {} '{}' not found (looked for {})", r.name(), what, relative, path));
    return false;
  }
  if (std::filesystem::is_directory(status)) {
    r.error(fmt::format("<{}> {} '{}' is a folder, expected a file ({})", r.name(), what, relative, path));
    return false;
  }
  if (!std::filesystem::is_regular_file(status)) {
    r.error(fmt::format("<{}> {} '{}' is not a regular file ({})", r.name(), what, relative, path));
    return false;
  }
  if (::access(path.c_str(), R_OK) != 0) {
    r.error(fmt::format("<{}> {} '{}' cannot be read ({})", r.name(), what, relative, path));
    return false;
  }
  return true;
}

TriangleMesh read_mesh_file(ElementReader& r, Eigen::Vector3f* bounds_min, Eigen::Vector3f* bounds_max) {
  const auto rel = r.required_text("file");
  const UpAxis up = r.choice("up_axis", {"z", "y"}, 0) == 0 ? UpAxis::Z : UpAxis::Y;
  const double scale = r.number("scale", 1.0, ranges::kMeshScale);
  if (!rel) return {};
  const std::string path = path_beside(r.file(), *rel);
  if (!check_readable_file(r, "mesh file", *rel, path)) return {};
  MeshLoadResult loaded = load_mesh(path, up, scale);
  if (!loaded.error.empty()) {
    r.error(fmt::format("<{}> mesh file '{}': {}", r.name(), *rel, loaded.error));
    return {};
  }
  // A mesh's numbers are as unchecked as an attribute's: a vertex at 1e39 is infinite as a float,
  // and ODE aborts on it. Every vertex must lie, once scaled, within the world's reach.
  const double reach = ranges::kWorldXY.max;
  const auto bad = std::find_if(loaded.mesh.vertices.begin(), loaded.mesh.vertices.end(),
                                [&](const Eigen::Vector3f& v) {
                                  return !v.allFinite() || v.cast<double>().cwiseAbs().maxCoeff() > reach;
                                });
  if (bad != loaded.mesh.vertices.end()) {
    r.error(fmt::format("<{}> mesh file '{}': vertex {} is at ({}, {}, {}) m after scale {}; every vertex must be "
                        "finite and within -100000..100000 m",
                        r.name(), *rel, bad - loaded.mesh.vertices.begin() + 1, (*bad).x(), (*bad).y(), (*bad).z(),
                        scale));
    return {};
  }
  if (bounds_min && bounds_max) mesh_bounds(loaded.mesh, *bounds_min, *bounds_max);
  return std::move(loaded.mesh);
}

void check_name(ElementReader& r, const std::string& name) {
  const bool safe = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  // Shown as written only when it is plain ASCII: the message itself must stay valid UTF-8.
  if (!safe)
    r.error(fmt::format("<{}> name '{}': use letters, digits, '_' and '-' only", r.name(),
                        first_invalid_utf8(name) == std::string::npos ? name : std::string("(not UTF-8)")));
  else if (name.size() > ranges::kMaxNameLength)
    r.error(fmt::format("<{}> name '{}...' is {} characters long; names become file names: at most {}", r.name(),
                        name.substr(0, 16), name.size(), ranges::kMaxNameLength));
}

void check_label(ElementReader& r, const char* attribute, const std::string& text) {
  constexpr std::size_t kMaxLabel = 200;
  if (first_invalid_utf8(text) != std::string::npos) {
    r.error(fmt::format("<{}> attribute '{}' is not valid UTF-8", r.name(), attribute));
    return;
  }
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    // C0 controls and DEL; C1 controls (U+0080..U+009F) are 0xC2 0x80..0x9F in UTF-8.
    const bool c1 = c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) <= 0x9F;
    if (c < 0x20 || c == 0x7F || c1) {
      r.error(fmt::format("<{}> attribute '{}' holds a control character (byte {} is 0x{:02X}); use printable text",
                          r.name(), attribute, i + 1, c1 ? static_cast<unsigned>(static_cast<unsigned char>(text[i + 1])) : c));
      return;
    }
  }
  if (text.size() > kMaxLabel)
    r.error(fmt::format("<{}> attribute '{}' is {} bytes long; at most {}", r.name(), attribute, text.size(), kMaxLabel));
}

bool parse_xml(const std::string& xml, const std::string& path, Diagnostics& diagnostics, tinyxml2::XMLDocument& doc) {
  if (!check_utf8(xml, path, diagnostics)) return false;
  if (doc.Parse(xml.data(), xml.size()) == tinyxml2::XML_SUCCESS) return true;
  // tinyxml2's own text is its enum's name and the line where it gave up; expat says what is wrong
  // and where it was written.
  if (const auto syntax = xml_syntax_error(xml))
    diagnostics.error(path, syntax->line, "malformed XML: " + syntax->message);
  else
    diagnostics.error(path, doc.ErrorLineNum(), "malformed XML: " + tinyxml2_error_words(doc.ErrorID()));
  return false;
}

bool read_text_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream all;
  all << in.rdbuf();
  text = all.str();
  return !in.bad();
}

std::optional<std::string> read_named_file(const std::string& path, const char* what, Diagnostics& diagnostics) {
  std::string text;
  if (read_text_file(path, text)) return text;
  diagnostics.error(path, 0, std::filesystem::exists(path) ? fmt::format("cannot read {}", what)
                                                           : fmt::format("{} not found", what));
  return std::nullopt;
}

std::size_t first_invalid_utf8(const std::string& text) {
  // glibc's iconv decodes UTF-8 strictly (no overlong forms, surrogates or values past
  // U+10FFFF) and stops at the first bad byte: converting to UTF-32 finds it without a
  // hand-written decoder. Pure ASCII, the usual case, needs no conversion at all.
  if (std::all_of(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; }))
    return std::string::npos;
  iconv_t cd = iconv_open("UTF-32LE", "UTF-8");
  if (cd == reinterpret_cast<iconv_t>(-1)) return std::string::npos;  // no converter: nothing to judge by
  char* in = const_cast<char*>(text.data());
  std::size_t in_left = text.size();
  std::size_t bad = std::string::npos;
  char buffer[4096];
  while (in_left > 0) {
    char* out = buffer;
    std::size_t out_left = sizeof buffer;
    if (iconv(cd, &in, &in_left, &out, &out_left) != static_cast<std::size_t>(-1)) continue;
    if (errno == E2BIG) continue;  // the buffer is full: go on with an empty one
    bad = static_cast<std::size_t>(in - text.data());  // EILSEQ, or EINVAL for a sequence cut short at the end
    break;
  }
  iconv_close(cd);
  return bad;
}

bool check_utf8(const std::string& text, const std::string& file, Diagnostics& diagnostics) {
  const std::size_t bad = first_invalid_utf8(text);
  if (bad == std::string::npos) return true;
  const auto at = text.begin() + static_cast<std::ptrdiff_t>(bad);
  const int line = 1 + static_cast<int>(std::count(text.begin(), at, '\n'));
  const std::size_t newline = bad == 0 ? std::string::npos : text.rfind('\n', bad - 1);
  const std::size_t column = newline == std::string::npos ? bad + 1 : bad - newline;
  diagnostics.error(file, line,
                    fmt::format("the file is not valid UTF-8 (byte 0x{:02X} at column {}); SEAR reads project and robot "
                                "files as UTF-8, so save it as UTF-8 (a Latin-1 file can be converted with "
                                "'iconv -f LATIN1 -t UTF-8')",
                                static_cast<unsigned>(static_cast<unsigned char>(text[bad])), column));
  return false;
}

void check_at_most_one(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                       std::initializer_list<const char*> kinds) {
  for (const char* kind : kinds) {
    const tinyxml2::XMLElement* first = element.FirstChildElement(kind);
    if (!first) continue;
    for (auto* again = first->NextSiblingElement(kind); again; again = again->NextSiblingElement(kind))
      diagnostics.error(file, again->GetLineNum(),
                        fmt::format("<{}> may appear only once in <{}> (first at line {})", kind, element.Name(),
                                    first->GetLineNum()));
  }
}

}  // namespace sear
