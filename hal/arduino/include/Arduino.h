/* The Arduino API for the simulated build (issue 19): an Arduino Mega 2560's pins and macros on
 * SEAR's C HAL. ARDUINO is defined, __AVR__ and ARDUINO_ARCH_AVR are not, so libraries take their
 * portable paths. Print, Stream and WString are Debian's arduino-core-avr, compiled unchanged.
 * The guard is the core's own (Arduino_h), so that the core's sources, which include "Arduino.h"
 * from their own folder, find this one already included. */
#ifndef Arduino_h
#define Arduino_h

#include <ctype.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <avr/pgmspace.h>
#include <hal/adc.h>
#include <hal/gpio.h>
#include <hal/irq.h>
#include <hal/time.h>
#include <sear_registers_refused.h>

#ifndef ARDUINO
#define ARDUINO 10807 /* the IDE release whose core (arduino-core-avr 1.8.7) this follows */
#endif
#define ARDUINO_ARCH_SEAR 1
#define ARDUINO_AVR_MEGA2560_SEAR 1
#ifndef F_CPU
#define F_CPU 16000000UL
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Constants (hal/gpio.h already gives HIGH, LOW, INPUT, OUTPUT, INPUT_PULLUP, A0..A15) ---- */
#define PI 3.1415926535897932384626433832795
#define HALF_PI 1.5707963267948966192313216916398
#define TWO_PI 6.283185307179586476925286766559
#define DEG_TO_RAD 0.017453292519943295769236907684886
#define RAD_TO_DEG 57.295779513082320876798154814105
#define EULER 2.718281828459045235360287471352

#define SERIAL 0x0
#define DISPLAY 0x1
#define LSBFIRST 0
#define MSBFIRST 1

/* attachInterrupt() modes, with the values the AVR core gives them */
#define CHANGE 1
#define FALLING 2
#define RISING 3

/* analogReference(), the Mega's values */
#define DEFAULT 1
#define EXTERNAL 0
#define INTERNAL1V1 2
#define INTERNAL2V56 3
#define INTERNAL INTERNAL1V1

#define NOT_A_PIN 0
#define NOT_A_PORT 0
#define NOT_AN_INTERRUPT -1

/* ---- The Mega 2560's pins (pins_arduino.h, variant "mega") ---- */
#define NUM_DIGITAL_PINS 70
#define NUM_ANALOG_INPUTS 16
#define LED_BUILTIN 13
#define PIN_SPI_SS 53
#define PIN_SPI_MOSI 51
#define PIN_SPI_MISO 50
#define PIN_SPI_SCK 52
#define PIN_WIRE_SDA 20
#define PIN_WIRE_SCL 21
#define SS PIN_SPI_SS
#define MOSI PIN_SPI_MOSI
#define MISO PIN_SPI_MISO
#define SCK PIN_SPI_SCK
#define SDA PIN_WIRE_SDA
#define SCL PIN_WIRE_SCL
#define PIN_A0 A0
#define PIN_A1 A1
#define PIN_A2 A2
#define PIN_A3 A3
#define PIN_A4 A4
#define PIN_A5 A5
#define PIN_A6 A6
#define PIN_A7 A7
#define PIN_A8 A8
#define PIN_A9 A9
#define PIN_A10 A10
#define PIN_A11 A11
#define PIN_A12 A12
#define PIN_A13 A13
#define PIN_A14 A14
#define PIN_A15 A15
#define analogInputToDigitalPin(p) (((p) < 16) ? (p) + 54 : -1)
#define digitalPinHasPWM(p) (((p) >= 2 && (p) <= 13) || ((p) >= 44 && (p) <= 46))
/* INT0..INT5 are on pins 21, 20, 19, 18, 2, 3; the core numbers them 2, 3, 4, 5, 0, 1. */
#define digitalPinToInterrupt(p) \
  ((p) == 2 ? 0 : ((p) == 3 ? 1 : ((p) >= 18 && (p) <= 21 ? 23 - (p) : NOT_AN_INTERRUPT)))
#define digitalPinToPCICR(p) \
  ((((p) >= 10 && (p) <= 13) || ((p) >= 50 && (p) <= 53) || ((p) >= 62 && (p) <= 69)) ? 1 : 0)

/* ---- Macros ---- */
#define constrain(amt, low, high) ((amt) < (low) ? (low) : ((amt) > (high) ? (high) : (amt)))
#define radians(deg) ((deg) * DEG_TO_RAD)
#define degrees(rad) ((rad) * RAD_TO_DEG)
#define sq(x) ((x) * (x))
#define lowByte(w) ((uint8_t)((w) & 0xff))
#define highByte(w) ((uint8_t)((w) >> 8))
#define bitRead(value, bit) (((value) >> (bit)) & 0x01)
#define bitSet(value, bit) ((value) |= (1UL << (bit)))
#define bitClear(value, bit) ((value) &= ~(1UL << (bit)))
#define bitToggle(value, bit) ((value) ^= (1UL << (bit)))
#define bitWrite(value, bit, bitvalue) ((bitvalue) ? bitSet(value, bit) : bitClear(value, bit))
#define bit(b) (1UL << (b))
#define clockCyclesPerMicrosecond() (F_CPU / 1000000L)
#define clockCyclesToMicroseconds(a) ((a) / clockCyclesPerMicrosecond())
#define microsecondsToClockCycles(a) ((a) * clockCyclesPerMicrosecond())
#define interrupts() irq_enable()
#define noInterrupts() irq_disable()

typedef unsigned int word;
typedef bool boolean;
typedef uint8_t byte;

/* ---- Functions ---- */
void pinMode(uint8_t pin, uint8_t mode);
void digitalWrite(uint8_t pin, uint8_t val);
int digitalRead(uint8_t pin);
int analogRead(uint8_t pin);
void analogReference(uint8_t mode);
void analogWrite(uint8_t pin, int val);
void delay(unsigned long ms);
void delayMicroseconds(unsigned int us);
unsigned long pulseIn(uint8_t pin, uint8_t state, unsigned long timeout);
unsigned long pulseInLong(uint8_t pin, uint8_t state, unsigned long timeout);
void shiftOut(uint8_t dataPin, uint8_t clockPin, uint8_t bitOrder, uint8_t val);
uint8_t shiftIn(uint8_t dataPin, uint8_t clockPin, uint8_t bitOrder);
void attachInterrupt(uint8_t interruptNum, void (*userFunc)(void), int mode);
void detachInterrupt(uint8_t interruptNum);
void yield(void);

void setup(void);
void loop(void);

/* avr-libc's number formatting, which WString uses (stdlib_avr.c) */
char *itoa(int value, char *s, int radix);
char *ltoa(long value, char *s, int radix);
char *utoa(unsigned int value, char *s, int radix);
char *ultoa(unsigned long value, char *s, int radix);
char *dtostrf(double val, signed char width, unsigned char prec, char *s);

#ifdef __cplusplus
} /* extern "C" */

#include "WCharacter.h"
#include "WString.h"
#include "HardwareSerial.h"

/* min and max as functions, not the AVR core's macros, which would break the host's C++ headers. */
template <class T, class U>
constexpr auto min(const T &a, const U &b) -> decltype(a < b ? a : b) { return b < a ? b : a; }
template <class T, class U>
constexpr auto max(const T &a, const U &b) -> decltype(a < b ? a : b) { return a < b ? b : a; }

unsigned int makeWord(unsigned int w);
unsigned int makeWord(unsigned char h, unsigned char l);
#define word(...) makeWord(__VA_ARGS__)

unsigned long pulseIn(uint8_t pin, uint8_t state);
unsigned long pulseInLong(uint8_t pin, uint8_t state);
void tone(uint8_t pin, unsigned int frequency, unsigned long duration = 0);
void noTone(uint8_t pin);

/* WMath.cpp (Debian's core) */
long random(long howbig);
long random(long howsmall, long howbig);
void randomSeed(unsigned long seed);
long map(long value, long fromLow, long fromHigh, long toLow, long toHigh);
#endif

#endif
