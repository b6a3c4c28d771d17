// See refuse.hpp.
#include "refuse.hpp"

#include <hal/system.h>

#include <string>

void sear_arduino_refuse(const char* call, const char* why) {
  const std::string message = std::string(call) + ": " + why + " (the Arduino layer on SEAR's HAL cannot model this)";
  hal_refuse(message.c_str());
}
