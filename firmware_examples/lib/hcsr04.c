/* The HC-SR04 ranger: see hcsr04.h. Figures from the HC-SR04 datasheet (ElecFreaks/Cytron):
 * trigger at least 10 us, range = high time / 58 in cm, a measurement cycle of over 60 ms so that
 * the last echo has died away, and a 38 ms pulse when nothing is in range. */
#include "hcsr04.h"

#include <hal/hal.h>

#define TRIGGER_US 12 /* datasheet: at least 10 us */

static uint8_t trig_pin, echo_pin;
static volatile uint32_t rise_us, width;
static volatile uint8_t echo_done;

static void on_echo(void) {
  const uint32_t now = micros();
  if (digital_read(echo_pin)) {
    rise_us = now;
  } else {
    width = now - rise_us;
    echo_done = 1;
  }
}

void hcsr04_begin(uint8_t trig, uint8_t echo) {
  trig_pin = trig;
  echo_pin = echo;
  pin_mode(trig, OUTPUT);
  digital_write(trig, LOW);
  pin_mode(echo, INPUT);
  irq_attach_pin(echo, IRQ_CHANGE, on_echo);
}

void hcsr04_trigger(void) {
  echo_done = 0;
  digital_write(trig_pin, HIGH);
  delay_us(TRIGGER_US);
  digital_write(trig_pin, LOW);
}

uint8_t hcsr04_done(uint32_t *width_us) {
  if (!echo_done) return 0;
  irq_disable(); /* a 32-bit value is four byte reads on the AVR: keep the handler out */
  *width_us = width;
  irq_enable();
  return 1;
}
