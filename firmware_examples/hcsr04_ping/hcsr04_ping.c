/* HC-SR04 ultrasonic ranger: a 10 us pulse on TRIG starts a ping, and ECHO stays HIGH for the
 * sound's round trip. A pin-change interrupt on ECHO stamps both edges with micros(), so the main
 * loop never busy-waits on the pin. Figures from the HC-SR04 datasheet (ElecFreaks/Cytron): trigger
 * at least 10 us, range = high time / 58 in cm, a measurement cycle of over 60 ms so that the last
 * echo has died away, and a 38 ms pulse when nothing is in range.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#define CONSOLE 0
#define TRIG_PIN 24 /* output */
#define ECHO_PIN 10 /* input with a pin-change interrupt (PCINT4) */

#define TRIGGER_US 12    /* datasheet: at least 10 us */
#define CYCLE_MS 65      /* datasheet: "over 60 ms measurement cycle"; millis() ticks in whole ms, so 65 */
#define NO_ECHO_US 30000 /* over 5 m: the module's 38 ms "nothing there" pulse, or no edge at all */
#define US_PER_CM 58     /* datasheet: us / 58 = cm (2 / 343 m/s = 58.3 us per cm there and back) */

static volatile uint32_t rise_us, width_us;
static volatile uint8_t echo_done;

static void on_echo(void) {
  const uint32_t now = micros();
  if (digital_read(ECHO_PIN)) {
    rise_us = now;
  } else {
    width_us = now - rise_us;
    echo_done = 1;
  }
}

/* One ping: the echo's high time in microseconds, or 0 when none came back in time. */
static uint32_t ping(void) {
  echo_done = 0;
  digital_write(TRIG_PIN, HIGH);
  delay_us(TRIGGER_US);
  digital_write(TRIG_PIN, LOW);
  const uint32_t start = millis();
  while (!echo_done && millis() - start < CYCLE_MS) delay_ms(1);
  irq_disable(); /* a 32-bit value is four byte reads on the AVR: keep the handler out */
  const uint32_t width = echo_done ? width_us : 0;
  irq_enable();
  return width;
}

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  pin_mode(TRIG_PIN, OUTPUT);
  digital_write(TRIG_PIN, LOW);
  pin_mode(ECHO_PIN, INPUT);
  irq_attach_pin(ECHO_PIN, IRQ_CHANGE, on_echo);
  uart_print(CONSOLE, "hcsr04_ping: ready\r\n");
  delay_ms(CYCLE_MS);

  char line[64];
  uint32_t n = 0;
  for (;;) {
    const uint32_t cycle_start = millis();
    const uint32_t width = ping();
    ++n;
    if (width == 0 || width >= NO_ECHO_US) {
      snprintf(line, sizeof line, "ping %lu: no echo\r\n", (unsigned long)n);
    } else {
      const uint32_t tenths_cm = (width * 10u + US_PER_CM / 2) / US_PER_CM;
      snprintf(line, sizeof line, "ping %lu: %lu us, %lu.%lu cm\r\n", (unsigned long)n, (unsigned long)width,
               (unsigned long)(tenths_cm / 10u), (unsigned long)(tenths_cm % 10u));
    }
    uart_print(CONSOLE, line);
    /* the next ping only once this cycle's 60 ms are over, so that no late echo of this one
     * is taken for the next one's */
    while (millis() - cycle_start < CYCLE_MS) delay_ms(1);
  }
}
