// What the Arduino layer cannot model stops the MCU with a message naming the call (and, through
// the run's report, the sim time and the last HAL call), never silently.
#pragma once

[[noreturn]] void sear_arduino_refuse(const char* call, const char* why);
