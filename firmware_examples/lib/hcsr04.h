/* An HC-SR04 ultrasonic ranger: a 10 us pulse on TRIG starts a ping, and ECHO stays HIGH for the
 * sound's round trip; a pin-change interrupt on ECHO stamps both edges with micros(), so nothing
 * busy-waits on the pin. */
#ifndef FIRMWARE_HCSR04_H
#define FIRMWARE_HCSR04_H
#include <stdint.h>

#define HCSR04_CYCLE_MS 65      /* datasheet: "over 60 ms measurement cycle"; millis() ticks in whole ms */
#define HCSR04_NO_ECHO_US 30000 /* over 5 m: the module's 38 ms "nothing there" pulse, or no edge at all */
#define HCSR04_US_PER_CM 58     /* datasheet: us / 58 = cm (2 / 343 m/s = 58.3 us per cm there and back) */

/* TRIG to an output held LOW, ECHO to an input with its interrupt attached. */
void hcsr04_begin(uint8_t trig, uint8_t echo);
/* Starts a ping; its echo is timed in the background. */
void hcsr04_trigger(void);
/* 1 once the echo of the last trigger has ended, its high time in *width_us. */
uint8_t hcsr04_done(uint32_t *width_us);

#endif
