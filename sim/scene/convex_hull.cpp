#include "scene/convex_hull.hpp"

#include <libqhull_r/qhull_ra.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>

namespace sear {

ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points) {
  ConvexHull out;
  if (points.size() < 4) {
    out.error = "fewer than 4 points";
    return out;
  }
  std::vector<coordT> coords;
  coords.reserve(3 * points.size());
  for (const auto& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});

  // qhull writes its reasons to a FILE: kept in memory for our own message.
  char* err_text = nullptr;
  std::size_t err_size = 0;
  FILE* err = open_memstream(&err_text, &err_size);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  QHULL_LIB_CHECK
  qh_zero(qh, err);
  // Default options: 3-d hulls merge coplanar facets (C-0), so a box's face is one polygon
  // whatever its triangles; no random perturbation, so the same points give the same hull.
  char options[] = "qhull";
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False, options, nullptr, err);
  if (code == 0) {
    // Corners in the order of the points they are: the same input gives the same numbering.
    std::map<int, std::uint32_t> index;
    vertexT* vertex;
    FORALLvertices index[qh_pointid(qh, vertex->point)] = 0;
    for (auto& [id, k] : index) {
      k = static_cast<std::uint32_t>(out.vertices.size());
      out.vertices.push_back(points[static_cast<std::size_t>(id)]);
    }
    facetT* facet;
    FORALLfacets {
      ConvexHull::Face face;
      face.normal = Eigen::Vector3d(facet->normal[0], facet->normal[1], facet->normal[2]);
      face.offset = -facet->offset;  // qhull's plane: normal . x + offset = 0
      // qh_facet3vertex orders a 3-d facet's vertices around it (a merged facet's too); the
      // winding is checked against the outward normal below rather than taken on trust.
      setT* corners = qh_facet3vertex(qh, facet);
      vertexT** vertexp;
      FOREACHvertex_(corners) face.corners.push_back(index[qh_pointid(qh, vertex->point)]);
      qh_settempfree(qh, &corners);
      Eigen::Vector3d area(0, 0, 0);
      for (std::size_t k = 0; k < face.corners.size(); ++k)
        area += out.vertices[face.corners[k]].cross(out.vertices[face.corners[(k + 1) % face.corners.size()]]);
      if (area.dot(face.normal) < 0) std::reverse(face.corners.begin(), face.corners.end());
      out.faces.push_back(std::move(face));
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  if (code != 0) {
    std::string text = err_text ? err_text : "";
    // Its first line says why ("QH6154 Qhull precision error: initial simplex is flat ...").
    text = text.substr(0, text.find('\n'));
    out.error = text.empty() ? "qhull failed" : text;
    out.vertices.clear();
    out.faces.clear();
  }
  std::free(err_text);
  return out;
}

TriangleMesh hull_triangles(const ConvexHull& hull) {
  TriangleMesh mesh;
  for (const auto& v : hull.vertices) mesh.vertices.push_back(v.cast<float>());
  for (const auto& f : hull.faces)
    for (std::size_t k = 1; k + 1 < f.corners.size(); ++k)
      mesh.indices.insert(mesh.indices.end(), {f.corners[0], f.corners[k], f.corners[k + 1]});
  return mesh;
}

double hull_volume(const ConvexHull& hull) {
  double six_v = 0;
  for (const auto& f : hull.faces)
    for (std::size_t k = 1; k + 1 < f.corners.size(); ++k)
      six_v += hull.vertices[f.corners[0]].dot(hull.vertices[f.corners[k]].cross(hull.vertices[f.corners[k + 1]]));
  return six_v / 6;
}

}  // namespace sear
