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

const std::vector<TraceColumn>& trace_columns() {
  static const std::vector<TraceColumn> columns{
      {"time_s", TracePer::Robot, "sim time"},
      {"x_m", TracePer::Robot, "position, world (x east, y north, z up)"},
      {"y_m", TracePer::Robot, ""},
      {"z_m", TracePer::Robot, ""},
      {"roll_rad", TracePer::Robot, "attitude, Z-Y-X Euler angles"},
      {"pitch_rad", TracePer::Robot, ""},
      {"yaw_rad", TracePer::Robot, ""},
      {"vx_mps", TracePer::Robot, "velocity, world"},
      {"vy_mps", TracePer::Robot, ""},
      {"vz_mps", TracePer::Robot, ""},
      {"wx_radps", TracePer::Robot, "angular velocity, world"},
      {"wy_radps", TracePer::Robot, ""},
      {"wz_radps", TracePer::Robot, ""},
      {"forward_mps", TracePer::Robot, "speed along the chassis' x axis"},
      {"wheel_{}_radps", TracePer::Wheel, "per wheel: spin relative to the chassis, positive rolling forward"},
      {"motor_{}_duty", TracePer::Motor, "per motor: duty, signed (+ forward, − reverse)"},
      {"motor_{}_mode", TracePer::Motor, "per motor: F forward, R reverse, B brake, C coast"},
      {"servo_{}_pulse_us", TracePer::Servo, "per servo: the pulse it is given (µs, 0 for none)"},
      {"joint_{}_pos", TracePer::Joint,
       "per live URDF joint: its position from the URDF's zero (rad, or m for a prismatic one)"},
  };
  return columns;
}

// "`time_s` sim time; `x_m` `y_m` `z_m` position, ...": columns that share a meaning are named
// together before it; `<name>` stands for the part's name.
std::string trace_columns_markdown() {
  const auto& columns = trace_columns();
  std::string out;
  for (std::size_t i = 0; i < columns.size();) {
    std::size_t end = i + 1;
    while (end < columns.size() && !*columns[end].meaning) ++end;
    if (!out.empty()) out += "; ";
    for (std::size_t k = i; k < end; ++k) {
      std::string name = columns[k].name;
      if (const auto at = name.find("{}"); at != std::string::npos) name.replace(at, 2, "<name>");
      out += fmt::format("`{}` ", name);
    }
    out += columns[i].meaning;
    i = end;
  }
  return out + ".";
}

TraceCsv::TraceCsv(const std::string& folder, const Simulation& sim, std::uint64_t max_file_bytes) {
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const RobotDesc& d = sim.robot(r).desc();
    const std::string path = fmt::format("{}/trace_{}.csv", folder, d.name);
    files_.push_back(std::make_unique<BoundedFile>(path, max_file_bytes, text_truncation_note(max_file_bytes)));
    std::string header;
    const auto add = [&](TracePer per, const std::string& part) {
      for (const TraceColumn& c : trace_columns())
        if (c.per == per) header += (header.empty() ? "" : ",") + fmt::format(fmt::runtime(c.name), part);
    };
    add(TracePer::Robot, "");
    for (const auto& w : d.wheels) add(TracePer::Wheel, w.name);
    for (const auto& m : d.motors) add(TracePer::Motor, m.name);
    for (const auto& sv : d.servos) add(TracePer::Servo, sv.name);
    for (const auto& j : d.joints) add(TracePer::Joint, j.joint);
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
    for (std::size_t j = 0; j < v.joint_count(); ++j) put(v.joint(j).position());
    row.push_back('\n');
    files_[r]->write(std::string_view(row.data(), row.size()));
  }
}

std::vector<const BoundedFile*> TraceCsv::outputs() const {
  std::vector<const BoundedFile*> out;
  for (const auto& f : files_) out.push_back(f.get());
  return out;
}

void TraceCsv::flush() {
  for (auto& f : files_) f->flush();
}

}  // namespace sear
