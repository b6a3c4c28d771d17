/* MPU-6000/6050 model: an 8 kHz internal tick drives sampling, the digital low-pass filters, the
 * sample-rate divider, the FIFO and the INT pin; the bus side reads and writes a 128-byte map. */
#include "mpu6000.h"

#include <math.h>
#include <string.h>

#include "noise.h"

#define PI 3.14159265358979323846
#define DEG_TO_RAD (PI / 180.0)
#define STANDARD_GRAVITY 9.80665 /* m/s^2 per g, as the datasheet's LSB/g use it */
#define BASE_TICK_NS INT64_C(125000) /* 8 kHz, the fastest internal rate (RM 4.2) */
#define GARBAGE_STREAM UINT64_C(0x8CB92BA72F3D8DD7)

void mpu6000_default_config(struct mpu6000_config *c, enum mpu6000_variant variant) {
  memset(c, 0, sizeof *c);
  c->variant = variant;
  c->i2c_address = 0x68;
  c->product_id = variant == MPU6000_VARIANT_6000 ? MPU6000_REV_D8 : MPU6050_REV_D8;
  c->seed = 1;
  /* PS-MPU-6000A table 6.1 (gyroscope), FS_SEL = 0, 25 C:
   *  - rate noise spectral density 0.005 deg/s/sqrt(Hz) (and total RMS noise 0.05 deg/s at a
   *    100 Hz DLPF, which the one-sided reading of the density in imu_error.h reproduces);
   *  - initial ZRO tolerance +-20 deg/s, taken as 3 sd;
   *  - sensitivity scale factor tolerance +-3 % and cross-axis sensitivity +-2 %, taken as 3 sd.
   * The datasheet gives no bias instability or random walk: 0.001 deg/s/sqrt(s) (the bias
   * wanders ~0.06 deg/s in an hour, small beside the ZRO's +-0.24 deg/s per C drift over
   * temperature) is our assumption. */
  c->gyro.noise_density = 0.005 * DEG_TO_RAD;
  for (int i = 0; i < 3; ++i) c->gyro.turn_on_bias[i] = 20.0 / 3.0 * DEG_TO_RAD;
  c->gyro.bias_walk = 0.001 * DEG_TO_RAD;
  c->gyro.scale_error = 0.03 / 3.0;
  c->gyro.cross_axis = 0.02 / 3.0;
  /* Table 6.2 (accelerometer), AFS_SEL = 0: noise power spectral density 400 ug/sqrt(Hz);
   * initial zero-g output +-50 mg on X and Y, +-80 mg on Z, as 3 sd; initial calibration tolerance
   * +-3 % and cross-axis +-2 %, as 3 sd. Bias walk 0.0001 m/s^2/sqrt(s): our assumption again. */
  c->accel.noise_density = 400e-6 * STANDARD_GRAVITY;
  c->accel.turn_on_bias[0] = c->accel.turn_on_bias[1] = 0.050 / 3.0 * STANDARD_GRAVITY;
  c->accel.turn_on_bias[2] = 0.080 / 3.0 * STANDARD_GRAVITY;
  c->accel.bias_walk = 1e-4;
  c->accel.scale_error = 0.03 / 3.0;
  c->accel.cross_axis = 0.02 / 3.0;
  c->temperature_c = 25.0;
  /* Mid-range trim codes: responses of 45-50 deg/s and 0.57-0.61 g, as parts commonly read. */
  c->self_test_gyro_code[0] = 14;
  c->self_test_gyro_code[1] = 15;
  c->self_test_gyro_code[2] = 16;
  c->self_test_accel_code[0] = 16;
  c->self_test_accel_code[1] = 17;
  c->self_test_accel_code[2] = 18;
  c->self_test_error = 0.0;
}

/* ---- self-test ---- */

double mpu6000_gyro_trim_dps(uint8_t code, int axis) {
  if (code == 0) return 0.0;
  const double trim = 25.0 * pow(1.046, (double)code - 1.0);
  return axis == 1 ? -trim : trim;
}

double mpu6000_accel_trim_g(uint8_t code) {
  if (code == 0) return 0.0;
  return 0.34 * pow(0.92 / 0.34, ((double)code - 1.0) / 30.0);
}

/* SELF_TEST_X..A as the factory leaves them (RM 4.1's bit layout). */
static void load_trim(struct mpu6000 *s) {
  const uint8_t *g = s->cfg.self_test_gyro_code, *a = s->cfg.self_test_accel_code;
  for (int i = 0; i < 3; ++i)
    s->reg[MPU6000_SELF_TEST_X + i] = (uint8_t)(((a[i] >> 2) & 7u) << 5 | (g[i] & 0x1Fu));
  s->reg[MPU6000_SELF_TEST_A] = (uint8_t)((a[0] & 3u) << 4 | (a[1] & 3u) << 2 | (a[2] & 3u));
}

/* With an axis' ST bit set its proof mass is actuated: the output moves by the part's response,
 * the trim times (1 + self_test_error), on top of what it senses. */
static void add_self_test(const struct mpu6000 *s, double gyro_radps[3], double accel_mps2[3]) {
  const double k = 1.0 + s->cfg.self_test_error;
  for (int i = 0; i < 3; ++i) {
    const uint8_t bit = (uint8_t)(0x80u >> i);
    if (gyro_radps && (s->reg[MPU6000_GYRO_CONFIG] & bit))
      gyro_radps[i] += k * mpu6000_gyro_trim_dps(s->cfg.self_test_gyro_code[i], i) * DEG_TO_RAD;
    if (accel_mps2 && (s->reg[MPU6000_ACCEL_CONFIG] & bit))
      accel_mps2[i] += k * mpu6000_accel_trim_g(s->cfg.self_test_accel_code[i]) * STANDARD_GRAVITY;
  }
}

/* ---- digital low-pass filter ---- */

/* RM 4.3 (CONFIG) bandwidths in Hz for DLPF_CFG 0..6; 7 is "reserved" on the map and is run here
 * like 0. The part's filter structure is not published: a two-pole Butterworth with its -3 dB
 * point at the table's bandwidth matches the amplitude response the table states, not its delays
 * (for example 1.9 ms at 188 Hz against the Butterworth's 1.2 ms at DC). */
static const double gyro_bw_hz[8] = {256, 188, 98, 42, 20, 10, 5, 256};
static const double accel_bw_hz[8] = {260, 184, 94, 44, 21, 10, 5, 260};

static int dlpf_cfg(const struct mpu6000 *s) { return s->reg[MPU6000_CONFIG] & 7; }
static int gyro_fast(const struct mpu6000 *s) { return dlpf_cfg(s) == 0 || dlpf_cfg(s) == 7; }

static void biquad_design(struct mpu6000_biquad *f, double fc_hz, double fs_hz) {
  /* Bilinear transform with the cutoff pre-warped, so the -3 dB point lands at fc exactly. */
  const double k = tan(PI * fc_hz / fs_hz);
  const double norm = 1.0 / (1.0 + sqrt(2.0) * k + k * k);
  f->b0 = k * k * norm;
  f->b1 = 2.0 * f->b0;
  f->b2 = f->b0;
  f->a1 = 2.0 * (k * k - 1.0) * norm;
  f->a2 = (1.0 - sqrt(2.0) * k + k * k) * norm;
  f->primed = 0;
}

static void biquad_run(struct mpu6000_biquad *f, const double in[3], double out[3]) {
  for (int i = 0; i < 3; ++i) {
    if (!f->primed) {
      /* Start in steady state on the first input: the part's start-up settling is not modelled. */
      f->z1[i] = in[i] * (1.0 - f->b0);
      f->z2[i] = in[i] * (f->b2 - f->a2);
    }
    const double y = f->b0 * in[i] + f->z1[i];
    f->z1[i] = f->b1 * in[i] - f->a1 * y + f->z2[i];
    f->z2[i] = f->b2 * in[i] - f->a2 * y;
    out[i] = y;
  }
  f->primed = 1;
}

static void design_filters(struct mpu6000 *s) {
  const int cfg = dlpf_cfg(s);
  biquad_design(&s->gyro_lpf, gyro_bw_hz[cfg], gyro_fast(s) ? MPU6000_GYRO_RATE_FAST_HZ : MPU6000_GYRO_RATE_SLOW_HZ);
  biquad_design(&s->accel_lpf, accel_bw_hz[cfg], MPU6000_ACCEL_RATE_HZ);
  s->lpf_cfg = cfg;
}

/* ---- conversion to register codes ---- */

static double gyro_lsb_per_dps(const struct mpu6000 *s) {
  static const double lsb[4] = {131.0, 65.5, 32.8, 16.4}; /* RM 4.4 / PS table 6.1 */
  return lsb[(s->reg[MPU6000_GYRO_CONFIG] >> 3) & 3];
}

static double accel_lsb_per_g(const struct mpu6000 *s) {
  double lsb = 16384.0 / (double)(1 << ((s->reg[MPU6000_ACCEL_CONFIG] >> 3) & 3)); /* RM 4.5 */
  const int rev = s->cfg.product_id & 0x0F;
  if (s->cfg.variant == MPU6000_VARIANT_6000 && (rev == 4 || rev == 5)) lsb *= 2.0; /* rev C */
  return lsb;
}

static int16_t to_code(double v) {
  const double r = floor(v + 0.5);
  if (r > 32767.0) return 32767;
  if (r < -32768.0) return -32768;
  return (int16_t)r;
}

static void put_be(uint8_t *p, int16_t v) {
  const uint16_t u = (uint16_t)v;
  p[0] = (uint8_t)(u >> 8);
  p[1] = (uint8_t)(u & 0xFF);
}

/* ---- FIFO ---- */

static void fifo_clear(struct mpu6000 *s) {
  s->fifo_head = 0;
  s->fifo_count = 0;
}

static void fifo_push(struct mpu6000 *s, uint8_t b) {
  if (s->fifo_count == MPU6000_FIFO_BYTES) {
    /* RM 4.33: on overflow the oldest data is lost and the new data written. */
    s->fifo_head = (s->fifo_head + 1) % MPU6000_FIFO_BYTES;
    --s->fifo_count;
    s->reg[MPU6000_INT_STATUS] |= MPU6000_FIFO_OFLOW; /* RM 4.33: whether or not it is enabled */
  }
  s->fifo[(s->fifo_head + s->fifo_count) % MPU6000_FIFO_BYTES] = b;
  ++s->fifo_count;
}

static uint8_t fifo_pop(struct mpu6000 *s) {
  /* RM 4.33: reading an empty FIFO returns the last byte read until new data arrives. */
  if (s->fifo_count == 0) return s->fifo_last_read;
  s->fifo_last_read = s->fifo[s->fifo_head];
  s->fifo_head = (s->fifo_head + 1) % MPU6000_FIFO_BYTES;
  --s->fifo_count;
  return s->fifo_last_read;
}

/* ---- reset ---- */

static void reset_registers(struct mpu6000 *s) {
  memset(s->reg, 0, sizeof s->reg);
  s->reg[MPU6000_PWR_MGMT_1] = MPU6000_PWR_MGMT_1_RESET;
  s->reg[MPU6000_WHO_AM_I] = MPU6000_WHO_AM_I_VALUE;
  s->reg[MPU6000_PRODUCT_ID] = s->cfg.product_id;
  load_trim(s);
  memset(s->shown, 0, sizeof s->shown);
  memset(s->latest, 0, sizeof s->latest);
  fifo_clear(s);
  s->fifo_last_read = 0;
  s->div_count = 0;
  s->pulse_end_ns = INT64_MIN;
  design_filters(s);
}

void mpu6000_init(struct mpu6000 *s, const struct mpu6000_config *c, int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->cfg = *c;
  /* Distinct seeds for the two sensors of one part, from the part's seed. */
  imu_error_init(&s->gyro_err, &c->gyro, noise_hash64(c->seed, 1));
  imu_error_init(&s->accel_err, &c->accel, noise_hash64(c->seed, 2));
  s->power_on_ns = power_on_ns;
  s->now_ns = power_on_ns;
  reset_registers(s);
}

/* ---- sampling ---- */

static int asleep(const struct mpu6000 *s) { return (s->reg[MPU6000_PWR_MGMT_1] & MPU6000_SLEEP) != 0; }
static int64_t tick_time(const struct mpu6000 *s, uint64_t n) { return s->power_on_ns + (int64_t)n * BASE_TICK_NS; }

static void sample_tick(struct mpu6000 *s, int64_t t) {
  uint8_t *d = s->latest;
  const double a_lsb = accel_lsb_per_g(s), g_lsb = gyro_lsb_per_dps(s);
  for (int i = 0; i < 3; ++i) {
    put_be(d + 2 * i, to_code(s->accel_out[i] / STANDARD_GRAVITY * a_lsb));
    put_be(d + 8 + 2 * i, to_code(s->gyro_out[i] / DEG_TO_RAD * g_lsb));
  }
  /* RM 4.18: deg C = TEMP_OUT / 340 + 36.53. */
  if (!(s->reg[MPU6000_PWR_MGMT_1] & MPU6000_TEMP_DIS)) put_be(d + 6, to_code((s->cfg.temperature_c - 36.53) * 340.0));
  if (!s->bus_busy) memcpy(s->shown, s->latest, sizeof s->shown);
  ++s->last_tick_index;

  const uint8_t en = s->reg[MPU6000_FIFO_EN];
  if ((s->reg[MPU6000_USER_CTRL] & MPU6000_USER_FIFO_EN) && en) {
    /* RM 4.7 / 4.33: registers are written in order of register number, 59 up. */
    if (en & MPU6000_FIFO_EN_ACCEL)
      for (int i = 0; i < 6; ++i) fifo_push(s, d[i]);
    if (en & MPU6000_FIFO_EN_TEMP) fifo_push(s, d[6]), fifo_push(s, d[7]);
    for (int axis = 0; axis < 3; ++axis)
      if (en & (MPU6000_FIFO_EN_XG >> axis)) fifo_push(s, d[8 + 2 * axis]), fifo_push(s, d[9 + 2 * axis]);
  }
  if (s->reg[MPU6000_INT_ENABLE] & MPU6000_DATA_RDY) s->reg[MPU6000_INT_STATUS] |= MPU6000_DATA_RDY;
  if (s->reg[MPU6000_INT_STATUS] & s->reg[MPU6000_INT_ENABLE]) s->pulse_end_ns = t + MPU6000_INT_PULSE_NS;
}

static void process_tick(struct mpu6000 *s, uint64_t n) {
  if (s->lpf_cfg != dlpf_cfg(s)) design_filters(s);
  const int fast = gyro_fast(s);
  /* The accelerometer samples at 1 kHz, and once at the first tick after waking so that its
   * registers never show a stale zero beside a fresh gyro sample. */
  if (n % 8 == 0 || !s->accel_lpf.primed) {
    double a[3];
    imu_error_walk(&s->gyro_err, 1e-3);
    imu_error_walk(&s->accel_err, 1e-3);
    imu_error_apply(&s->accel_err, s->specific_force, MPU6000_ACCEL_RATE_HZ, n / 8, a);
    add_self_test(s, NULL, a);
    biquad_run(&s->accel_lpf, a, s->accel_out);
  }
  if (!fast && n % 8 != 0) return;
  double g[3];
  imu_error_apply(&s->gyro_err, s->rate, fast ? MPU6000_GYRO_RATE_FAST_HZ : MPU6000_GYRO_RATE_SLOW_HZ, n, g);
  add_self_test(s, g, NULL);
  biquad_run(&s->gyro_lpf, g, s->gyro_out);
  if (s->div_count == 0) sample_tick(s, tick_time(s, n));
  s->div_count = (s->div_count + 1) % (1u + s->reg[MPU6000_SMPLRT_DIV]);
}

void mpu6000_advance(struct mpu6000 *s, int64_t now_ns) {
  if (now_ns <= s->now_ns) return;
  if (asleep(s)) {
    /* Asleep nothing is sampled, filtered or walked: skip to the first tick after now. */
    s->base_tick = (uint64_t)((now_ns - s->power_on_ns) / BASE_TICK_NS) + 1u;
  } else {
    while (tick_time(s, s->base_tick) <= now_ns) process_tick(s, s->base_tick++);
  }
  s->now_ns = now_ns;
}

void mpu6000_set_truth(struct mpu6000 *s, int64_t t_ns, const double specific_force_mps2[3],
                       const double rate_radps[3]) {
  mpu6000_advance(s, t_ns - 1); /* a tick at t_ns itself samples the new truth */
  for (int i = 0; i < 3; ++i) {
    s->specific_force[i] = specific_force_mps2[i];
    s->rate[i] = rate_radps[i];
  }
}

int64_t mpu6000_sample_period_ns(const struct mpu6000 *s) {
  const int64_t gyro_ns = gyro_fast(s) ? BASE_TICK_NS : 8 * BASE_TICK_NS;
  return gyro_ns * (1 + s->reg[MPU6000_SMPLRT_DIV]);
}

/* ---- interrupt pin ---- */

static int int_active(const struct mpu6000 *s) {
  if (s->reg[MPU6000_INT_PIN_CFG] & MPU6000_LATCH_INT_EN)
    return (s->reg[MPU6000_INT_STATUS] & s->reg[MPU6000_INT_ENABLE]) != 0;
  return s->now_ns < s->pulse_end_ns;
}

int mpu6000_int_level(const struct mpu6000 *s) {
  const int active_low = (s->reg[MPU6000_INT_PIN_CFG] & MPU6000_INT_LEVEL_LOW) != 0;
  return int_active(s) ? !active_low : active_low;
}

int64_t mpu6000_next_event_ns(const struct mpu6000 *s) {
  const int latch = (s->reg[MPU6000_INT_PIN_CFG] & MPU6000_LATCH_INT_EN) != 0;
  if (!latch && s->now_ns < s->pulse_end_ns) return s->pulse_end_ns;
  if (asleep(s) || !(s->reg[MPU6000_INT_ENABLE] & (MPU6000_DATA_RDY | MPU6000_FIFO_OFLOW))) return INT64_MAX;
  if (latch && int_active(s)) return INT64_MAX; /* only a read clears it */
  /* The next sample-rate tick: the next gyro sample, then the divider's remaining count. */
  uint64_t n = s->base_tick;
  const int fast = gyro_fast(s);
  if (!fast) n = (n + 7u) / 8u * 8u;
  const unsigned period = 1u + s->reg[MPU6000_SMPLRT_DIV];
  const unsigned more = (period - s->div_count) % period;
  n += (uint64_t)more * (fast ? 1u : 8u);
  return tick_time(s, n);
}

/* ---- register semantics ---- */

static int read_only(uint8_t addr) {
  return addr == MPU6000_PRODUCT_ID || (addr >= MPU6000_INT_STATUS && addr <= 0x60) ||
         addr == MPU6000_FIFO_COUNTH || addr == MPU6000_FIFO_COUNTL || addr == MPU6000_WHO_AM_I;
}

uint8_t mpu6000_reg_read(struct mpu6000 *s, uint8_t addr) {
  addr &= 0x7F;
  uint8_t v;
  if (addr >= MPU6000_ACCEL_XOUT_H && addr < MPU6000_ACCEL_XOUT_H + 14) v = s->shown[addr - MPU6000_ACCEL_XOUT_H];
  else if (addr == MPU6000_FIFO_COUNTH) v = (uint8_t)(s->fifo_count >> 8);
  else if (addr == MPU6000_FIFO_COUNTL) v = (uint8_t)(s->fifo_count & 0xFF);
  else if (addr == MPU6000_FIFO_R_W) v = fifo_pop(s);
  else v = s->reg[addr];
  /* RM 4.16: INT_STATUS clears when read, or on any read with INT_RD_CLEAR. */
  if (addr == MPU6000_INT_STATUS || (s->reg[MPU6000_INT_PIN_CFG] & MPU6000_INT_RD_CLEAR)) s->reg[MPU6000_INT_STATUS] = 0;
  return v;
}

void mpu6000_reg_write(struct mpu6000 *s, uint8_t addr, uint8_t value) {
  addr &= 0x7F;
  if (read_only(addr)) return;
  switch (addr) {
    case MPU6000_PWR_MGMT_1:
      if (value & MPU6000_DEVICE_RESET) {
        reset_registers(s);
        return;
      }
      if (asleep(s) && !(value & MPU6000_SLEEP)) {
        /* Waking: sampling restarts at the next tick, filters from steady state. */
        s->base_tick = (uint64_t)((s->now_ns - s->power_on_ns) / BASE_TICK_NS) + 1u;
        s->gyro_lpf.primed = s->accel_lpf.primed = 0;
      }
      break;
    case MPU6000_USER_CTRL:
      if (value & MPU6000_USER_FIFO_RESET) fifo_clear(s);
      if (value & MPU6000_USER_SIG_COND_RESET) {
        memset(s->latest, 0, sizeof s->latest);
        memset(s->shown, 0, sizeof s->shown);
        s->gyro_lpf.primed = s->accel_lpf.primed = 0;
      }
      if (s->cfg.variant == MPU6000_VARIANT_6050) value &= (uint8_t)~MPU6000_USER_I2C_IF_DIS; /* "write as 0" */
      value &= (uint8_t)~(MPU6000_USER_FIFO_RESET | MPU6000_USER_SIG_COND_RESET | 0x02); /* self-clearing */
      break;
    case MPU6000_SIGNAL_PATH_RESET:
      if (value & 0x10) s->gyro_lpf.primed = 0;
      if (value & 0x08) s->accel_lpf.primed = 0;
      value = 0;
      break;
    case MPU6000_SMPLRT_DIV:
      s->div_count = 0;
      break;
    case MPU6000_FIFO_R_W:
      fifo_push(s, value);
      return;
    default:
      break;
  }
  s->reg[addr] = value;
}

/* ---- SPI framing ---- */

static int spi_fast_readable(uint8_t addr) {
  /* PS 6.5: 20 MHz "for reading sensor and interrupt registers": INT_STATUS, the data registers
   * (0x3A-0x60) and, as ArduPilot and Betaflight read it at their high clock, the FIFO. */
  return (addr >= MPU6000_INT_STATUS && addr <= 0x60) || (addr >= MPU6000_FIFO_COUNTH && addr <= MPU6000_FIFO_R_W);
}

static uint8_t garbage(struct mpu6000 *s) {
  return (uint8_t)(noise_hash64(s->cfg.seed ^ GARBAGE_STREAM, s->garbage_count++) & 0xFF);
}

void mpu6000_spi_select(struct mpu6000 *s, int selected, int64_t t_ns) {
  mpu6000_advance(s, t_ns);
  if (s->cfg.variant != MPU6000_VARIANT_6000) return;
  s->bus_busy = selected != 0;
  s->spi_bytes = 0;
  /* RM 4.17-4.20: the data registers hold one sample while the interface is busy. */
  if (!s->bus_busy) memcpy(s->shown, s->latest, sizeof s->shown);
}

uint8_t mpu6000_spi_transfer(struct mpu6000 *s, uint8_t mosi, uint32_t sck_hz, int64_t t_ns) {
  if (s->cfg.variant != MPU6000_VARIANT_6000 || !s->bus_busy) return 0xFF; /* MISO not driven */
  mpu6000_advance(s, t_ns);
  if (s->spi_bytes++ == 0) {
    s->spi_read = (mosi & 0x80) != 0;
    s->spi_addr = mosi & 0x7F;
    return 0x00;
  }
  const uint8_t addr = s->spi_addr;
  if (addr != MPU6000_FIFO_R_W) s->spi_addr = (uint8_t)((addr + 1) & 0x7F);
  const uint32_t limit = (s->spi_read && spi_fast_readable(addr)) ? MPU6000_SPI_SENSOR_READ_MAX_HZ : MPU6000_SPI_ALL_REGS_MAX_HZ;
  if (s->spi_read) {
    const uint8_t v = mpu6000_reg_read(s, addr); /* the part still sees the read */
    return sck_hz > limit ? garbage(s) : v;
  }
  if (sck_hz <= limit) mpu6000_reg_write(s, addr, mosi);
  return 0x00;
}

/* ---- I2C framing ---- */

static int i2c_enabled(const struct mpu6000 *s) {
  return !(s->cfg.variant == MPU6000_VARIANT_6000 && (s->reg[MPU6000_USER_CTRL] & MPU6000_USER_I2C_IF_DIS));
}

static uint8_t next_pointer(uint8_t addr) { return addr == MPU6000_FIFO_R_W ? addr : (uint8_t)((addr + 1) & 0x7F); }

int mpu6000_i2c_write(struct mpu6000 *s, const uint8_t *data, size_t n, int64_t t_ns) {
  mpu6000_advance(s, t_ns);
  if (!i2c_enabled(s)) return -1;
  if (n == 0) return 0;
  uint8_t p = data[0] & 0x7F;
  for (size_t i = 1; i < n; ++i) {
    mpu6000_reg_write(s, p, data[i]);
    p = next_pointer(p);
  }
  s->i2c_pointer = p;
  return 0;
}

int mpu6000_i2c_read(struct mpu6000 *s, uint8_t *data, size_t n, int64_t t_ns) {
  mpu6000_advance(s, t_ns);
  if (!i2c_enabled(s)) return -1;
  uint8_t p = s->i2c_pointer;
  for (size_t i = 0; i < n; ++i) {
    data[i] = mpu6000_reg_read(s, p);
    p = next_pointer(p);
  }
  s->i2c_pointer = p;
  return 0;
}

void mpu6000_latest_si(const struct mpu6000 *s, double accel_mps2[3], double gyro_radps[3]) {
  static const double gyro_lsb[4] = {131.0, 65.5, 32.8, 16.4};
  const double a_lsb = 16384.0 / (double)(1 << ((s->reg[MPU6000_ACCEL_CONFIG] >> 3) & 3));
  const double g_lsb = gyro_lsb[(s->reg[MPU6000_GYRO_CONFIG] >> 3) & 3];
  for (int i = 0; i < 3; ++i) {
    const int16_t a = (int16_t)(uint16_t)(s->latest[2 * i] << 8 | s->latest[2 * i + 1]);
    const int16_t g = (int16_t)(uint16_t)(s->latest[8 + 2 * i] << 8 | s->latest[8 + 2 * i + 1]);
    accel_mps2[i] = a / a_lsb * STANDARD_GRAVITY;
    gyro_radps[i] = g / g_lsb * DEG_TO_RAD;
  }
}
