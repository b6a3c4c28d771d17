// The core's pin, analog, time, pulse and interrupt functions on the HAL, with the AVR core's
// behaviour where it differs from the HAL's (analogWrite on a pin without PWM, analogRead's
// channel numbers, attachInterrupt's numbering).
#include <Arduino.h>
#include <hal/pulse.h>
#include <hal/pwm.h>

#include "refuse.hpp"
#include "servo_timer.hpp"
#include "tone_timer.hpp"

namespace {
bool pwm_running[NUM_DIGITAL_PINS]; /* analogWrite() left a PWM waveform on the pin */
}

namespace {
// TCCRnA = 0 disconnects the compare outputs: the pin keeps the level of its PORT latch, LOW
// after analogWrite()'s pinMode.
void stop_pwm(uint8_t pin) {
  if (pwm_running[pin]) digital_write(pin, LOW);
  pwm_running[pin] = false;
}
}  // namespace

void sear_servo_take_timer5() {
  for (uint8_t pin = 44; pin <= 46; ++pin) stop_pwm(pin);
}

void sear_tone_take_timer2() {
  stop_pwm(9);
  stop_pwm(10);
}

extern "C" {

void pinMode(uint8_t pin, uint8_t mode) { pin_mode(pin, mode); }

void digitalWrite(uint8_t pin, uint8_t val) {
  if (pin < NUM_DIGITAL_PINS) pwm_running[pin] = false;
  digital_write(pin, val ? HIGH : LOW);
}

int digitalRead(uint8_t pin) { return digital_read(pin); }

// 0..15 and A0..A15 (54..69) both name a channel, as on the Mega.
int analogRead(uint8_t pin) {
  if (pin >= A0) pin = static_cast<uint8_t>(pin - A0);
  return adc_read(pin);
}

void analogReference(uint8_t mode) {
  switch (mode) {
    case DEFAULT: adc_reference(ADC_REF_AVCC); break;
    case EXTERNAL: adc_reference(ADC_REF_EXTERNAL); break;
    case INTERNAL1V1: adc_reference(ADC_REF_1V1); break;
    case INTERNAL2V56: adc_reference(ADC_REF_2V56); break;
    default: sear_arduino_refuse("analogReference()", "use DEFAULT, EXTERNAL, INTERNAL1V1 or INTERNAL2V56 (the Mega's)");
  }
}

// As the core: pins without a timer channel, and the ends of the range, get plain levels.
void analogWrite(uint8_t pin, int val) {
  pinMode(pin, OUTPUT);
  if (sear_servo_timer5_taken() && pin >= 44 && pin <= 46)
    sear_arduino_refuse("analogWrite() on pin 44, 45 or 46",
                        "the first Servo took Timer5, as on the Mega, and these pins' PWM stopped with it");
  // On the chip it would rewrite OCR2A, the tone's own compare value, and change its pitch.
  if (sear_tone_timer2_taken() && (pin == 9 || pin == 10))
    sear_arduino_refuse("analogWrite() on pin 9 or 10 while tone() plays",
                        "tone() holds Timer2, as on the Mega; call noTone() first");
  if (val <= 0 || val >= 255 || !digitalPinHasPWM(pin)) {
    digitalWrite(pin, val < 128 ? LOW : HIGH);
    return;
  }
  pwm_write(pin, static_cast<uint8_t>(val));
  pwm_running[pin] = true;
}

void delay(unsigned long ms) { delay_ms(static_cast<uint32_t>(ms)); }

void delayMicroseconds(unsigned int us) { delay_us(us); }

unsigned long pulseIn(uint8_t pin, uint8_t state, unsigned long timeout) {
  return pulse_in(pin, state, static_cast<uint32_t>(timeout));
}

// The core's pulseInLong counts with micros() instead of cycles: here both are the HAL's exact
// measurement.
unsigned long pulseInLong(uint8_t pin, uint8_t state, unsigned long timeout) { return pulseIn(pin, state, timeout); }

void shiftOut(uint8_t dataPin, uint8_t clockPin, uint8_t bitOrder, uint8_t val) {
  for (uint8_t i = 0; i < 8; i++) {
    digitalWrite(dataPin, static_cast<uint8_t>(bitOrder == LSBFIRST ? (val >> i) & 1 : (val >> (7 - i)) & 1));
    digitalWrite(clockPin, HIGH);
    digitalWrite(clockPin, LOW);
  }
}

uint8_t shiftIn(uint8_t dataPin, uint8_t clockPin, uint8_t bitOrder) {
  uint8_t value = 0;
  for (uint8_t i = 0; i < 8; ++i) {
    digitalWrite(clockPin, HIGH);
    if (bitOrder == LSBFIRST)
      value = static_cast<uint8_t>(value | digitalRead(dataPin) << i);
    else
      value = static_cast<uint8_t>(value | digitalRead(dataPin) << (7 - i));
    digitalWrite(clockPin, LOW);
  }
  return value;
}

// The core's interrupt numbers 0..5 are INT4, INT5, INT0..INT3: pins 2, 3, 21, 20, 19, 18.
static const uint8_t kInterruptPins[6] = {2, 3, 21, 20, 19, 18};

void attachInterrupt(uint8_t interruptNum, void (*userFunc)(void), int mode) {
  if (interruptNum >= 6) sear_arduino_refuse("attachInterrupt()", "the Mega has interrupts 0..5 (digitalPinToInterrupt)");
  uint8_t edge = 0;
  switch (mode) {
    case LOW: edge = IRQ_LOW; break;
    case CHANGE: edge = IRQ_CHANGE; break;
    case FALLING: edge = IRQ_FALLING; break;
    case RISING: edge = IRQ_RISING; break;
    default: sear_arduino_refuse("attachInterrupt()", "the mode must be LOW, CHANGE, FALLING or RISING");
  }
  irq_attach_pin(kInterruptPins[interruptNum], edge, userFunc);
}

void detachInterrupt(uint8_t interruptNum) {
  if (interruptNum < 6) irq_detach_pin(kInterruptPins[interruptNum]);
}

void yield(void) {}

}  // extern "C"

unsigned long pulseIn(uint8_t pin, uint8_t state) { return pulseIn(pin, state, 1000000UL); }
unsigned long pulseInLong(uint8_t pin, uint8_t state) { return pulseInLong(pin, state, 1000000UL); }
