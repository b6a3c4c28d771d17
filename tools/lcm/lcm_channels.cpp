#include "lcm/lcm_channels.hpp"

namespace sear {

std::string lcm_pose_channel(const std::string& robot) { return "SEAR/" + robot + "/POSE"; }
std::string lcm_drive_channel(const std::string& robot) { return "SEAR/" + robot + "/DRIVE"; }
std::string lcm_reading_channel(const std::string& robot, const std::string& mcu, const std::string& device) {
  return "SEAR/" + robot + "/" + mcu + "/" + device + "/READING";
}
std::string lcm_serial_channel(const std::string& robot, const std::string& mcu, const std::string& device,
                               bool from_device) {
  return "SEAR/" + robot + "/" + mcu + "/" + device + (from_device ? "/TX" : "/RX");
}
std::string lcm_outputs_channel(const std::string& robot, const std::string& mcu) {
  return "SEAR/" + robot + "/" + mcu + "/OUTPUTS";
}
std::string lcm_can_channel(const std::string& bus) { return "SEAR/CAN/" + bus; }

}  // namespace sear
