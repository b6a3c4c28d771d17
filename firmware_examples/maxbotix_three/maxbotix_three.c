/* MaxBotix LV-MaxSonar-EZ1 read three ways at once, printed side by side: its analog voltage on
 * ADC channel 2, its pulse width on pin 62 (A8) timed by a pin-change interrupt, and its serial
 * "R###<CR>" on UART2 (RX2, pin 17) through an inverter, since the sensor's TX is RS-232 polarity
 * at 0..Vcc levels. Figures from the LV-MaxSonar-EZ datasheet: AN = Vcc/512 per inch, PW = 147 us
 * per inch, serial 9600 8N1 with inches as three ASCII digits (max 255), a reading every 49 ms,
 * 6..254 in, and 250 ms after power-up before the first one. Its RX pin, held HIGH (or left open),
 * keeps it ranging continuously.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#define CONSOLE 0
#define MB_ADC 2     /* AN */
#define MB_PW_PIN 62 /* PW, pin A8: pin-change interrupt PCINT16 */
#define MB_UART 2    /* TX through an inverter to RX2 */
#define MB_RX_PIN 23 /* the sensor's RX: HIGH ranges continuously */

#define US_PER_INCH 147u
#define REPORT_MS 250u
#define STALE_MS 200u /* four missed 49 ms cycles: show "--" rather than an old value */

/* PW: HIGH for 147 us per inch once per cycle; both edges stamped here. */
static volatile uint32_t pw_rise_us, pw_width_us, pw_at_ms;
static volatile uint8_t pw_new;

static void on_pw(void) {
  const uint32_t now = micros();
  if (digital_read(MB_PW_PIN)) {
    pw_rise_us = now;
  } else {
    pw_width_us = now - pw_rise_us;
    pw_at_ms = millis();
    pw_new = 1;
  }
}

/* AN: Vcc/512 per inch, and the ADC gives 1024 codes over Vcc (AVCC reference): 2 codes per inch,
 * whatever the supply, as both scale with Vcc. */
static uint16_t analog_inches(void) { return (uint16_t)((adc_read(MB_ADC) + 1u) / 2u); }

/* Serial: 'R', three digits, CR. Anything else resets the parser, so a lost or corrupted byte
 * costs one reading and the next 'R' resynchronises. */
struct serial_parser {
  uint8_t digits; /* digits taken since 'R'; 0xFF while waiting for an 'R' */
  uint16_t value;
};

/* Feeds one byte; returns the reading in inches when a complete one ends here, else -1. */
static int16_t serial_feed(struct serial_parser *p, uint8_t byte) {
  if (byte == 'R') {
    p->digits = 0;
    p->value = 0;
  } else if (p->digits <= 2 && byte >= '0' && byte <= '9') {
    p->value = (uint16_t)(p->value * 10u + (uint16_t)(byte - '0'));
    p->digits++;
  } else if (p->digits == 3 && byte == '\r') {
    p->digits = 0xFF;
    return (int16_t)p->value;
  } else {
    p->digits = 0xFF;
  }
  return -1;
}

/* "39" or "--" */
static void show(char *out, uint8_t size, uint8_t valid, uint16_t inches) {
  if (valid) snprintf(out, size, "%u", inches);
  else snprintf(out, size, "--");
}

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  uart_begin(MB_UART, 9600);
  adc_reference(ADC_REF_AVCC);
  pin_mode(MB_RX_PIN, OUTPUT);
  digital_write(MB_RX_PIN, HIGH);
  pin_mode(MB_PW_PIN, INPUT);
  irq_attach_pin(MB_PW_PIN, IRQ_CHANGE, on_pw);
  uart_print(CONSOLE, "maxbotix_three: ready\r\n");
  delay_ms(300); /* 250 ms start-up, then the first 49 ms cycle */

  struct serial_parser parser = {0xFF, 0};
  uint16_t serial_in = 0, pw_in = 0;
  uint32_t serial_at = 0, pw_at = 0;
  uint8_t have_serial = 0, have_pw = 0;
  uint16_t bad_serial = 0;
  uint32_t next_report = millis();
  char line[80], a[6], p[6], s[6];
  for (;;) {
    int16_t byte;
    while ((byte = uart_read(MB_UART)) >= 0) {
      const int16_t inches = serial_feed(&parser, (uint8_t)byte);
      if (inches >= 0) {
        serial_in = (uint16_t)inches;
        serial_at = millis();
        have_serial = 1;
      } else if (parser.digits == 0xFF && byte != '\r') {
        bad_serial++;
      }
    }
    if (pw_new) {
      irq_disable(); /* four byte reads on the AVR: keep the handler out */
      const uint32_t width = pw_width_us, at = pw_at_ms;
      pw_new = 0;
      irq_enable();
      pw_in = (uint16_t)((width + US_PER_INCH / 2u) / US_PER_INCH);
      pw_at = at;
      have_pw = 1;
    }

    const uint32_t now = millis();
    if ((int32_t)(now - next_report) >= 0) {
      next_report += REPORT_MS;
      show(a, sizeof a, 1, analog_inches());
      show(p, sizeof p, have_pw && now - pw_at < STALE_MS, pw_in);
      show(s, sizeof s, have_serial && now - serial_at < STALE_MS, serial_in);
      snprintf(line, sizeof line, "analog %s in, pw %s in, serial %s in\r\n", a, p, s);
      uart_print(CONSOLE, line);
      if (bad_serial) {
        snprintf(line, sizeof line, "  %u stray serial bytes\r\n", bad_serial);
        uart_print(CONSOLE, line);
        bad_serial = 0;
      }
    }
    delay_ms(2);
  }
}
