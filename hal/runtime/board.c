/* Pin capabilities of the ATmega2560 as wired on an Arduino Mega 2560 (datasheet table 1-1 and
 * the board's schematic): which pins reach a timer's output compare, which an interrupt. */
#include "board.h"

int board_has_pwm(uint8_t pin) { return (pin >= 2 && pin <= 13) || (pin >= 44 && pin <= 46); }

int board_has_servo(uint8_t pin) {
  switch (pin) {
    case 2: case 3: case 5:    /* timer 3 */
    case 6: case 7: case 8:    /* timer 4 */
    case 11: case 12:          /* timer 1 */
    case 44: case 45: case 46: /* timer 5 */
      return 1;
    default:
      return 0;
  }
}

int board_has_interrupt(uint8_t pin) {
  if (pin == 2 || pin == 3 || (pin >= 18 && pin <= 21)) return 1; /* INT4, INT5, INT3..INT0 */
  return board_has_pin_change(pin);
}

int board_has_pin_change(uint8_t pin) {
  if (pin >= 10 && pin <= 15) return 1;                            /* PCINT4..7, PCINT9..10 */
  if (pin >= 50 && pin <= 53) return 1;                            /* PCINT0..3 */
  return pin >= 62 && pin <= 69;                                   /* A8..A15: PCINT16..23 */
}
