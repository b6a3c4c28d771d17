/* Heading from an MPU-6000's gyro: the IMU on SPI (chip select pin 53), its data-ready interrupt
 * on pin 63 (A9, pin change); each sample is read in one 14-byte burst and the z rate, less a bias
 * measured while standing still, is integrated into a heading. The rover's turns come from the
 * project's script, not from this firmware.
 * Registers and figures: InvenSense "MPU-6000 and MPU-6050 Register Map and Descriptions" rev 4.2
 * (numbers in hex below) and the product specification rev 3.4: SPI mode 0 or 3, 1 MHz for all
 * registers, 20 MHz for reading the sensor and interrupt registers; bit 7 of the first byte set
 * for a read; WHO_AM_I = 0x68; it wakes from reset asleep.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#define CONSOLE 0
#define IMU_CS 53   /* SS, held HIGH between transfers */
#define IMU_INT 63  /* A9: PCINT17 */

#define REG_SMPLRT_DIV 0x19
#define REG_CONFIG 0x1A
#define REG_GYRO_CONFIG 0x1B
#define REG_ACCEL_CONFIG 0x1C
#define REG_INT_PIN_CFG 0x37
#define REG_INT_ENABLE 0x38
#define REG_ACCEL_XOUT_H 0x3B /* ..0x48: accel X Y Z, temperature, gyro X Y Z, big-endian */
#define REG_SIGNAL_PATH_RESET 0x68
#define REG_USER_CTRL 0x6A
#define REG_PWR_MGMT_1 0x6B
#define REG_WHO_AM_I 0x75
#define READ 0x80

#define SLOW_SPI 1000000uL  /* any register */
#define FAST_SPI 20000000uL /* sensor registers only; the AVR makes 8 MHz of it */

/* DLPF_CFG 3: 44 Hz gyro bandwidth and a 1 kHz gyro rate, divided by 1 + 9: 100 samples/s. */
#define CONFIG_DLPF 0x03
#define SAMPLE_DIV 9
#define SAMPLE_US 10000uL
/* FS_SEL 1: +-500 deg/s at 65.5 LSB per deg/s; AFS_SEL 1: +-4 g at 8192 LSB per g. */
#define GYRO_FS 0x08
#define GYRO_LSB_PER_DPS 65.5f
#define ACCEL_FS 0x08
#define ACCEL_LSB_PER_G 8192
#define BIAS_SAMPLES 200 /* 2 s standing still */

static void imu_write(uint8_t reg, uint8_t value) {
  digital_write(IMU_CS, LOW);
  spi_transfer(reg);
  spi_transfer(value);
  digital_write(IMU_CS, HIGH);
}

/* n registers from reg on, in one burst with CS held low: the register address auto-increments. */
static void imu_read(uint8_t reg, uint8_t *out, uint8_t n) {
  digital_write(IMU_CS, LOW);
  spi_transfer((uint8_t)(reg | READ));
  for (uint8_t i = 0; i < n; ++i) out[i] = spi_transfer(0x00);
  digital_write(IMU_CS, HIGH);
}

static int16_t be16(const uint8_t *p) { return (int16_t)(((uint16_t)p[0] << 8) | p[1]); }

static volatile uint8_t data_ready;
static volatile uint32_t ready_us;
static volatile uint16_t missed;

/* INT pulses HIGH for 50 us per sample: the rising edge is the sample. */
static void on_int(void) {
  if (!digital_read(IMU_INT)) return;
  if (data_ready) missed++;
  data_ready = 1;
  ready_us = micros();
}

static uint8_t imu_begin(void) {
  uint8_t id;
  spi_begin(3, SLOW_SPI);
  imu_read(REG_WHO_AM_I, &id, 1);
  if (id != 0x68) return 0;
  imu_write(REG_PWR_MGMT_1, 0x00); /* SLEEP off, internal 8 MHz clock */
  delay_ms(10);
  imu_write(REG_USER_CTRL, 0x10); /* I2C_IF_DIS: SPI only, as the register map asks for SPI */
  imu_write(REG_SMPLRT_DIV, SAMPLE_DIV);
  imu_write(REG_CONFIG, CONFIG_DLPF);
  imu_write(REG_GYRO_CONFIG, GYRO_FS);
  imu_write(REG_ACCEL_CONFIG, ACCEL_FS);
  imu_write(REG_INT_PIN_CFG, 0x00); /* active high, push-pull, 50 us pulse */
  imu_write(REG_INT_ENABLE, 0x01);  /* DATA_RDY_EN */
  uint8_t check[4];
  imu_read(REG_SMPLRT_DIV, check, 4);
  spi_begin(3, FAST_SPI);
  return check[0] == SAMPLE_DIV && check[1] == CONFIG_DLPF && check[2] == GYRO_FS && check[3] == ACCEL_FS;
}

struct sample {
  int16_t ax, ay, az, temp, gx, gy, gz;
};

static struct sample imu_sample(void) {
  uint8_t raw[14];
  imu_read(REG_ACCEL_XOUT_H, raw, 14);
  struct sample s;
  s.ax = be16(raw);
  s.ay = be16(raw + 2);
  s.az = be16(raw + 4);
  s.temp = be16(raw + 6);
  s.gx = be16(raw + 8);
  s.gy = be16(raw + 10);
  s.gz = be16(raw + 12);
  return s;
}

/* Waits for the next data-ready and reads that sample; its time in *at_us. */
static struct sample next_sample(uint32_t *at_us) {
  while (!data_ready) delay_us(200);
  irq_disable(); /* four byte reads on the AVR: keep the handler out */
  *at_us = ready_us;
  data_ready = 0;
  irq_enable();
  return imu_sample();
}

/* "-12.3" from tenths */
static void tenths(char *out, uint8_t size, int32_t value) {
  const uint32_t magnitude = (uint32_t)(value < 0 ? -value : value);
  snprintf(out, size, "%s%lu.%lu", value < 0 ? "-" : "", (unsigned long)(magnitude / 10u),
           (unsigned long)(magnitude % 10u));
}

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  pin_mode(IMU_CS, OUTPUT);
  digital_write(IMU_CS, HIGH);
  pin_mode(IMU_INT, INPUT);
  uart_print(CONSOLE, "imu_heading: ready\r\n");
  delay_ms(100); /* start-up time of the gyro: 30 ms typical, and the supply's own rise */
  while (!imu_begin()) {
    uart_print(CONSOLE, "imu: no MPU-6000 (WHO_AM_I is not 0x68) or its settings did not take\r\n");
    delay_ms(1000);
  }
  irq_attach_pin(IMU_INT, IRQ_CHANGE, on_int);

  /* The z gyro's zero-rate offset (up to +-20 deg/s on a part, the specification says) would
   * turn into a drift of that many degrees a second, so measure it while the rover stands. */
  uart_print(CONSOLE, "imu: hold still, measuring the gyro's bias\r\n");
  uint32_t at_us, last_us;
  next_sample(&last_us); /* the first sample after wake-up may predate the settings */
  int32_t sum = 0;
  for (uint16_t i = 0; i < BIAS_SAMPLES; ++i) sum += next_sample(&at_us).gz;
  const float bias = (float)sum / (float)BIAS_SAMPLES;
  last_us = at_us;
  char line[144], a[16], b[16], c[16];
  tenths(a, sizeof a, (int32_t)(bias * 10.0f / GYRO_LSB_PER_DPS));
  snprintf(line, sizeof line, "imu: gyro z bias %s deg/s\r\n", a);
  uart_print(CONSOLE, line);
  missed = 0;

  float heading = 0; /* degrees, counter-clockwise positive as the z axis points up */
  uint32_t samples = 0, next_report = millis();
  for (;;) {
    const struct sample s = next_sample(&at_us);
    /* Each sample stands for the interval since the one before; counting it from the interrupt
     * times also covers a sample missed while busy. */
    const float dt = (float)(at_us - last_us) * 1e-6f;
    last_us = at_us;
    heading += ((float)s.gz - bias) / GYRO_LSB_PER_DPS * dt;
    if (heading >= 180.0f) heading -= 360.0f;
    if (heading < -180.0f) heading += 360.0f;
    samples++;

    if ((int32_t)(millis() - next_report) >= 0) {
      next_report += 500;
      tenths(a, sizeof a, (int32_t)(heading * 10.0f));
      tenths(b, sizeof b, (int32_t)(((float)s.gz - bias) * 10.0f / GYRO_LSB_PER_DPS));
      /* Temperature: raw / 340 + 36.53 deg C (register map, TEMP_OUT) */
      tenths(c, sizeof c, (int32_t)((float)s.temp * 10.0f / 340.0f + 365.3f));
      snprintf(line, sizeof line, "heading %s deg, rate %s deg/s, az %ld mg, %s C, %lu samples, %u missed\r\n", a, b,
               (long)s.az * 1000L / ACCEL_LSB_PER_G, c, (unsigned long)samples, missed);
      uart_print(CONSOLE, line);
    }
  }
}
