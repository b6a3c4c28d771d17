#include "lcm/reading_meaning.hpp"

#include <map>

namespace sear {
namespace {

struct Meanings {
  ReadingMeaning sample;  // mirrors the value[] comments of enum sear_input_kind
  ReadingMeaning output;  // mirrors those of struct sear_link_reading
};

const ReadingMeaning kImuValues{{"specific_force_x", "specific_force_y", "specific_force_z", "angular_rate_x",
                                 "angular_rate_y", "angular_rate_z"},
                                {"m/s^2", "m/s^2", "m/s^2", "rad/s", "rad/s", "rad/s"}};
const ReadingMeaning kFieldValues{{"field_x", "field_y", "field_z"}, {"T", "T", "T"}};

const Meanings* find(const std::string& element) {
  static const std::map<std::string, Meanings> table = {
      {"gp2d12", {{{"distance"}, {"m"}}, {{"output_voltage"}, {"V"}}}},
      {"gp2d15", {{{"distance"}, {"m"}}, {{"output_level"}, {"1"}}}},
      {"hcsr04", {{{"distance"}, {"m"}}, {{"echo_width", "distance"}, {"s", "m"}}}},
      {"bump", {{{"closed"}, {"1"}}, {{"closed"}, {"1"}}}},
      {"maxbotix_lv_ez", {{{"range"}, {"in"}}, {{"output_voltage", "range"}, {"V", "in"}}}},
      {"quadrature_encoder", {{{"shaft_angle", "shaft_rate"}, {"rad", "rad/s"}}, {{"count", "shaft_angle"}, {"1", "rad"}}}},
      {"mpu6000", {kImuValues, kImuValues}},
      {"mpu6050", {kImuValues, kImuValues}},
      {"hmc5883l", {kFieldValues, kFieldValues}},
      {"qmc5883l", {kFieldValues, kFieldValues}},
  };
  const auto it = table.find(element);
  return it == table.end() ? nullptr : &it->second;
}

const ReadingMeaning kUnknown{{"value0", "value1", "value2", "value3", "value4", "value5"},
                              {"?", "?", "?", "?", "?", "?"}};

}  // namespace

const ReadingMeaning& reading_meaning(const std::string& element) {
  const Meanings* m = find(element);
  return m ? m->sample : kUnknown;
}

const ReadingMeaning& output_meaning(const std::string& element) {
  const Meanings* m = find(element);
  return m ? m->output : kUnknown;
}

}  // namespace sear
