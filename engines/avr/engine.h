/* The AVR engine's shared state: one ATmega2560 on libsimavr, its clock in cycles against the
 * link's nanoseconds, and the parts (pins, USARTs, buses) that turn register traffic into link
 * events and device-model calls. One process per MCU, so this state is global. */
#ifndef SEAR_ENGINES_AVR_ENGINE_H
#define SEAR_ENGINES_AVR_ENGINE_H

#include <stdint.h>

#include "lockstep_link.h"

struct avr_t;

struct engine {
  struct avr_t *avr;
  struct sear_link *link;
  uint64_t clock_hz;
  uint64_t quantum_end_cycle; /* the first cycle at or after the quantum's end */
  int64_t quantum_end_ns;
  int64_t turn_start_ns;      /* the link's clock when this turn began: no event before it */
  uint16_t bss_end;           /* the first SRAM address above .data and .bss */
  uint16_t lowest_sp;         /* the deepest the stack has gone */
  uint32_t code_end;          /* the first flash byte past the image */
};

extern struct engine engine;

/* Exact conversions between the chip's cycles and the link's nanoseconds. */
int64_t engine_ns_of_cycle(uint64_t cycle);
uint64_t engine_cycle_at_or_after(int64_t t_ns);
/* The time of the cycle the chip is at, never past the quantum's end (an instruction may run
 * a few cycles over it; what it does is stamped at the end). */
int64_t engine_now_ns(void);

/* The link's event queue (hands over to drain it when full) and fatal refusals. */
void engine_emit(enum sear_event_kind kind, uint8_t index, uint32_t value, int64_t time_ns);
void engine_fatal(const char *format, ...) __attribute__((noreturn, format(printf, 1, 2)));

/* Pins (pins.c): the board interface of devices.h, the firmware's outputs as events. */
void avr_pins_init(void);
void avr_pin_change_init(void); /* PCINT1 and PCINT2, which simavr 1.6 lacks */
void avr_pins_poll_pwm(void); /* timer outputs: duty and servo pulses from the registers */
uint8_t avr_pin_at(int port, int bit); /* the board's pin on port A..L (0..10) bit, >= SEAR_LINK_PINS if none */

/* The wiring report's usage (usage.c): pins and ADC channels the firmware read. */
void avr_usage_init(void);
void avr_usage_note_interrupts(void); /* once a quantum */

/* USARTs (usarts.c). */
void avr_usarts_init(void);
void avr_usarts_take_quantum(void);  /* the link's rx[] for the quantum just begun */
int64_t avr_usarts_next_ns(void);    /* the next byte's stop-bit end, INT64_MAX if none */
void avr_usarts_run_due(int64_t now_ns);
uint32_t avr_usart_overruns(int n); /* bytes lost to overrun on USARTn so far */

/* Timers (timer_modes.c): defines the phase-correct PWM modes simavr 1.6 leaves undefined,
 * before the firmware runs; returns how many timers it found. */
int avr_timer_modes_define(struct avr_t *avr);

/* The EEPROM the project keeps (eeprom.c): loaded before the chip starts, saved at each
 * hand-over; neither does anything when the project does not keep it. */
void avr_eeprom_load(void);
void avr_eeprom_save(void);

/* SPI and TWI (buses.c). */
void avr_buses_init(void);

#endif
