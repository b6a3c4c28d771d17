/* pulse_in on the chip: the pin polled through its PIN register, timed with micros() (4 us steps
 * of timer0), as the Arduino core's pulseInLong does; interrupts stay on. */
#include <hal/pulse.h>
#include <hal/time.h>

#include "pin_map.h"

#include <avr/io.h>

static uint8_t level_of(pin_io io)
{
    return (PIN_IN(io) & io.mask) ? 1u : 0u;
}

uint32_t pulse_in(uint8_t pin, uint8_t level, uint32_t timeout_us)
{
    pin_io io = hal_avr_pin_io(pin);
    if (io.mask == 0)
        return 0;
    uint8_t want = level ? 1u : 0u;
    uint32_t start = micros();
    while (level_of(io) == want) {
        if (micros() - start >= timeout_us)
            return 0;
    }
    while (level_of(io) != want) {
        if (micros() - start >= timeout_us)
            return 0;
    }
    uint32_t began = micros();
    while (level_of(io) == want) {
        if (micros() - start >= timeout_us)
            return 0;
    }
    return micros() - began;
}
