/* Reads the position sensors the way their datasheets say and prints the raw numbers every
 * 100 ms, for the tests to hold against the run's trace: the HMC5883L's X, Z, Y (gain 1090 LSB/G,
 * single measurements), the MPU-6000's accelerometer and gyro (+-2 g, +-250 deg/s, burst read over
 * SPI), and the quadrature counts of both wheels (every edge, pin-change interrupts). */
#include <hal/hal.h>
#include <stdio.h>

#define MPU_CS 53
#define ENC_LA 64
#define ENC_LB 65
#define ENC_RA 66
#define ENC_RB 67

static volatile long count_left, count_right;
static volatile uint8_t last_left, last_right;

/* Gray-code step: +1 one way, -1 the other, 0 for no change. */
static int step(uint8_t from, uint8_t to) {
  static const signed char table[16] = {0, 1, -1, 0, -1, 0, 0, 1, 1, 0, 0, -1, 0, -1, 1, 0};
  return table[(from << 2) | to];
}

static void on_left(void) {
  const uint8_t now = (uint8_t)(digital_read(ENC_LA) | (digital_read(ENC_LB) << 1));
  count_left += step(last_left, now);
  last_left = now;
}

static void on_right(void) {
  const uint8_t now = (uint8_t)(digital_read(ENC_RA) | (digital_read(ENC_RB) << 1));
  count_right += step(last_right, now);
  last_right = now;
}

static void mpu_write(uint8_t reg, uint8_t value) {
  spi_begin(3, 1000000);
  digital_write(MPU_CS, LOW);
  spi_transfer(reg);
  spi_transfer(value);
  digital_write(MPU_CS, HIGH);
}

static void mpu_burst(int16_t out[7]) {
  spi_begin(3, 20000000);
  digital_write(MPU_CS, LOW);
  spi_transfer(0x3B | 0x80);
  for (int i = 0; i < 7; ++i) {
    const uint8_t hi = spi_transfer(0);
    out[i] = (int16_t)((hi << 8) | spi_transfer(0));
  }
  digital_write(MPU_CS, HIGH);
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(MPU_CS, OUTPUT);
  digital_write(MPU_CS, HIGH);
  mpu_write(0x6B, 0x01); /* awake, gyro PLL clock */
  mpu_write(0x1A, 0x03); /* DLPF 44 Hz */
  i2c_begin(400000);
  i2c_write_reg(0x1E, 0x00, 0x10); /* one sample per measurement, 15 Hz */
  i2c_write_reg(0x1E, 0x01, 0x20); /* gain 1090 LSB/G */
  for (uint8_t pin = ENC_LA; pin <= ENC_RB; ++pin) pin_mode(pin, INPUT);
  last_left = (uint8_t)(digital_read(ENC_LA) | (digital_read(ENC_LB) << 1));
  last_right = (uint8_t)(digital_read(ENC_RA) | (digital_read(ENC_RB) << 1));
  irq_attach_pin(ENC_LA, IRQ_CHANGE, on_left);
  irq_attach_pin(ENC_LB, IRQ_CHANGE, on_left);
  irq_attach_pin(ENC_RA, IRQ_CHANGE, on_right);
  irq_attach_pin(ENC_RB, IRQ_CHANGE, on_right);
  char line[128];
  for (uint32_t t = 100;; t += 100) {
    i2c_write_reg(0x1E, 0x02, 0x01); /* single measurement, ready within 6 ms */
    while (millis() < t) delay_ms(1);
    uint8_t m[6];
    i2c_read_regs(0x1E, 0x03, m, 6);
    int16_t imu[7];
    mpu_burst(imu);
    irq_disable();
    const long left = count_left, right = count_right;
    irq_enable();
    snprintf(line, sizeof line, "%lu mag %d %d %d imu %d %d %d %d %d %d enc %ld %ld\n", (unsigned long)t,
             (int16_t)((m[0] << 8) | m[1]), (int16_t)((m[2] << 8) | m[3]), (int16_t)((m[4] << 8) | m[5]), imu[0], imu[1],
             imu[2], imu[4], imu[5], imu[6], left, right);
    uart_print(0, line);
  }
}
