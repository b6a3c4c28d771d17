/* Times an HC-SR04's echo the way most Arduino sketches do (pulseIn): raise TRIG for 10 us, then
 * poll ECHO with digital_read() and micros() for its rising and falling edges; prints the width. */
#include <hal/hal.h>
#include <stdio.h>

#define TRIG 24
#define ECHO 10

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(TRIG, OUTPUT);
  pin_mode(ECHO, INPUT);
  char line[48];
  for (;;) {
    delay_ms(70);
    digital_write(TRIG, HIGH);
    delay_us(10);
    digital_write(TRIG, LOW);
    const uint32_t start = micros();
    while (!digital_read(ECHO) && micros() - start < 5000) {
    }
    const uint32_t rise = micros();
    while (digital_read(ECHO) && micros() - rise < 40000) {
    }
    snprintf(line, sizeof line, "echo %lu us\n", (unsigned long)(micros() - rise));
    uart_print(0, line);
  }
}
