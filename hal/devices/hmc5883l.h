/* Honeywell HMC5883L 3-axis magnetometer on I2C (address 0x1E): the register file, gains, single
 * and continuous measurement timing and overflow code of the HMC5883L datasheet (Rev. E, 2013),
 * fed with the magnetic field in tesla along the part's own axes. Times in integer nanoseconds. */
#ifndef SEAR_DEVICES_HMC5883L_H
#define SEAR_DEVICES_HMC5883L_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HMC5883L_I2C_ADDRESS 0x1E
/* Register list (datasheet table 2) */
enum {
  HMC5883L_CONFIG_A = 0x00, /* MA1:0 averaging, DO2:0 output rate, MS1:0 measurement bias */
  HMC5883L_CONFIG_B = 0x01, /* GN2:0 gain in bits 7:5 */
  HMC5883L_MODE = 0x02,     /* MD1:0: 0 continuous, 1 single, 2/3 idle */
  HMC5883L_DATA_X_MSB = 0x03, /* X, Z, Y, each MSB first, to 0x08 */
  HMC5883L_STATUS = 0x09,   /* bit 0 RDY, bit 1 LOCK */
  HMC5883L_ID_A = 0x0A      /* 'H', '4', '3' at 0x0A-0x0C */
};
#define HMC5883L_RDY 0x01
#define HMC5883L_LOCK 0x02
#define HMC5883L_OVERFLOW_CODE (-4096)  /* a channel that over- or underflowed reads this */
#define HMC5883L_SINGLE_MEASUREMENT_NS INT64_C(6000000) /* "about 6 ms" to data ready */
#define HMC5883L_DRDY_LOW_NS INT64_C(250000) /* DRDY pin: low 250 us as data is placed (pin table) */

struct hmc5883l_config {
  uint64_t seed;
  double noise_sd_T;       /* per axis, one sample with no averaging */
  double hard_iron_T[3];   /* a constant offset, from the board's own magnetised parts */
};

/* Datasheet defaults: noise floor 2 milligauss (table "Specifications", GN = 0, one sample). */
void hmc5883l_default_config(struct hmc5883l_config *c);

struct hmc5883l {
  struct hmc5883l_config cfg;
  uint8_t reg[13];
  uint8_t pointer;
  double field_T[3];
  int64_t now_ns;
  int64_t result_ns;       /* when the measurement under way completes; INT64_MAX: none */
  int continuous;
  int gain_in_use;         /* a gain change applies from the second measurement on */
  uint8_t read_mask;       /* data bytes read since the last update, bit per register 3..8 */
  int locked;
  uint64_t sample_index;
  int64_t drdy_low_until_ns; /* end of the DRDY pin's low pulse */
};

void hmc5883l_init(struct hmc5883l *s, const struct hmc5883l_config *c, int64_t power_on_ns);
void hmc5883l_set_truth(struct hmc5883l *s, int64_t t_ns, const double field_T[3]);
void hmc5883l_advance(struct hmc5883l *s, int64_t now_ns);
/* Returns 0 (ACK); the part acknowledges every byte, even to registers it ignores. */
int hmc5883l_i2c_write(struct hmc5883l *s, const uint8_t *data, size_t n, int64_t t_ns);
int hmc5883l_i2c_read(struct hmc5883l *s, uint8_t *data, size_t n, int64_t t_ns);
/* Digital resolution of gain code GN (0..7), LSB per gauss: 1370 ... 230. */
double hmc5883l_lsb_per_gauss(int gain_code);
/* The data registers (X, Y, Z) as a driver decodes them at the gain CONFIG_B holds, in T. */
void hmc5883l_field_read_T(const struct hmc5883l *s, double field_T[3]);
/* The DRDY pin (pulled high, low for 250 us as each result lands) as of the last advance, and
 * the next time it may change without a bus access (INT64_MAX: never). */
int hmc5883l_drdy_level(const struct hmc5883l *s);
int64_t hmc5883l_next_event_ns(const struct hmc5883l *s);

#ifdef __cplusplus
}
#endif
#endif
