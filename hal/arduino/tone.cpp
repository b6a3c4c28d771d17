// tone()/noTone() as the Mega's core makes them: Timer2 in CTC mode, its compare interrupt toggling
// the pin every half-period, one tone at a time. Timer2 is the HAL's one periodic timer here, so
// the edges fall at the interrupt's times, exactly as the chip's do while the sketch waits.
#include <Arduino.h>
#include <hal/irq.h>

#include "refuse.hpp"
#include "tone_timer.hpp"

namespace {

const uint8_t kNoPin = 255;
uint8_t tone_pin = kNoPin;   // the core's tone_pins[0]
volatile long toggle_count;  // > 0: toggles left; < 0: until noTone(); as timer2_toggle_count

// The core's search for Timer2's prescaler (Tone.cpp): the smallest of 1, 8, 32, 64, 128, 256,
// 1024 whose compare value fits 8 bits; a half-period is (OCR2A + 1) * prescaler clock cycles.
// Below 31 Hz even /1024 does not fit and the core writes the value anyway: OCR2A keeps its low
// 8 bits, and the chip plays a higher note (30 Hz comes out at 1953 Hz), as here.
uint32_t half_period_cycles(unsigned int frequency) {
  static const uint32_t kPrescalers[] = {1, 8, 32, 64, 128, 256, 1024};
  uint32_t ocr = 0;
  uint32_t prescaler = 1;
  for (uint32_t p : kPrescalers) {
    prescaler = p;
    ocr = static_cast<uint32_t>(F_CPU / frequency / 2 / p - 1);
    if (ocr <= 255) break;
  }
  return ((ocr & 0xFF) + 1) * prescaler;
}

void on_compare_match() {
  if (toggle_count != 0) {
    digital_toggle(tone_pin);
    if (toggle_count > 0) toggle_count--;
  } else {
    noTone(tone_pin);  // as the core's ISR: frees Timer2 and leaves the pin LOW
  }
}

}  // namespace

bool sear_tone_timer2_taken() { return tone_pin != kNoPin; }

void tone(uint8_t pin, unsigned int frequency, unsigned long duration) {
  // The core has one tone pin: a tone on another pin while one plays is ignored, as toneBegin()
  // finds no free timer.
  if (tone_pin != kNoPin && tone_pin != pin) return;
  if (frequency == 0) sear_arduino_refuse("tone(pin, 0)", "a frequency of 0 Hz divides by zero in the core");
  const uint32_t cycles = half_period_cycles(frequency);
  // The HAL's timer counts whole microseconds from 16 us: the chip's half-periods are whole
  // microseconds for every prescaler from 32 on (up to 3.9 kHz), half-microseconds with
  // prescaler 8 (up to 31.25 kHz), which are rounded up here.
  const uint32_t cycles_per_us = static_cast<uint32_t>(F_CPU / 1000000UL);
  const uint32_t half_us = (cycles + cycles_per_us - 1) / cycles_per_us;
  if (half_us < 16)
    sear_arduino_refuse("tone() above 31250 Hz", "the HAL's timer ticks at most every 16 us");
  if (tone_pin == kNoPin) {
    tone_pin = pin;
    sear_tone_take_timer2();
  }
  pinMode(pin, OUTPUT);
  // As the core's arithmetic on the chip: 2 * frequency in a 16-bit int, then times the duration.
  toggle_count = duration > 0 ? static_cast<long>(static_cast<uint16_t>(2 * frequency) * duration / 1000) : -1;
  irq_timer_start(half_us, on_compare_match);
}

void noTone(uint8_t pin) {
  if (tone_pin == pin) {
    irq_timer_stop();
    tone_pin = kNoPin;
  }
  digitalWrite(pin, LOW);
}
