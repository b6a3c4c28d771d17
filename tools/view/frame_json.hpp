// The world part of the viewer's "frame" message (tools/view/PROTOCOL.md section 3): each robot's
// pose, wheels and what its sensors see now, and where the movable obstacles are.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "runtime/simulation.hpp"
#include "scene/geodetic.hpp"
#include "sensors/range_sensor.hpp"
#include "view/mcu_panel.hpp"

namespace sear {

class FrameWorld {
 public:
  explicit FrameWorld(const ProjectDesc& project);

  // "robots" and "obstacles" of a frame. `panels` in Lockstep's MCU order (robots, then their MCUs).
  // Casts rays for cones whose model gets no truth sample (a MaxBotix's serial output): call it
  // from the thread that steps `sim`, between steps.
  void put(const Simulation& sim, const std::vector<McuPanel>& panels, nlohmann::ordered_json& frame);

 private:
  nlohmann::ordered_json sensor(const Simulation& sim, std::size_t robot, std::size_t mcu, std::size_t device,
                                const PanelDevice& panel);

  const ProjectDesc& project_;
  LocalTangentPlane plane_;
  std::map<std::pair<std::size_t, std::size_t>, std::unique_ptr<RangeSensor>> casters_;  // by (mcu, device)
};

}  // namespace sear
