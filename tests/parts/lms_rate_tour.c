/* Takes an LMS200 on UART1 through every change between its four rates (9600, 19200, 38400,
 * 500000 baud), each way: at each step it asks for the new rate at the old one, switches its own
 * port the moment the answer's last byte is in, and asks for the status at the new rate at once,
 * as sicktoolbox does. Prints every byte it received, so a test can check them byte for byte. */
#include <hal/hal.h>
#include <stdio.h>

/* SICK's CRC-16 (telegram listing, "Formation of the CRC16 checksum"): generator 0x8005, each step
 * folds in the current byte (low) and the previous one (high). */
static uint16_t crc16(const uint8_t *p, unsigned n) {
  uint16_t crc = 0;
  uint8_t previous = 0;
  for (unsigned i = 0; i < n; ++i) {
    crc = (uint16_t)((crc & 0x8000u) ? ((crc & 0x7FFFu) << 1) ^ 0x8005u : (unsigned)crc << 1);
    crc ^= (uint16_t)(p[i] | (previous << 8));
    previous = p[i];
  }
  return crc;
}

/* A request: STX, address 0, length, the command and its data, CRC low byte first. */
static void request(const uint8_t *payload, unsigned n) {
  uint8_t t[8];
  t[0] = 0x02;
  t[1] = 0x00;
  t[2] = (uint8_t)n;
  t[3] = 0;
  for (unsigned i = 0; i < n; ++i) t[4 + i] = payload[i];
  const uint16_t crc = crc16(t, 4 + n);
  t[4 + n] = (uint8_t)(crc & 0xFF);
  t[5 + n] = (uint8_t)(crc >> 8);
  for (unsigned i = 0; i < 6 + n; ++i) uart_write(1, t[i]);
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

static void print_hex(const uint8_t *p, unsigned n) {
  char two[4];
  for (unsigned i = 0; i < n; ++i) {
    snprintf(two, sizeof two, "%02x", p[i]);
    uart_print(0, two);
  }
}

static uint8_t code_of(uint32_t baud) {
  switch (baud) {
    case 38400: return 0x40;
    case 19200: return 0x41;
    case 500000: return 0x48;
    default: return 0x42;
  }
}

int main(void) {
  /* Every ordered pair of the four rates once: an Euler circuit of the complete graph on them. */
  static const uint32_t tour[] = {9600,  19200, 9600,   38400, 9600,   500000, 19200,
                                  38400, 19200, 500000, 38400, 500000, 9600};
  hal_init();
  uart_begin(0, 115200);
  uart_begin(1, 9600);
  delay_ms(2500); /* the power-up telegram (power_up="2") comes and goes */
  while (uart_read(1) >= 0) {
  }
  for (unsigned step = 1; step < sizeof tour / sizeof tour[0]; ++step) {
    const uint8_t change[2] = {0x20, code_of(tour[step])};
    request(change, 2);
    uint8_t answer[10];
    const unsigned got = receive(answer, sizeof answer, 1000);
    uart_begin(1, tour[step]);
    const uint8_t status = 0x31;
    request(&status, 1);
    static uint8_t reply[161]; /* ACK and the 0xB1 telegram: 4 + 1 + 152 + 1 + 2 bytes */
    const unsigned n = receive(reply, sizeof reply, 1000);
    char head[48];
    snprintf(head, sizeof head, "%lu>%lu mode ", (unsigned long)tour[step - 1], (unsigned long)tour[step]);
    uart_print(0, head);
    print_hex(answer, got);
    uart_print(0, " status ");
    print_hex(reply, n);
    uart_print(0, "\n");
  }
  uart_print(0, "done\n");
  for (;;) delay_ms(100);
}
