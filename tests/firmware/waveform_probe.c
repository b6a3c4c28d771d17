/* Drives what the VCD waveform shows, at times the waveform test knows (run with
 * hal_call_cycles="0", so that every call takes no time and each moment is a delay's end):
 * "AAB" at 9600 baud on UART 1 (looped back to its RX) from 0 s, pin 4 high at 1.5 ms (inside the
 * second byte's frame), PWM duties on pin 3 and servo pulses on pin 44 every 10 ms from 5 ms, and
 * a 64-byte burst at 500 kbaud on UART 2 at 60 ms. */
#include <hal/hal.h>

int main(void) {
  hal_init();
  uart_begin(1, 9600);
  pin_mode(4, OUTPUT);
  uart_print(1, "AAB"); /* two equal bytes in a row */

  delay_us(1500); /* 1.5 ms: a pin changes while the second byte's frame is on the line */
  digital_write(4, HIGH);
  delay_us(3500); /* 5 ms */
  pwm_write(3, 64);
  servo_write_us(44, 1500);
  delay_ms(10); /* 15 ms */
  pwm_write(3, 200);
  delay_ms(10); /* 25 ms */
  pwm_write(3, 0); /* a plain low level */
  servo_write_us(44, 2000);
  delay_ms(10); /* 35 ms */
  pwm_write(3, 128);
  delay_ms(10); /* 45 ms */
  digital_write(3, HIGH); /* ends the PWM: duty 255 */
  servo_write_us(44, 0);  /* pulses stop */
  delay_ms(10); /* 55 ms */
  pin_mode(3, INPUT);

  delay_ms(5); /* 60 ms */
  uart_begin(2, 500000);
  for (uint8_t i = 0; i < 64; ++i) uart_write(2, (uint8_t)(i / 2)); /* each value twice */

  for (;;) delay_ms(100);
}
