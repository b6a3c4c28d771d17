/* Moves an LMS200 on UART1 from 9600 to 500000 baud and asks for its status at the new rate the
 * moment the mode change is answered, as host drivers do; prints what came back, so a test can
 * tell that the scanner listened at the new rate from the very end of its answer. */
#include <hal/hal.h>
#include <stdio.h>

static const uint8_t to_500k[] = {0x02, 0x00, 0x02, 0x00, 0x20, 0x48, 0x58, 0x08};
static const uint8_t status[] = {0x02, 0x00, 0x01, 0x00, 0x31, 0x15, 0x12};

static void send(const uint8_t *bytes, unsigned n) {
  for (unsigned i = 0; i < n; ++i) uart_write(1, bytes[i]);
}

/* Reads n bytes, or gives up after timeout_ms; returns how many came. */
static unsigned receive(uint8_t *out, unsigned n, uint32_t timeout_ms) {
  const uint32_t start = millis();
  unsigned got = 0;
  while (got < n && millis() - start < timeout_ms) {
    const int16_t b = uart_read(1);
    if (b >= 0) out[got++] = (uint8_t)b;
  }
  return got;
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  uart_begin(1, 9600);
  delay_ms(2500); /* the power-up telegram (power_up="2") comes and goes */
  while (uart_read(1) >= 0) {
  }
  send(to_500k, sizeof to_500k);
  uint8_t answer[10];
  const unsigned got = receive(answer, sizeof answer, 100);
  uart_begin(1, 500000);
  send(status, sizeof status);
  uint8_t ack = 0;
  const unsigned acked = receive(&ack, 1, 20);
  char line[80];
  snprintf(line, sizeof line, "mode change: %u bytes, first %02x; status at 500k: %s %02x\n", got, answer[0],
           acked ? "answered" : "silent", ack);
  uart_print(0, line);
  for (;;) delay_ms(100);
}
