/* The MPU-6000 over SPI: see mpu6000_spi.h. Registers and figures: InvenSense "MPU-6000 and
 * MPU-6050 Register Map and Descriptions" rev 4.2 (numbers in hex below) and the product
 * specification rev 3.4: SPI mode 0 or 3, 1 MHz for all registers, 20 MHz for reading the sensor
 * and interrupt registers; bit 7 of the first byte set for a read; WHO_AM_I = 0x68; it wakes from
 * reset asleep. */
#include "mpu6000_spi.h"

#include <hal/hal.h>

#define REG_SMPLRT_DIV 0x19
#define REG_INT_PIN_CFG 0x37
#define REG_INT_ENABLE 0x38
#define REG_ACCEL_XOUT_H 0x3B /* ..0x48: accel X Y Z, temperature, gyro X Y Z, big-endian */
#define REG_USER_CTRL 0x6A
#define REG_PWR_MGMT_1 0x6B
#define REG_WHO_AM_I 0x75
#define READ 0x80

static uint8_t cs_pin;

void mpu_select_pin(uint8_t cs) {
  cs_pin = cs;
  pin_mode(cs, OUTPUT);
  digital_write(cs, HIGH);
}

static void imu_write(uint8_t reg, uint8_t value) {
  digital_write(cs_pin, LOW);
  spi_transfer(reg);
  spi_transfer(value);
  digital_write(cs_pin, HIGH);
}

/* n registers from reg on, in one burst with CS held low: the register address auto-increments. */
static void imu_read(uint8_t reg, uint8_t *out, uint8_t n) {
  digital_write(cs_pin, LOW);
  spi_transfer((uint8_t)(reg | READ));
  for (uint8_t i = 0; i < n; ++i) out[i] = spi_transfer(0x00);
  digital_write(cs_pin, HIGH);
}

static int16_t be16(const uint8_t *p) { return (int16_t)(((uint16_t)p[0] << 8) | p[1]); }

uint8_t mpu_begin(const struct mpu_settings *s, uint8_t clock_source) {
  uint8_t id;
  spi_begin(3, MPU_SLOW_SPI);
  imu_read(REG_WHO_AM_I, &id, 1);
  if (id != 0x68) return 0;
  imu_write(REG_PWR_MGMT_1, clock_source); /* SLEEP off */
  delay_ms(10);
  imu_write(REG_USER_CTRL, 0x10); /* I2C_IF_DIS: SPI only, as the register map asks for SPI */
  imu_write(REG_SMPLRT_DIV, s->sample_div);
  imu_write(REG_SMPLRT_DIV + 1u, s->dlpf);     /* CONFIG */
  imu_write(REG_SMPLRT_DIV + 2u, s->gyro_fs);  /* GYRO_CONFIG */
  imu_write(REG_SMPLRT_DIV + 3u, s->accel_fs); /* ACCEL_CONFIG */
  imu_write(REG_INT_PIN_CFG, 0x00); /* active high, push-pull, 50 us pulse */
  imu_write(REG_INT_ENABLE, 0x01);  /* DATA_RDY_EN */
  uint8_t check[4];
  imu_read(REG_SMPLRT_DIV, check, 4);
  spi_begin(3, MPU_FAST_SPI);
  return check[0] == s->sample_div && check[1] == s->dlpf && check[2] == s->gyro_fs && check[3] == s->accel_fs;
}

struct mpu_sample mpu_read_sample(void) {
  uint8_t raw[14];
  imu_read(REG_ACCEL_XOUT_H, raw, 14);
  struct mpu_sample s;
  s.ax = be16(raw);
  s.ay = be16(raw + 2);
  s.az = be16(raw + 4);
  s.temp = be16(raw + 6);
  s.gx = be16(raw + 8);
  s.gy = be16(raw + 10);
  s.gz = be16(raw + 12);
  return s;
}
