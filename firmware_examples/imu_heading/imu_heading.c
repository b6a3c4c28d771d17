/* Heading from an MPU-6000's gyro: the IMU on SPI (chip select pin 53, ../lib/mpu6000_spi), its
 * data-ready interrupt on pin 63 (A9, pin change); each sample is read in one 14-byte burst and
 * the z rate, less a bias measured while standing still, is integrated into a heading. The rover's
 * turns come from the project's script, not from this firmware.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#include "../lib/mpu6000_spi.h"

#define CONSOLE 0
#define IMU_CS 53   /* SS, held HIGH between transfers */
#define IMU_INT 63  /* A9: PCINT17 */

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
static const struct mpu_settings settings = {SAMPLE_DIV, CONFIG_DLPF, GYRO_FS, ACCEL_FS};

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

/* Waits for the next data-ready and reads that sample; its time in *at_us. */
static struct mpu_sample next_sample(uint32_t *at_us) {
  while (!data_ready) delay_us(200);
  irq_disable(); /* four byte reads on the AVR: keep the handler out */
  *at_us = ready_us;
  data_ready = 0;
  irq_enable();
  return mpu_read_sample();
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
  mpu_select_pin(IMU_CS);
  pin_mode(IMU_INT, INPUT);
  uart_print(CONSOLE, "imu_heading: ready\r\n");
  delay_ms(100); /* start-up time of the gyro: 30 ms typical, and the supply's own rise */
  while (!mpu_begin(&settings, 0x00)) { /* 0x00: internal 8 MHz clock */
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
    const struct mpu_sample s = next_sample(&at_us);
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
