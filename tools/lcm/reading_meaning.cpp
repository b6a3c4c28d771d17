#include "lcm/reading_meaning.hpp"

#include <map>

namespace sear {

const ReadingMeaning& reading_meaning(const std::string& element) {
  // Mirrors the value[] comments of enum sear_input_kind.
  static const std::map<std::string, ReadingMeaning> table = {
      {"gp2d12", {{"distance"}, {"m"}}},
      {"gp2d15", {{"distance"}, {"m"}}},
      {"hcsr04", {{"distance"}, {"m"}}},
      {"bump", {{"closed"}, {"1"}}},
      {"maxbotix_lv_ez", {{"range"}, {"in"}}},
      {"quadrature_encoder", {{"shaft_angle", "shaft_rate"}, {"rad", "rad/s"}}},
      {"mpu6000",
       {{"specific_force_x", "specific_force_y", "specific_force_z", "angular_rate_x", "angular_rate_y",
         "angular_rate_z"},
        {"m/s^2", "m/s^2", "m/s^2", "rad/s", "rad/s", "rad/s"}}},
      {"mpu6050",
       {{"specific_force_x", "specific_force_y", "specific_force_z", "angular_rate_x", "angular_rate_y",
         "angular_rate_z"},
        {"m/s^2", "m/s^2", "m/s^2", "rad/s", "rad/s", "rad/s"}}},
      {"hmc5883l", {{"field_x", "field_y", "field_z"}, {"T", "T", "T"}}},
      {"qmc5883l", {{"field_x", "field_y", "field_z"}, {"T", "T", "T"}}},
  };
  static const ReadingMeaning unknown{{"value0", "value1", "value2", "value3", "value4", "value5"},
                                      {"?", "?", "?", "?", "?", "?"}};
  const auto it = table.find(element);
  return it == table.end() ? unknown : it->second;
}

}  // namespace sear
