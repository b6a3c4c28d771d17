/* Lockstep probe with the default HAL-call cost: a busy-wait on the millisecond clock that must
 * end, then "HELLO" at 9600 baud on UART 1, whose TX is looped back to its RX, received through
 * the RX interrupt; and a global counter, so that two copies can show they do not share it. */
#include <hal/hal.h>
#include <stdio.h>

static volatile uint8_t received[8];
static volatile uint8_t received_count;
static uint16_t counter;

static void on_byte(uint8_t byte) {
  if (received_count < sizeof received) received[received_count++] = byte;
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  char line[48];
  const uint32_t until = millis() + 250;
  while (millis() < until) {
  }
  snprintf(line, sizeof line, "busy-wait ended at %lu us\n", (unsigned long)micros());
  uart_print(0, line);

  uart_begin(1, 9600);
  irq_attach_uart_rx(1, on_byte);
  uart_print(1, "HELLO");
  uart_flush(1);
  delay_ms(5);
  snprintf(line, sizeof line, "rx %u: %c%c%c%c%c\n", received_count, received[0], received[1], received[2],
           received[3], received[4]);
  uart_print(0, line);

  for (;;) {
    delay_ms(100);
    counter++;
    snprintf(line, sizeof line, "count %u\n", counter);
    uart_print(0, line);
  }
}
