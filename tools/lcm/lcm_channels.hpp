// The LCM channels a run publishes and listens on (docs/bridges.md lists them), one place for the
// bridge, the tests and users' programs to agree.
#pragma once

#include <string>

namespace sear {

inline constexpr const char* kLcmDefaultUrl = "udpm://239.255.76.67:7667?ttl=0";  // ttl=0: stays on this machine
inline constexpr const char* kLcmClockChannel = "SEAR/CLOCK";                     // sear.sim_clock_t
inline constexpr const char* kLcmControlChannel = "SEAR/CONTROL";                 // sear.control_t, subscribed

std::string lcm_pose_channel(const std::string& robot);   // SEAR/<robot>/POSE, sear.pose_t
std::string lcm_drive_channel(const std::string& robot);  // SEAR/<robot>/DRIVE, sear.drive_t, subscribed
// SEAR/<robot>/<mcu>/<device>/READING, sear.reading_t
std::string lcm_reading_channel(const std::string& robot, const std::string& mcu, const std::string& device);
// SEAR/<robot>/<mcu>/<device>/TX or RX, sear.serial_t
std::string lcm_serial_channel(const std::string& robot, const std::string& mcu, const std::string& device,
                               bool from_device);
std::string lcm_outputs_channel(const std::string& robot, const std::string& mcu);  // sear.outputs_t
std::string lcm_can_channel(const std::string& bus);                                // SEAR/CAN/<bus>, sear.can_t

}  // namespace sear
