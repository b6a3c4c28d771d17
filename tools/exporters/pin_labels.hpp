// What is wired to each of an MCU's pins, as the waveforms name them: "sonar.trig", "left.pwm",
// "gps.rx" (the GPS's RX, on the MCU's TX pin), so that a logic analyser's view reads as the wiring.
#pragma once

#include <string>
#include <vector>

namespace sear {

struct McuDesc;

// One label per pin of the board (SEAR_LINK_PINS), empty where nothing is wired. Names are made
// of letters, digits, '_', '-' and '.', as a VCD name and sigrok's decoder options take them;
// several things on one pin are joined with '+'.
std::vector<std::string> pin_labels(const McuDesc& mcu);

}  // namespace sear
