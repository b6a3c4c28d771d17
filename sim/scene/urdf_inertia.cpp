#include "scene/urdf_inertia.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "scene/mesh_loader.hpp"

namespace sear {

MassProperties place(const MassProperties& part, const Eigen::Vector3d& position, const Eigen::Matrix3d& rotation) {
  MassProperties out;
  out.mass_kg = part.mass_kg;
  out.com_m = position + rotation * part.com_m;
  out.inertia_kgm2 = rotation * part.inertia_kgm2 * rotation.transpose();
  return out;
}

MassProperties combine(const MassProperties& a, const MassProperties& b) {
  MassProperties out;
  out.mass_kg = a.mass_kg + b.mass_kg;
  if (out.mass_kg <= 0) return out;
  out.com_m = (a.mass_kg * a.com_m + b.mass_kg * b.com_m) / out.mass_kg;
  // Parallel axes: each tensor moved from its own centre to the common one adds m (|d|^2 E - d d^T).
  const auto shifted = [&](const MassProperties& p) {
    const Eigen::Vector3d d = p.com_m - out.com_m;
    return Eigen::Matrix3d(p.inertia_kgm2 +
                           p.mass_kg * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  out.inertia_kgm2 = shifted(a) + shifted(b);
  return out;
}

std::string non_physical_reason(const MassProperties& m, double size_m) {
  if (!(m.mass_kg > 0)) return fmt::format("mass {} kg is not positive", m.mass_kg);
  const Eigen::Matrix3d& I = m.inertia_kgm2;
  if (!I.allFinite()) return "the inertia is not finite";
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(0.5 * (I + I.transpose()));
  const Eigen::Vector3d p = solver.eigenvalues();  // ascending
  if (!(p.x() > 0))
    return fmt::format("the inertia is not positive definite (principal moments {:.4g}, {:.4g}, {:.4g} kg*m^2)", p.x(),
                       p.y(), p.z());
  // Each principal moment of a real body is at most the sum of the other two (equal for a flat
  // plate); 1e-9 of the largest allows for the rounding of values written with a few digits.
  if (p.z() > (p.x() + p.y()) * (1 + 1e-9) + 1e-12)
    return fmt::format("the principal moments {:.4g}, {:.4g}, {:.4g} kg*m^2 break the triangle inequality "
                       "(the largest exceeds the sum of the other two)",
                       p.x(), p.y(), p.z());
  // No point of a body lies further from its centre than the body's extent, so neither can its
  // radius of gyration about any axis through that centre: sqrt(I_max / m) <= size.
  const double gyration = std::sqrt(p.z() / m.mass_kg);
  if (size_m > 0 && gyration > size_m)
    return fmt::format("its radius of gyration sqrt({:.4g} kg*m^2 / {:.4g} kg) = {:.3g} m is larger than the link "
                       "itself ({:.3g} m across), as a placeholder inertia has",
                       p.z(), m.mass_kg, gyration, size_m);
  return "";
}

MassProperties solid_shape(const ShapeDesc& shape, double density_kg_m3) {
  MassProperties out;
  Eigen::Vector3d d(0, 0, 0);
  Eigen::Vector3d centre(0, 0, 0);
  switch (shape.kind) {
    case ShapeDesc::Kind::Sphere: {
      const double r = shape.size_m.x();
      out.mass_kg = density_kg_m3 * 4.0 / 3.0 * M_PI * r * r * r;
      out.inertia_kgm2 = Eigen::Matrix3d::Identity() * 0.4 * out.mass_kg * r * r;
      return out;
    }
    case ShapeDesc::Kind::Cylinder: {
      const double r = shape.size_m.x(), l = shape.size_m.z();
      out.mass_kg = density_kg_m3 * M_PI * r * r * l;
      const double across = out.mass_kg * (3 * r * r + l * l) / 12.0;
      out.inertia_kgm2.diagonal() << across, across, 0.5 * out.mass_kg * r * r;
      return out;
    }
    case ShapeDesc::Kind::Box: d = shape.size_m; break;
    case ShapeDesc::Kind::Mesh: {
      Eigen::Vector3f lo, hi;
      mesh_bounds(shape.mesh, lo, hi);
      d = (hi - lo).cast<double>();
      centre = 0.5 * (hi + lo).cast<double>();
      break;
    }
  }
  out.mass_kg = density_kg_m3 * d.x() * d.y() * d.z();
  out.inertia_kgm2.diagonal() << d.y() * d.y() + d.z() * d.z(), d.x() * d.x() + d.z() * d.z(),
      d.x() * d.x() + d.y() * d.y();
  out.inertia_kgm2 *= out.mass_kg / 12.0;
  out.com_m = centre;
  return out;
}

}  // namespace sear
