#include "exporters/trace_csv.hpp"

#include <fmt/format.h>


namespace sear {

namespace {
// Signed duty: positive forward, negative reverse; brake and coast both apply no drive voltage.
double signed_duty(const DcMotorCommand& c) {
  switch (c.direction) {
    case MotorDirection::Forward: return c.duty;
    case MotorDirection::Reverse: return -c.duty;
    default: return 0.0;
  }
}

const char* mode_letter(MotorDirection d) {
  switch (d) {
    case MotorDirection::Forward: return "F";
    case MotorDirection::Reverse: return "R";
    case MotorDirection::Brake: return "B";
    case MotorDirection::Coast: return "C";
  }
  return "?";
}
}  // namespace

TraceCsv::TraceCsv(const std::string& folder, const Simulation& sim, std::uint64_t max_file_bytes) {
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const RobotDesc& d = sim.robot(r).desc();
    const std::string path = fmt::format("{}/trace_{}.csv", folder, d.name);
    files_.push_back(std::make_unique<BoundedFile>(path, max_file_bytes, text_truncation_note(max_file_bytes)));
    std::string header =
        "time_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,vx_mps,vy_mps,vz_mps,wx_radps,wy_radps,wz_radps,forward_mps";
    for (const auto& w : d.wheels) header += fmt::format(",wheel_{}_radps", w.name);
    for (const auto& m : d.motors) header += fmt::format(",motor_{}_duty,motor_{}_mode", m.name, m.name);
    for (const auto& s : d.servos) header += fmt::format(",servo_{}_pulse_us", s.name);
    files_.back()->write(header + "\n");
  }
}

void TraceCsv::write_row(const Simulation& sim) {
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const Vehicle& v = sim.robot(r);
    const VehicleState s = v.state();
    fmt::memory_buffer row;
    // Fixed decimals: the same state always prints the same bytes (the determinism tests compare them).
    fmt::format_to(std::back_inserter(row), "{:.6f}", sim.time_s());
    const auto put = [&](double x) { fmt::format_to(std::back_inserter(row), ",{:.6f}", x); };
    for (int i = 0; i < 3; ++i) put(s.position_m[i]);
    for (int i = 0; i < 3; ++i) put(s.roll_pitch_yaw[i]);
    for (int i = 0; i < 3; ++i) put(s.velocity_mps[i]);
    for (int i = 0; i < 3; ++i) put(s.angular_velocity[i]);
    put(s.forward_speed_mps);
    for (std::size_t w = 0; w < v.desc().wheels.size(); ++w) put(v.wheel_speed(w));
    for (std::size_t m = 0; m < v.desc().motors.size(); ++m) {
      put(signed_duty(v.motor_command(m)));
      fmt::format_to(std::back_inserter(row), ",{}", mode_letter(v.motor_command(m).direction));
    }
    for (std::size_t k = 0; k < v.desc().servos.size(); ++k) fmt::format_to(std::back_inserter(row), ",{:.1f}", v.servo_pulse(k));
    row.push_back('\n');
    files_[r]->write(std::string_view(row.data(), row.size()));
  }
  flush();
}

std::vector<const BoundedFile*> TraceCsv::outputs() const {
  std::vector<const BoundedFile*> out;
  for (const auto& f : files_) out.push_back(f.get());
  return out;
}

void TraceCsv::flush() {
  // Each row reaches the file before the next step, so a run that dies keeps all it traced; a
  // full disk is an error, not a silently short trace.
  for (auto& f : files_) f->flush();
}

}  // namespace sear
