/* HMC5883L: measurements complete at set times and land in the data registers unless a partial
 * read holds them locked; the register pointer walks as the datasheet's "register access" says. */
#include "hmc5883l.h"

#include <math.h>
#include <string.h>

#include "noise.h"

#define GAUSS_PER_TESLA 1e4

void hmc5883l_default_config(struct hmc5883l_config *c) {
  memset(c, 0, sizeof *c);
  c->seed = 1;
  c->noise_sd_T = 2e-3 / GAUSS_PER_TESLA;
}

double hmc5883l_lsb_per_gauss(int gain_code) {
  /* Table 9 (configuration register B): digital resolution per gain setting. */
  static const double lsb[8] = {1370, 1090, 820, 660, 440, 390, 330, 230};
  return lsb[gain_code & 7];
}

static int64_t output_period_ns(const struct hmc5883l *s) {
  /* Table 5: 0.75, 1.5, 3, 7.5, 15 (default), 30, 75 Hz; code 7 is reserved, run at 75 Hz. */
  static const double hz[8] = {0.75, 1.5, 3, 7.5, 15, 30, 75, 75};
  return (int64_t)(1e9 / hz[(s->reg[HMC5883L_CONFIG_A] >> 2) & 7] + 0.5);
}

static void reset(struct hmc5883l *s) {
  memset(s->reg, 0, sizeof s->reg);
  /* Table 2 defaults: CRA 0x10 (1 sample, 15 Hz, normal), CRB 0x20 (gain 1, 1090 LSB/G), MR 0x01. */
  s->reg[HMC5883L_CONFIG_A] = 0x10;
  s->reg[HMC5883L_CONFIG_B] = 0x20;
  s->reg[HMC5883L_MODE] = 0x01;
  s->reg[HMC5883L_ID_A] = 'H';
  s->reg[HMC5883L_ID_A + 1] = '4';
  s->reg[HMC5883L_ID_A + 2] = '3';
  s->pointer = 0;
  s->result_ns = INT64_MAX;
  s->continuous = 0;
  s->gain_in_use = 1;
  s->read_mask = 0;
  s->locked = 0;
}

void hmc5883l_init(struct hmc5883l *s, const struct hmc5883l_config *c, int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->cfg = *c;
  s->now_ns = power_on_ns;
  s->drdy_low_until_ns = INT64_MIN;
  /* MR reads single-measurement mode at power-on; we take no measurement until it is written. */
  reset(s);
}

static void put_axis(uint8_t *p, double gauss, double lsb) {
  const double code = floor(gauss * lsb + 0.5);
  /* Output range 0xF800-0x07FF (-2048..2047); beyond, the channel reads -4096. */
  const int16_t v = (code < -2048.0 || code > 2047.0) ? (int16_t)HMC5883L_OVERFLOW_CODE : (int16_t)code;
  p[0] = (uint8_t)((uint16_t)v >> 8);
  p[1] = (uint8_t)((uint16_t)v & 0xFF);
}

static void complete_measurement(struct hmc5883l *s) {
  const uint8_t cra = s->reg[HMC5883L_CONFIG_A];
  const int samples = 1 << ((cra >> 5) & 3);
  const double sd = s->cfg.noise_sd_T / sqrt((double)samples);
  /* Self-test bias fields (section "Self Test"): +1.16 Oe on X and Y, +1.08 Oe on Z. */
  static const double bias_G[3] = {1.16, 1.16, 1.08};
  const int ms = cra & 3;
  double g[3];
  for (int i = 0; i < 3; ++i) {
    g[i] = (s->field_T[i] + s->cfg.hard_iron_T[i]) * GAUSS_PER_TESLA;
    if (sd > 0.0) g[i] += sd * GAUSS_PER_TESLA * noise_gaussian(s->cfg.seed, 3u * s->sample_index + (uint64_t)i);
    if (ms == 1) g[i] += bias_G[i];
    if (ms == 2) g[i] -= bias_G[i];
  }
  ++s->sample_index;
  const double lsb = hmc5883l_lsb_per_gauss(s->gain_in_use);
  s->gain_in_use = s->reg[HMC5883L_CONFIG_B] >> 5;
  /* LOCK: after a partial read new data is not placed until all six bytes are read. */
  if (s->locked) return;
  put_axis(&s->reg[3], g[0], lsb);
  put_axis(&s->reg[5], g[2], lsb);
  put_axis(&s->reg[7], g[1], lsb);
  s->reg[HMC5883L_STATUS] |= HMC5883L_RDY;
  s->read_mask = 0;
  s->drdy_low_until_ns = s->result_ns + HMC5883L_DRDY_LOW_NS;
}

void hmc5883l_advance(struct hmc5883l *s, int64_t now_ns) {
  while (s->result_ns <= now_ns) {
    complete_measurement(s);
    if (s->continuous) {
      s->result_ns += output_period_ns(s);
    } else {
      /* Single measurement done: back to idle, MR7 set internally (table 14). */
      s->reg[HMC5883L_MODE] = 0x83;
      s->result_ns = INT64_MAX;
    }
  }
  if (now_ns > s->now_ns) s->now_ns = now_ns;
}

void hmc5883l_set_truth(struct hmc5883l *s, int64_t t_ns, const double field_T[3]) {
  hmc5883l_advance(s, t_ns - 1);
  for (int i = 0; i < 3; ++i) s->field_T[i] = field_T[i];
}

int hmc5883l_drdy_level(const struct hmc5883l *s) { return s->now_ns >= s->drdy_low_until_ns; }

int64_t hmc5883l_next_event_ns(const struct hmc5883l *s) {
  if (s->now_ns < s->drdy_low_until_ns && s->drdy_low_until_ns < s->result_ns) return s->drdy_low_until_ns;
  return s->result_ns;
}

static uint8_t next_pointer(uint8_t p) {
  /* "Register access": past 12 the pointer goes to 0, and after 8 it rolls back to 3 so the
   * six data bytes can be read again and again. */
  if (p >= 12) return 0;
  if (p == 8) return 3;
  return (uint8_t)(p + 1);
}

static void unlock(struct hmc5883l *s) {
  s->locked = 0;
  s->read_mask = 0;
  s->reg[HMC5883L_STATUS] &= (uint8_t)~HMC5883L_LOCK;
}

static void write_reg(struct hmc5883l *s, uint8_t p, uint8_t v) {
  if (p > HMC5883L_MODE) return; /* read-only */
  s->reg[p] = v;
  if (p == HMC5883L_CONFIG_A) unlock(s);
  if (p == HMC5883L_MODE) {
    unlock(s);
    s->reg[p] = v & 0x83;
    switch (v & 3) {
      case 0:
        s->continuous = 1;
        s->result_ns = s->now_ns + HMC5883L_SINGLE_MEASUREMENT_NS;
        break;
      case 1:
        s->continuous = 0;
        s->result_ns = s->now_ns + HMC5883L_SINGLE_MEASUREMENT_NS;
        break;
      default:
        s->continuous = 0;
        s->result_ns = INT64_MAX;
        break;
    }
  }
}

static uint8_t read_reg(struct hmc5883l *s, uint8_t p) {
  if (p > 12) return 0;
  const uint8_t v = s->reg[p];
  if (p >= 3 && p <= 8) {
    s->read_mask |= (uint8_t)(1u << (p - 3));
    if (s->read_mask == 0x3F) {
      /* All six read: unlocked, and RDY drops until the next result (our reading of the
       * status register's description, as firmware polling RDY expects). */
      unlock(s);
      s->reg[HMC5883L_STATUS] &= (uint8_t)~HMC5883L_RDY;
    } else {
      s->locked = 1;
      s->reg[HMC5883L_STATUS] |= HMC5883L_LOCK;
    }
  } else if (p == HMC5883L_MODE) {
    s->locked = 1; /* table 16: reading the mode register also locks the outputs */
    s->reg[HMC5883L_STATUS] |= HMC5883L_LOCK;
  }
  return p == HMC5883L_STATUS ? s->reg[p] : v;
}

int hmc5883l_i2c_write(struct hmc5883l *s, const uint8_t *data, size_t n, int64_t t_ns) {
  hmc5883l_advance(s, t_ns);
  if (n == 0) return 0;
  uint8_t p = data[0];
  for (size_t i = 1; i < n; ++i) {
    write_reg(s, p, data[i]);
    p = next_pointer(p);
  }
  s->pointer = p;
  return 0;
}

int hmc5883l_i2c_read(struct hmc5883l *s, uint8_t *data, size_t n, int64_t t_ns) {
  hmc5883l_advance(s, t_ns);
  uint8_t p = s->pointer;
  for (size_t i = 0; i < n; ++i) {
    data[i] = read_reg(s, p);
    p = next_pointer(p);
  }
  s->pointer = p;
  return 0;
}

void hmc5883l_field_read_T(const struct hmc5883l *s, double field_T[3]) {
  const double lsb = hmc5883l_lsb_per_gauss(s->reg[HMC5883L_CONFIG_B] >> 5);
  static const int at[3] = {3, 7, 5}; /* X, Y, Z: the registers go X, Z, Y */
  for (int i = 0; i < 3; ++i) {
    const int16_t v = (int16_t)(uint16_t)(s->reg[at[i]] << 8 | s->reg[at[i] + 1]);
    field_T[i] = v / lsb / GAUSS_PER_TESLA;
  }
}
