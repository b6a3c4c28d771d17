/* The MPU-6000's gyro self-test on the X axis as InvenSense's driver runs it, over SPI (chip select
 * 53): at +-250 deg/s and a 44 Hz filter, the mean of 50 readings 1 ms apart with the self-test
 * off and again with XG_ST on, each after 50 ms to settle, and the factory trim code in
 * SELF_TEST_X; prints the response (the difference, in LSB) and the code. */
#include <hal/hal.h>
#include <stdio.h>

#define CS 53

static void write_register(uint8_t reg, uint8_t value) {
  digital_write(CS, LOW);
  spi_transfer(reg);
  spi_transfer(value);
  digital_write(CS, HIGH);
}

static uint8_t read_register(uint8_t reg) {
  digital_write(CS, LOW);
  spi_transfer((uint8_t)(reg | 0x80));
  const uint8_t value = spi_transfer(0);
  digital_write(CS, HIGH);
  return value;
}

static long mean_gyro_x(void) {
  long sum = 0;
  for (int i = 0; i < 50; ++i) {
    delay_ms(1);
    sum += (int16_t)((uint16_t)read_register(0x43) << 8 | read_register(0x44)); /* GYRO_XOUT */
  }
  return sum / 50;
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(CS, OUTPUT);
  digital_write(CS, HIGH);
  spi_begin(3, 1000000);
  write_register(0x6B, 0x01); /* PWR_MGMT_1: awake, gyro X clock */
  delay_ms(10);
  write_register(0x6A, 0x10); /* USER_CTRL: SPI only */
  write_register(0x19, 0x00); /* SMPLRT_DIV: 1 kHz */
  write_register(0x1A, 0x03); /* CONFIG: DLPF 44 Hz */
  write_register(0x1B, 0x00); /* GYRO_CONFIG: +-250 deg/s, self-test off */
  delay_ms(50);
  const long off = mean_gyro_x();
  write_register(0x1B, 0xE0); /* XG_ST, YG_ST, ZG_ST */
  delay_ms(50);
  const long on = mean_gyro_x();
  char line[64];
  snprintf(line, sizeof line, "self-test x %ld lsb, code %u\n", on - off, (unsigned)(read_register(0x0D) & 0x1F));
  uart_print(0, line);
  for (;;) delay_ms(100);
}
