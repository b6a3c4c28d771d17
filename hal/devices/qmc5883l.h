/* QST QMC5883L 3-axis magnetometer on I2C (address 0x0D), the part most "HMC5883L" boards now
 * carry: its register file, ranges, output rates and status flags per the QMC5883L datasheet
 * (rev 1.0), fed with the field in tesla along the part's own axes. Times in integer ns. */
#ifndef SEAR_DEVICES_QMC5883L_H
#define SEAR_DEVICES_QMC5883L_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define QMC5883L_I2C_ADDRESS 0x0D
enum {
  QMC5883L_DATA_X_LSB = 0x00, /* X, Y, Z, each LSB first, to 0x05 */
  QMC5883L_STATUS = 0x06,     /* DRDY 0x01, OVL 0x02, DOR 0x04 */
  QMC5883L_TEMP_LSB = 0x07,
  QMC5883L_CONTROL_1 = 0x09,  /* OSR 7:6, RNG 5:4, ODR 3:2, MODE 1:0 */
  QMC5883L_CONTROL_2 = 0x0A,  /* SOFT_RST 0x80, ROL_PNT 0x40, INT_ENB 0x01 */
  QMC5883L_SET_RESET = 0x0B,  /* SET/RESET period, 0x01 recommended */
  QMC5883L_CHIP_ID = 0x0D     /* reads 0xFF */
};
#define QMC5883L_DRDY 0x01
#define QMC5883L_OVL 0x02
#define QMC5883L_DOR 0x04
#define QMC5883L_SOFT_RST 0x80
#define QMC5883L_ROL_PNT 0x40
#define QMC5883L_CHIP_ID_VALUE 0xFF
#define QMC5883L_TEMP_LSB_PER_C 100.0 /* "about 100 LSB/C"; offset uncompensated */

struct qmc5883l_config {
  uint64_t seed;
  double noise_sd_T;
  double hard_iron_T[3];
  double temperature_c;
  double temp_offset_lsb; /* the part's own, uncalibrated */
};

void qmc5883l_default_config(struct qmc5883l_config *c);

struct qmc5883l {
  struct qmc5883l_config cfg;
  uint8_t reg[14];
  uint8_t pointer;
  double field_T[3];
  int64_t now_ns;
  int64_t next_result_ns; /* INT64_MAX in standby */
  uint64_t sample_index;
};

void qmc5883l_init(struct qmc5883l *s, const struct qmc5883l_config *c, int64_t power_on_ns);
void qmc5883l_set_truth(struct qmc5883l *s, int64_t t_ns, const double field_T[3]);
void qmc5883l_advance(struct qmc5883l *s, int64_t now_ns);
int qmc5883l_i2c_write(struct qmc5883l *s, const uint8_t *data, size_t n, int64_t t_ns);
int qmc5883l_i2c_read(struct qmc5883l *s, uint8_t *data, size_t n, int64_t t_ns);
/* LSB per gauss for the RNG field of CONTROL_1: 12000 at +-2 G, 3000 at +-8 G. */
double qmc5883l_lsb_per_gauss(uint8_t control_1);
/* The data registers (X, Y, Z) as a driver decodes them at the range CONTROL_1 holds, in T. */
void qmc5883l_field_read_T(const struct qmc5883l *s, double field_T[3]);
int64_t qmc5883l_next_event_ns(const struct qmc5883l *s);

#ifdef __cplusplus
}
#endif
#endif
