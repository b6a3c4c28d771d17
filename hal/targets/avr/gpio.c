/* Digital pins by their Arduino Mega number: direction, pull-up, level. */
#include <hal/gpio.h>

#include "pin_map.h"

#include <util/atomic.h>

void pin_mode(uint8_t pin, uint8_t mode)
{
    pin_io io = hal_avr_pin_io(pin);
    if (!io.mask)
        return;
    /* A pin given a new role is no longer the timer's, as on a digital_write; otherwise a
     * later OUTPUT would silently bring old PWM back. */
    hal_avr_pin_timer_off(pin);
    /* Ports H..L are outside the reach of sbi/cbi, and handlers may touch the same port, so
     * each read-modify-write runs with interrupts off. */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        switch (mode) {
        case OUTPUT:
            PIN_DDR(io) |= io.mask;
            break;
        case INPUT:
            PIN_DDR(io) &= (uint8_t)~io.mask;
            PIN_PORT(io) &= (uint8_t)~io.mask;
            break;
        case INPUT_PULLUP:
            PIN_DDR(io) &= (uint8_t)~io.mask;
            PIN_PORT(io) |= io.mask;
            break;
        default:
            break;
        }
    }
}

uint8_t digital_read(uint8_t pin)
{
    pin_io io = hal_avr_pin_io(pin);
    if (!io.mask)
        return LOW;
    return (PIN_IN(io) & io.mask) ? HIGH : LOW;
}

void digital_write(uint8_t pin, uint8_t level)
{
    pin_io io = hal_avr_pin_io(pin);
    if (!io.mask)
        return;
    hal_avr_pin_timer_off(pin);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        if (level == LOW)
            PIN_PORT(io) &= (uint8_t)~io.mask;
        else
            PIN_PORT(io) |= io.mask;
    }
}

void digital_toggle(uint8_t pin)
{
    pin_io io = hal_avr_pin_io(pin);
    if (!io.mask)
        return;
    hal_avr_pin_timer_off(pin);
    /* Writing a one to PINx flips PORTx in hardware, in one store: no read-modify-write. */
    PIN_IN(io) = io.mask;
}
