// Debian's arduino-core-avr WString.cpp, compiled unchanged for the host: this file's Arduino.h comes
// first, so the core's own "Arduino.h" (which would pull in the AVR's registers) finds its guard
// set and adds nothing.
#include <Arduino.h>

#include "WString.cpp"
