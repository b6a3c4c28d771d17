/* InvenSense MPU-6000 (SPI and I2C) and MPU-6050 (I2C) 6-axis IMU: the register file of the
 * register map RM-MPU-6000A-00 rev 4.2 and the timing and errors of product specification
 * PS-MPU-6000A-00 rev 3.4, fed with specific force (m/s^2) and angular rate (rad/s) in the part's
 * own axes. Times are integer nanoseconds of simulated time; no world, no globals. */
#ifndef SEAR_DEVICES_MPU6000_H
#define SEAR_DEVICES_MPU6000_H

#include <stddef.h>
#include <stdint.h>

#include "imu_error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Register addresses (RM-MPU-6000A section 3, register map). PRODUCT_ID is not in the public map;
 * flight-controller drivers (Betaflight accgyro_mpu6000, ArduPilot, PX4) read it to tell silicon
 * revisions apart. */
enum {
  MPU6000_PRODUCT_ID = 0x0C,
  MPU6000_SELF_TEST_X = 0x0D, /* XA_TEST[4:2] in bits 7:5, XG_TEST[4:0] in bits 4:0 (RM 4.1) */
  MPU6000_SELF_TEST_Y = 0x0E,
  MPU6000_SELF_TEST_Z = 0x0F,
  MPU6000_SELF_TEST_A = 0x10, /* XA_TEST[1:0] bits 5:4, YA_TEST[1:0] 3:2, ZA_TEST[1:0] 1:0 */
  MPU6000_SMPLRT_DIV = 0x19,
  MPU6000_CONFIG = 0x1A,
  MPU6000_GYRO_CONFIG = 0x1B,
  MPU6000_ACCEL_CONFIG = 0x1C,
  MPU6000_FIFO_EN = 0x23,
  MPU6000_INT_PIN_CFG = 0x37,
  MPU6000_INT_ENABLE = 0x38,
  MPU6000_INT_STATUS = 0x3A,
  MPU6000_ACCEL_XOUT_H = 0x3B, /* 0x3B-0x40 accel, 0x41-0x42 temperature, 0x43-0x48 gyro */
  MPU6000_TEMP_OUT_H = 0x41,
  MPU6000_GYRO_XOUT_H = 0x43,
  MPU6000_SIGNAL_PATH_RESET = 0x68,
  MPU6000_USER_CTRL = 0x6A,
  MPU6000_PWR_MGMT_1 = 0x6B,
  MPU6000_PWR_MGMT_2 = 0x6C,
  MPU6000_FIFO_COUNTH = 0x72,
  MPU6000_FIFO_COUNTL = 0x73,
  MPU6000_FIFO_R_W = 0x74,
  MPU6000_WHO_AM_I = 0x75
};

/* Bits */
#define MPU6000_FIFO_EN_TEMP 0x80
#define MPU6000_FIFO_EN_XG 0x40
#define MPU6000_FIFO_EN_YG 0x20
#define MPU6000_FIFO_EN_ZG 0x10
#define MPU6000_FIFO_EN_ACCEL 0x08
#define MPU6000_INT_LEVEL_LOW 0x80    /* INT_PIN_CFG: pin active low */
#define MPU6000_LATCH_INT_EN 0x20     /* INT_PIN_CFG: held until cleared, else a 50 us pulse */
#define MPU6000_INT_RD_CLEAR 0x10     /* INT_PIN_CFG: any read clears INT_STATUS */
#define MPU6000_DATA_RDY 0x01         /* INT_ENABLE / INT_STATUS */
#define MPU6000_FIFO_OFLOW 0x10       /* INT_ENABLE / INT_STATUS */
#define MPU6000_XYZ_ST 0xE0            /* GYRO_CONFIG / ACCEL_CONFIG: X, Y, Z self-test (bits 7, 6, 5) */
#define MPU6000_USER_FIFO_EN 0x40
#define MPU6000_USER_I2C_IF_DIS 0x10
#define MPU6000_USER_FIFO_RESET 0x04
#define MPU6000_USER_SIG_COND_RESET 0x01
#define MPU6000_DEVICE_RESET 0x80     /* PWR_MGMT_1 */
#define MPU6000_SLEEP 0x40            /* PWR_MGMT_1 */
#define MPU6000_TEMP_DIS 0x08         /* PWR_MGMT_1 */

#define MPU6000_WHO_AM_I_VALUE 0x68   /* both parts, whatever AD0 is */
#define MPU6000_PWR_MGMT_1_RESET 0x40 /* asleep */
/* Revisions as drivers know them: high nibble 1 engineering sample, 5 production; low nibble the
 * revision, C4 = 4 ... D10 = 0xA. Rev C parts read accelerations at twice the map's sensitivity
 * (ArduPilot and PX4 program ACCEL_CONFIG differently for them), which this model reproduces. */
#define MPU6000_REV_C4 0x54
#define MPU6000_REV_C5 0x55
#define MPU6000_REV_D8 0x58
#define MPU6000_REV_D10 0x5A
/* PX4 lists this for the 6050, marked unverified; no InvenSense document gives one. */
#define MPU6050_REV_D8 0x28

#define MPU6000_FIFO_BYTES 1024               /* RM section 4.33 */
#define MPU6000_INT_PULSE_NS INT64_C(50000)   /* RM 4.15: a 50 us pulse when not latched */
#define MPU6000_SPI_ALL_REGS_MAX_HZ 1000000u  /* PS 6.5: 1 MHz for every register */
#define MPU6000_SPI_SENSOR_READ_MAX_HZ 20000000u /* PS 6.5: 20 MHz reading sensor/interrupt regs */
#define MPU6000_GYRO_RATE_FAST_HZ 8000        /* RM 4.2: DLPF_CFG 0 or 7 */
#define MPU6000_GYRO_RATE_SLOW_HZ 1000        /* DLPF_CFG 1..6 */
#define MPU6000_ACCEL_RATE_HZ 1000            /* RM 4.2: always 1 kHz */

enum mpu6000_variant { MPU6000_VARIANT_6000, MPU6000_VARIANT_6050 };

struct mpu6000_config {
  enum mpu6000_variant variant; /* the 6050 has no SPI */
  uint8_t i2c_address;          /* 0x68, or 0x69 with AD0 high */
  uint8_t product_id;           /* PRODUCT_ID's value */
  uint64_t seed;
  struct imu_error_figures gyro;   /* rad/s */
  struct imu_error_figures accel;  /* m/s^2 */
  double temperature_c;            /* die temperature reported at TEMP_OUT */
  /* Self-test (RM 4.1, PS 6.1/6.2): the factory trim codes the SELF_TEST registers hold, 1..31
   * (0: no trim), and how far this part's response is from the trim they encode, as a fraction:
   * 0 a healthy part; beyond +-0.14 (PS: "-14 to +14 % change from factory trim") it fails. */
  uint8_t self_test_gyro_code[3];
  uint8_t self_test_accel_code[3];
  double self_test_error;
};

/* Datasheet defaults (PS-MPU-6000A tables 6.1 and 6.2), see mpu6000.c for each figure's source. */
void mpu6000_default_config(struct mpu6000_config *c, enum mpu6000_variant variant);

/* Second-order low-pass filter state for one axis. */
struct mpu6000_biquad {
  double b0, b1, b2, a1, a2;
  double z1[3], z2[3];
  int primed;
};

struct mpu6000 {
  struct mpu6000_config cfg;
  struct imu_error gyro_err, accel_err;
  uint8_t reg[128];
  uint8_t shown[14];    /* what 0x3B-0x48 read: frozen while a bus transaction is open */
  uint8_t latest[14];   /* the newest sample, published when the bus goes idle */
  int bus_busy;
  int64_t power_on_ns;
  int64_t now_ns;
  uint64_t base_tick;   /* next 8 kHz tick to process, counted from power-on */
  unsigned div_count;   /* gyro samples since the last sample-rate tick */
  double specific_force[3], rate[3];
  double gyro_out[3], accel_out[3]; /* filtered, in SI, latest */
  struct mpu6000_biquad gyro_lpf, accel_lpf;
  int lpf_cfg;          /* the DLPF_CFG the filters were designed for, -1: none yet */
  uint8_t fifo[MPU6000_FIFO_BYTES];
  unsigned fifo_head, fifo_count;
  uint8_t fifo_last_read;
  int64_t pulse_end_ns; /* non-latched pin pulse */
  uint64_t last_tick_index; /* sample-rate ticks so far, for tests and tracing */
  /* SPI transaction state */
  int spi_bytes;        /* bytes exchanged since CS went low */
  int spi_read;
  uint8_t spi_addr;
  uint8_t i2c_pointer;  /* the I2C register pointer, kept between transactions */
  uint64_t garbage_count;
};

void mpu6000_init(struct mpu6000 *s, const struct mpu6000_config *c, int64_t power_on_ns);
/* The truth from t_ns on, held until the next call: the model first runs up to t_ns on the old. */
void mpu6000_set_truth(struct mpu6000 *s, int64_t t_ns, const double specific_force_mps2[3],
                       const double rate_radps[3]);
/* Runs internal sampling, filters, FIFO and interrupts for every 8 kHz tick up to now_ns. */
void mpu6000_advance(struct mpu6000 *s, int64_t now_ns);

/* SPI mode 0/3: a transaction is CS low .. CS high; the first byte is the address (bit 7 = read),
 * each later byte reads or writes the next register (FIFO_R_W does not advance). Clocked faster
 * than the part allows for that register, a read returns garbage and a write is lost. */
void mpu6000_spi_select(struct mpu6000 *s, int selected, int64_t t_ns);
uint8_t mpu6000_spi_transfer(struct mpu6000 *s, uint8_t mosi, uint32_t sck_hz, int64_t t_ns);

/* I2C: a write of n bytes (first = register pointer, the rest written from there on) and a read of
 * n bytes from the pointer. Returns 0 for ACK, -1 for NACK (an MPU-6000 with I2C_IF_DIS set). */
int mpu6000_i2c_write(struct mpu6000 *s, const uint8_t *data, size_t n, int64_t t_ns);
int mpu6000_i2c_read(struct mpu6000 *s, uint8_t *data, size_t n, int64_t t_ns);

/* INT_STATUS, as the register map (RM-MPU-6000A rev 4.2) gives it:
 *  - FIFO_OFLOW_INT is set on every overflow, enabled or not: 4.33 (FIFO_R_W) says "If the FIFO
 *    buffer has overflowed, the status bit FIFO_OFLOW_INT is automatically set to 1", with no
 *    condition; InvenSense's mpu_read_fifo relies on it (it enables only DATA_RDY, reads
 *    INT_STATUS when the FIFO is over half full, and resets the FIFO on an overflow).
 *  - DATA_RDY_INT is set only while DATA_RDY_EN is: 4.16 sets it "when a Data Ready interrupt is
 *    generated", and 4.15 has that interrupt enabled by DATA_RDY_EN ("enables the Data Ready
 *    interrupt, which occurs each time a write operation to all of the sensor registers has been
 *    completed"); no section sets it otherwise, unlike FIFO_OFLOW_INT's.
 *  Both clear when INT_STATUS is read (or on any read with INT_RD_CLEAR). The pin shows only the
 *  enabled ones; the motion and I2C-master sources are not modelled. The pin is push-pull logic;
 *  INT_OPEN is stored but not modelled.
 * The INT pin's logic level (1 high) as of the last advance, and the earliest time it may change
 * without a bus access (INT64_MAX: not before one); advancing there and asking again is safe. */
int mpu6000_int_level(const struct mpu6000 *s);
int64_t mpu6000_next_event_ns(const struct mpu6000 *s);

/* Register semantics without bus framing, for the runtime's tracing and for tests. */
uint8_t mpu6000_reg_read(struct mpu6000 *s, uint8_t addr);
void mpu6000_reg_write(struct mpu6000 *s, uint8_t addr, uint8_t value);
/* Sample-rate period in ns as configured: gyro output rate / (1 + SMPLRT_DIV). */
int64_t mpu6000_sample_period_ns(const struct mpu6000 *s);
/* The newest sample in the data registers (ACCEL_XOUT_H..GYRO_ZOUT_L) as a driver decodes it:
 * at the register map's sensitivity for the full scales ACCEL_CONFIG and GYRO_CONFIG hold (so a
 * revision C part's doubled acceleration shows as such), in m/s^2 and rad/s. */
void mpu6000_latest_si(const struct mpu6000 *s, double accel_mps2[3], double gyro_radps[3]);
/* The factory trim a self-test code encodes (RM 4.1), in the units drivers compare it in:
 * gyro 25 deg/s x 1.046^(code - 1), negative on Y; accel 0.34 g x (0.92 / 0.34)^((code - 1) / 30);
 * 0 for code 0. axis 0..2 = X..Z. */
double mpu6000_gyro_trim_dps(uint8_t code, int axis);
double mpu6000_accel_trim_g(uint8_t code);

#ifdef __cplusplus
}
#endif
#endif
