/* Exercises what the HAL gained for the Arduino layer (issue 19), printing what it measured on
 * the console for hal_additions_test.cpp: pulse_in against a MaxBotix's PW pin, I2C write-then-read
 * against an HMC5883L, the UART's transmit space, the 2.56 V reference, a level interrupt, servo
 * pulses on a pin without a timer channel, and the EEPROM. */
#include <hal/hal.h>
#include <stdio.h>

#define PW_PIN 62   /* the MaxBotix's pulse-width output (A8) */
#define AN_CHANNEL 2
#define COMPASS 0x1E
#define LEVEL_PIN 2 /* INT4 */

static char line[96];

static void say(void) { uart_print(0, line); }

static volatile unsigned level_rounds;

/* Clears its own cause after five rounds, as a driver reading a device's status would. */
static void on_low(void) {
  if (++level_rounds == 5) digital_write(LEVEL_PIN, HIGH);
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);

  /* The UART's transmit space: idle, then just after 10 bytes at 9600 baud (two go straight to
   * the shift and data registers), then after they have left. */
  uart_begin(1, 9600);
  const unsigned idle = uart_tx_space(1);
  for (int i = 0; i < 10; ++i) uart_write(1, 'U');
  const unsigned busy = uart_tx_space(1);
  uart_flush(1);
  snprintf(line, sizeof line, "tx space %u %u %u\n", idle, busy, (unsigned)uart_tx_space(1));
  say();

  /* I2C: the compass's identification registers by a write-then-read, by a write without stop
   * and a read, and an address nobody answers. */
  i2c_begin(400000);
  uint8_t reg = 0x0A, id[3] = {0, 0, 0}, id2[3] = {0, 0, 0};
  const int8_t wr = i2c_write_read(COMPASS, &reg, 1, id, 3);
  const int8_t ns = i2c_write_nostop(COMPASS, &reg, 1);
  const int8_t rd = i2c_read(COMPASS, id2, 3);
  const int8_t absent = i2c_write_read(0x50, &reg, 1, id, 3);
  snprintf(line, sizeof line, "i2c %d %c%c%c %d %d %c%c%c %d\n", wr, id[0], id[1], id[2], ns, rd, id2[0], id2[1], id2[2],
           absent);
  say();

  /* A level interrupt on a pin the firmware itself holds LOW: due at once, and again after each
   * round until the handler lets the pin go HIGH. */
  pin_mode(LEVEL_PIN, OUTPUT);
  digital_write(LEVEL_PIN, LOW);
  irq_attach_pin(LEVEL_PIN, IRQ_LOW, on_low);
  snprintf(line, sizeof line, "level rounds %u\n", level_rounds);
  say();

  /* Servo pulses on pin 30, which no timer reaches. */
  servo_write_us(30, 1500);

  /* EEPROM: a boot counter in byte 0 (erased 0xFF counts as none), then four writes in a row and
   * a read, timed: each write waits for the one before it to finish programming. */
  const uint8_t boots = eeprom_read(0);
  eeprom_write(0, (uint8_t)(boots == 0xFF ? 1 : boots + 1));
  const uint32_t t0 = micros();
  for (uint16_t a = 100; a < 104; ++a) eeprom_write(a, (uint8_t)a);
  const uint8_t back = eeprom_read(103);
  const uint32_t t1 = micros();
  snprintf(line, sizeof line, "eeprom boots %u erased %u back %u us %lu\n", boots == 0xFF ? 1u : boots + 1u,
           (unsigned)eeprom_read(4000), (unsigned)back, (unsigned long)(t1 - t0));
  say();

  delay_ms(600); /* the MaxBotix's 250 ms start-up and first cycles */
  for (int i = 0; i < 5; ++i) {
    adc_reference(ADC_REF_AVCC);
    const unsigned avcc = adc_read(AN_CHANNEL);
    adc_reference(ADC_REF_2V56);
    const unsigned r256 = adc_read(AN_CHANNEL);
    const uint32_t pw = pulse_in(PW_PIN, HIGH, 100000);
    const uint32_t none = pulse_in(PW_PIN, HIGH, 100); /* far shorter than a cycle */
    snprintf(line, sizeof line, "pw %lu us timeout %lu adc %u %u\n", (unsigned long)pw, (unsigned long)none, avcc, r256);
    say();
  }
  for (;;) delay_ms(100);
}
