/* QMC5883L: continuous measurements at the output data rate, saturating 16-bit little-endian
 * outputs, and status flags that any data read clears. */
#include "qmc5883l.h"

#include <math.h>
#include <string.h>

#include "noise.h"

#define GAUSS_PER_TESLA 1e4

void qmc5883l_default_config(struct qmc5883l_config *c) {
  memset(c, 0, sizeof *c);
  c->seed = 1;
  c->noise_sd_T = 2e-3 / GAUSS_PER_TESLA; /* "field resolution" 2 milligauss (table 2) */
  c->temperature_c = 25.0;
}

double qmc5883l_lsb_per_gauss(uint8_t control_1) {
  /* Table 2, sensitivity: 12000 LSB/G at RNG = 00 (+-2 G), 3000 LSB/G at 01 (+-8 G). Codes 10
   * and 11 are reserved; run as +-8 G. */
  return ((control_1 >> 4) & 3) == 0 ? 12000.0 : 3000.0;
}

static void reset(struct qmc5883l *s) {
  memset(s->reg, 0, sizeof s->reg);
  s->reg[0x0C] = 0x01; /* reserved, reads 1 */
  s->reg[QMC5883L_CHIP_ID] = QMC5883L_CHIP_ID_VALUE;
  s->pointer = 0;
  s->next_result_ns = INT64_MAX; /* standby after POR and soft reset */
}

void qmc5883l_init(struct qmc5883l *s, const struct qmc5883l_config *c, int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->cfg = *c;
  s->now_ns = power_on_ns;
  reset(s);
}

static int64_t period_ns(const struct qmc5883l *s) {
  static const int64_t hz[4] = {10, 50, 100, 200}; /* ODR, table 18 */
  return INT64_C(1000000000) / hz[(s->reg[QMC5883L_CONTROL_1] >> 2) & 3];
}

static void measure(struct qmc5883l *s) {
  const double lsb = qmc5883l_lsb_per_gauss(s->reg[QMC5883L_CONTROL_1]);
  uint8_t status = s->reg[QMC5883L_STATUS];
  /* DOR: the previous result was never read. */
  status = (uint8_t)((status & QMC5883L_DRDY) ? QMC5883L_DOR : 0);
  for (int i = 0; i < 3; ++i) {
    double g = (s->field_T[i] + s->cfg.hard_iron_T[i]) * GAUSS_PER_TESLA;
    if (s->cfg.noise_sd_T > 0.0)
      g += s->cfg.noise_sd_T * GAUSS_PER_TESLA * noise_gaussian(s->cfg.seed, 3u * s->sample_index + (uint64_t)i);
    double code = floor(g * lsb + 0.5);
    /* OVL: an axis beyond the 16-bit range saturates and flags the sample. */
    if (code > 32767.0) code = 32767.0, status |= QMC5883L_OVL;
    if (code < -32768.0) code = -32768.0, status |= QMC5883L_OVL;
    const uint16_t u = (uint16_t)(int16_t)code;
    s->reg[2 * i] = (uint8_t)(u & 0xFF);
    s->reg[2 * i + 1] = (uint8_t)(u >> 8);
  }
  ++s->sample_index;
  const double t = floor(s->cfg.temperature_c * QMC5883L_TEMP_LSB_PER_C + s->cfg.temp_offset_lsb + 0.5);
  const uint16_t tu = (uint16_t)(int16_t)t;
  s->reg[QMC5883L_TEMP_LSB] = (uint8_t)(tu & 0xFF);
  s->reg[QMC5883L_TEMP_LSB + 1] = (uint8_t)(tu >> 8);
  s->reg[QMC5883L_STATUS] = (uint8_t)(status | QMC5883L_DRDY);
}

void qmc5883l_advance(struct qmc5883l *s, int64_t now_ns) {
  while (s->next_result_ns <= now_ns) {
    measure(s);
    s->next_result_ns += period_ns(s);
  }
  if (now_ns > s->now_ns) s->now_ns = now_ns;
}

void qmc5883l_set_truth(struct qmc5883l *s, int64_t t_ns, const double field_T[3]) {
  qmc5883l_advance(s, t_ns - 1);
  for (int i = 0; i < 3; ++i) s->field_T[i] = field_T[i];
}

int64_t qmc5883l_next_event_ns(const struct qmc5883l *s) { return s->next_result_ns; }

static uint8_t next_pointer(const struct qmc5883l *s, uint8_t p) {
  /* With ROL_PNT the pointer rolls from 06H back to 00H, so one read can poll data and status. */
  if ((s->reg[QMC5883L_CONTROL_2] & QMC5883L_ROL_PNT) && p == QMC5883L_STATUS) return 0;
  return (uint8_t)(p + 1);
}

static void write_reg(struct qmc5883l *s, uint8_t p, uint8_t v) {
  if (p == QMC5883L_CONTROL_1) {
    s->reg[p] = v;
    /* MODE 01 continuous; 00 standby (10 and 11 are reserved: standby too). */
    s->next_result_ns = (v & 3) == 1 ? s->now_ns + period_ns(s) : INT64_MAX;
  } else if (p == QMC5883L_CONTROL_2) {
    if (v & QMC5883L_SOFT_RST) reset(s);
    else s->reg[p] = v;
  } else if (p == QMC5883L_SET_RESET) {
    s->reg[p] = v;
  }
}

static uint8_t read_reg(struct qmc5883l *s, uint8_t p) {
  if (p > QMC5883L_CHIP_ID) return 0;
  const uint8_t v = s->reg[p];
  /* DRDY and DOR are cleared by reading any data register (status register description). */
  if (p <= 5) s->reg[QMC5883L_STATUS] &= (uint8_t)~(QMC5883L_DRDY | QMC5883L_DOR);
  return v;
}

int qmc5883l_i2c_write(struct qmc5883l *s, const uint8_t *data, size_t n, int64_t t_ns) {
  qmc5883l_advance(s, t_ns);
  if (n == 0) return 0;
  uint8_t p = data[0];
  for (size_t i = 1; i < n; ++i) {
    write_reg(s, p, data[i]);
    p = next_pointer(s, p);
  }
  s->pointer = p;
  return 0;
}

int qmc5883l_i2c_read(struct qmc5883l *s, uint8_t *data, size_t n, int64_t t_ns) {
  qmc5883l_advance(s, t_ns);
  uint8_t p = s->pointer;
  for (size_t i = 0; i < n; ++i) {
    data[i] = read_reg(s, p);
    p = next_pointer(s, p);
  }
  s->pointer = p;
  return 0;
}

void qmc5883l_field_read_T(const struct qmc5883l *s, double field_T[3]) {
  const double lsb = qmc5883l_lsb_per_gauss(s->reg[QMC5883L_CONTROL_1]);
  for (int i = 0; i < 3; ++i) {
    const int16_t v = (int16_t)(uint16_t)(s->reg[2 * i] | s->reg[2 * i + 1] << 8);
    field_T[i] = v / lsb / GAUSS_PER_TESLA;
  }
}
