/* Readings per kind (see readings.h): computed from the model's state once a quantum for the
 * inputs operated on, published only when they differ from the last published, so a model at rest
 * costs a comparison. No allocation; the last values are kept here, not read back from the link, which
 * the firmware itself could have overwritten. */
#include "readings.h"

#include <string.h>

#include "devices.h"

static const uint8_t value_count[SEAR_INPUT_KIND_END] = {SEAR_LINK_READING_VALUES_BY_KIND};

static uint32_t touched; /* bit i: input i was operated on since the last publish */
static int64_t touched_ns[SEAR_LINK_MAX_INPUTS];

static struct {
  double value[SEAR_LINK_SAMPLE_VALUES];
  int64_t time_ns;
  int published;
} last[SEAR_LINK_MAX_INPUTS];

/* The reading of input i at t_ns into v; returns how many values, 0 while there is none yet. */
static int reading_of(uint32_t i, int64_t t_ns, double v[SEAR_LINK_SAMPLE_VALUES]) {
  const struct sear_link *link = mcu_devices_link();
  const struct sear_link_input *in = &link->inputs[i];
  const struct mcu_device *d = mcu_device_state(i);
  switch (in->kind) {
    case SEAR_INPUT_GP2D12:
      if (in->pins[0] >= SEAR_LINK_ADC_CHANNELS) return 0;
      v[0] = d->out_v;
      return 1;
    case SEAR_INPUT_GP2D15:
      v[0] = gp2d15_level(&d->u.gp2d15);
      return 1;
    case SEAR_INPUT_SWITCH:
      if (in->pins[0] >= SEAR_LINK_PINS) return 0;
      v[0] = d->out_level == 0; /* a closed contact pulls the pin to ground */
      return 1;
    case SEAR_INPUT_HCSR04: {
      const int64_t width = hcsr04_last_echo_width_ns(&d->u.hcsr04);
      if (width < 0) return 0;
      v[0] = (double)width * 1e-9;
      v[1] = v[0] * HCSR04_SOUND_SPEED_MPS / 2; /* the datasheet's 58 us per cm, both ways */
      return 2;
    }
    case SEAR_INPUT_MAXBOTIX:
      v[0] = maxbotix_lv_ez_analog_v(&d->u.maxbotix, t_ns, link->avcc_v);
      v[1] = maxbotix_lv_ez_shown_inches(&d->u.maxbotix, t_ns);
      return 2;
    case SEAR_INPUT_ENCODER:
      v[0] = (double)encoder_count(&d->u.encoder);
      v[1] = encoder_count_angle_rad(&d->u.encoder);
      return 2;
    case SEAR_INPUT_MPU6000:
    case SEAR_INPUT_MPU6050:
      mpu6000_latest_si(&d->u.mpu, &v[0], &v[3]);
      return 6;
    case SEAR_INPUT_HMC5883L:
      hmc5883l_field_read_T(&d->u.hmc, v);
      return 3;
    case SEAR_INPUT_QMC5883L:
      qmc5883l_field_read_T(&d->u.qmc, v);
      return 3;
    default:
      return 0;
  }
}

void mcu_readings_touch(uint32_t i, int64_t t_ns) {
  if (i >= SEAR_LINK_MAX_INPUTS) return;
  touched |= 1u << i;
  touched_ns[i] = t_ns;
}

static void update(uint32_t i, int64_t t_ns) {
  double v[SEAR_LINK_SAMPLE_VALUES] = {0};
  const int n = reading_of(i, t_ns, v);
  const uint32_t kind = mcu_devices_link()->inputs[i].kind;
  if (n <= 0 || kind >= SEAR_INPUT_KIND_END || n != value_count[kind]) return;
  if (last[i].published && memcmp(last[i].value, v, sizeof v) == 0) return;
  /* Each input's operations come in time order but a sample may be stamped a little before the
   * HAL call that brought it in; the link holds readings in time order. */
  if (last[i].published && t_ns < last[i].time_ns) t_ns = last[i].time_ns;
  memcpy(last[i].value, v, sizeof v);
  last[i].time_ns = t_ns;
  last[i].published = 1;
  struct sear_link_reading *r = &mcu_devices_link()->readings[i];
  r->time_ns = t_ns;
  memcpy(r->value, v, sizeof v);
  /* The simulator reads only between turns, while this process waits: no ordering beyond this. */
  r->count++;
}

void mcu_readings_publish(void) {
  for (uint32_t i = 0; touched != 0 && i < SEAR_LINK_MAX_INPUTS; ++i)
    if (touched >> i & 1u) update(i, touched_ns[i]);
  touched = 0;
}
