/* A hobbyist's first hour gone wrong in every way the run can see: TRIG pulsed on pin 24 while the
 * project wires the HC-SR04's trig to 22 (ECHO on 23 and ADC channel 0 are read), pin 30 written HIGH without ever
 * being made an OUTPUT (only its pull-up), and a line printed with printf rather than on the UART.
 * The project wires more than the firmware uses (an IR ranger on ADC 3, a GPS on uart1, a compass
 * on I2C, an IMU whose chip select 53 the firmware holds HIGH): no call ever reaches them.
 * WIRING_PROBE_BEFORE_INIT drives a pin, then asks for the clock, before hal_init();
 * WIRING_PROBE_PRINT_AFTER_MS waits that long before its printf. */
#include <hal/hal.h>
#include <stdio.h>

int main(void) {
#ifdef WIRING_PROBE_BEFORE_INIT
  pin_mode(13, OUTPUT); /* the port registers need no hal_init() on the board either */
  digital_write(13, HIGH);
  const uint32_t early = millis(); /* on the board: 0 for ever, as timer 0 is not running yet */
  (void)early;
#endif
  hal_init();
  uart_begin(0, 115200);
  pin_mode(24, OUTPUT);
  pin_mode(23, INPUT);
  digital_write(30, HIGH);
  pin_mode(53, OUTPUT); /* SS: an output keeps the SPI master a master; HIGH selects nobody */
  digital_write(53, HIGH);
#ifdef WIRING_PROBE_PRINT_AFTER_MS
  delay_ms(WIRING_PROBE_PRINT_AFTER_MS);
#endif
  printf("printf reaches the host log only\n");
  char line[40];
  for (;;) {
    digital_write(24, HIGH);
    delay_us(10);
    digital_write(24, LOW);
    const unsigned long echo_us = (unsigned long)pulse_in(23, HIGH, 30000);
    snprintf(line, sizeof line, "echo %lu us adc0 %u\n", echo_us, adc_read(0));
    uart_print(0, line);
    delay_ms(60);
  }
}
