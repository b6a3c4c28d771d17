// The device kinds SEAR knows, one registration line each: its element name, which names the
// function returning its row (XML element, wiring, parameters, factory) of the table.
#pragma once

#include "scene/device_kind.hpp"

#define SEAR_DEVICE_KINDS(X) \
  X(gp2d12)                  \
  X(gp2d15)                  \
  X(bump)                    \
  X(hcsr04)                  \
  X(maxbotix_lv_ez)          \
  X(lms2xx)                  \
  X(quadrature_encoder)      \
  X(mpu6000)                 \
  X(mpu6050)                 \
  X(hmc5883l)                \
  X(qmc5883l)                \
  X(ublox_neo6m)             \
  X(mtk3339)

namespace sear {

#define SEAR_DECLARE_KIND(name) const DeviceKind& name##_kind();
SEAR_DEVICE_KINDS(SEAR_DECLARE_KIND)
#undef SEAR_DECLARE_KIND

}  // namespace sear
