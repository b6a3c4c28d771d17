// The pieces every project-file reader uses: paths beside a file, materials, mesh files, names.
#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "scene/loader_parts.hpp"
#include "scene/mesh_loader.hpp"

namespace sear {

std::string path_beside(const std::string& file, const std::string& relative) {
  const std::filesystem::path rel(relative);
  if (rel.is_absolute()) return rel.string();
  return (std::filesystem::path(file).parent_path() / rel).lexically_normal().string();
}

Material read_material_element(ElementReader& r) {
  Material m;
  m.name = r.required_text("name").value_or("");
  m.friction = r.number("friction", m.friction, Range::non_negative());
  m.bounce = r.number("bounce", m.bounce, Range::between(0, 1, "0..1"));
  r.finish();
  return m;
}

TriangleMesh read_mesh_file(ElementReader& r, Eigen::Vector3f* bounds_min, Eigen::Vector3f* bounds_max) {
  const auto rel = r.required_text("file");
  const UpAxis up = r.choice("up_axis", {"z", "y"}, 0) == 0 ? UpAxis::Z : UpAxis::Y;
  const double scale = r.number("scale", 1.0, Range::positive());
  if (!rel) return {};
  const std::string path = path_beside(r.file(), *rel);
  if (!std::filesystem::exists(path)) {
    r.error(fmt::format("<{}> mesh file '{}' not found (looked for {})", r.name(), *rel, path));
    return {};
  }
  MeshLoadResult loaded = load_mesh(path, up, scale);
  if (!loaded.error.empty()) {
    r.error(fmt::format("<{}> mesh file '{}': {}", r.name(), *rel, loaded.error));
    return {};
  }
  if (bounds_min && bounds_max) mesh_bounds(loaded.mesh, *bounds_min, *bounds_max);
  return std::move(loaded.mesh);
}

void check_name(ElementReader& r, const std::string& name) {
  const bool safe = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!safe) r.error(fmt::format("<{}> name '{}': use letters, digits, '_' and '-' only", r.name(), name));
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
