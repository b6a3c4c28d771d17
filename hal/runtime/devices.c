/* The firmware-side half of each device kind (see devices.h): a table of what each kind does
 * with its samples, with pins the firmware drives, and with its own timed events. Kinds without
 * an entry for an operation simply have no such behaviour. */
#include "devices.h"

#include "devices/sharp_gp2d12.h"
#include "readings.h"

static struct sear_link *link;
static struct mcu_device devices[SEAR_LINK_MAX_INPUTS];
static uint8_t pin_device[SEAR_LINK_PINS]; /* the input told of the firmware's writes to the pin */
static int64_t operation_ns;                /* see mcu_devices_time_ns() */
/* The least of the devices' next_ns, asked for after nearly every HAL call: kept as refresh()
 * moves them, and found again only when the device that held it moves later. Scanning every
 * input for it on each call was a fifth of the reference rover's firmware time. */
static int64_t earliest_ns = MCU_TIME_NEVER;
static int earliest_stale = 1;

/* An analog output's volts and a digital output's level go on the board and are kept for the
 * device's reading. */
static void put_analog(struct mcu_device *d, uint32_t channel, double volts) {
  if (channel >= SEAR_LINK_ADC_CHANNELS) return;
  d->out_v = volts;
  board_set_analog((uint8_t)channel, volts);
}

static void put_level(struct mcu_device *d, uint32_t pin, uint8_t level) {
  if (pin >= SEAR_LINK_PINS) return;
  d->out_level = level;
  board_drive_pin((uint8_t)pin, level);
}

struct device_ops {
  uint8_t listens; /* bit n: pins[n] is a pin the firmware drives that the device is told of */
  void (*init)(struct mcu_device *d, const struct sear_link_input *in);
  void (*sample)(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s);
  void (*pin_written)(struct mcu_device *d, const struct sear_link_input *in, uint8_t pin, uint8_t level, int64_t t_ns);
  int64_t (*next_event)(const struct mcu_device *d);
  void (*run_event)(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns);
  /* A bus device: which pins[] slot holds its chip-select pin (SPI) or its address (I2C). */
  int spi_cs_slot;
  uint8_t (*spi_transfer)(struct mcu_device *d, uint8_t mosi, uint32_t sck_hz, int64_t t_ns);
  int i2c_address_slot;
  int (*i2c_write)(struct mcu_device *d, const uint8_t *data, uint8_t length, int64_t t_ns);
  int (*i2c_read)(struct mcu_device *d, uint8_t *data, uint8_t length, int64_t t_ns);
  /* Puts the model's own output pins (an interrupt or data-ready line) on the board, after
   * anything that may have moved them: its events, and the bus reads that clear them. */
  void (*drive)(struct mcu_device *d, const struct sear_link_input *in);
};

static void gp2d12_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  put_analog(d, in->pins[0], gp2d12_sample_v(s->value[0], in->seed, s->index, in->param[0]));
}

static void gp2d15_start(struct mcu_device *d, const struct sear_link_input *in) {
  gp2d15_init(&d->u.gp2d15, in->param[0], in->param[1]);
}

static void gp2d15_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  put_level(d, in->pins[0], (uint8_t)gp2d15_update(&d->u.gp2d15, s->value[0]));
}

static void switch_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  /* A closed contact pulls the pin to ground; an open one leaves it to the pull-up. */
  put_level(d, in->pins[0], s->value[0] != 0.0 ? 0 : MCU_FLOATING);
}

/* HC-SR04: the firmware's TRIG pulses start measurements; ECHO edges follow at their own times. */
static void hcsr04_start(struct mcu_device *d, const struct sear_link_input *in) { hcsr04_init(&d->u.hcsr04, in->seed); }

static void hcsr04_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)in;
  hcsr04_set_distance(&d->u.hcsr04, s->value[0], s->time_ns);
}

static void hcsr04_trig(struct mcu_device *d, const struct sear_link_input *in, uint8_t pin, uint8_t level,
                        int64_t t_ns) {
  (void)in;
  (void)pin;
  hcsr04_trigger(&d->u.hcsr04, level, t_ns);
}

static int64_t hcsr04_next(const struct mcu_device *d) { return hcsr04_next_edge_ns(&d->u.hcsr04); }

static void hcsr04_edge(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns) {
  (void)now_ns;
  put_level(d, in->pins[1], (uint8_t)hcsr04_take_edge(&d->u.hcsr04));
}

/* MaxBotix LV-EZ: the simulator decides each reading (the serial output it hosts gives the same
 * one); here its analog voltage and pulse width are played out. */
static void maxbotix_start(struct mcu_device *d, const struct sear_link_input *in) {
  maxbotix_lv_ez_init(&d->u.maxbotix);
  put_level(d, in->pins[1], 0);
}

static void maxbotix_update_analog(struct mcu_device *d, const struct sear_link_input *in, int64_t t_ns) {
  put_analog(d, in->pins[0], maxbotix_lv_ez_analog_v(&d->u.maxbotix, t_ns, link->avcc_v));
}

static void maxbotix_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  maxbotix_lv_ez_take_reading(&d->u.maxbotix, (int)s->value[0], s->time_ns);
  maxbotix_update_analog(d, in, s->time_ns);
}

/* The analog output moves at the end of each cycle; the PW pin at its edges: both are events. */
static int64_t maxbotix_next(const struct mcu_device *d) {
  const int64_t edge = maxbotix_lv_ez_next_edge_ns(&d->u.maxbotix);
  const int64_t ramp = d->u.maxbotix.an_ramp_end_ns > d->analog_shown_ns ? d->u.maxbotix.an_ramp_end_ns : MCU_TIME_NEVER;
  return edge < ramp ? edge : ramp;
}

static void maxbotix_event(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns) {
  if (maxbotix_lv_ez_next_edge_ns(&d->u.maxbotix) <= now_ns) {
    const int level = maxbotix_lv_ez_take_edge(&d->u.maxbotix);
    put_level(d, in->pins[1], (uint8_t)level);
  } else {
    d->analog_shown_ns = now_ns;
    maxbotix_update_analog(d, in, now_ns);
  }
}

/* Quadrature encoder: edges at the exact times the shaft crosses them, from each quantum's motion. */
static void encoder_start(struct mcu_device *d, const struct sear_link_input *in) {
  encoder_init(&d->u.encoder, (uint32_t)in->param[0], 0.0);
  const int levels = encoder_levels(&d->u.encoder);
  put_level(d, in->pins[0], (uint8_t)(levels & 1));
  put_level(d, in->pins[1], (uint8_t)((levels >> 1) & 1));
}

static void encoder_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)in;
  encoder_set_motion(&d->u.encoder, s->value[0], s->value[1], s->time_ns);
}

static int64_t encoder_next(const struct mcu_device *d) { return encoder_next_edge_ns(&d->u.encoder); }

static void encoder_edge(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns) {
  (void)now_ns;
  int channel = 0, level = 0;
  encoder_take_edge(&d->u.encoder, &channel, &level);
  put_level(d, in->pins[channel ? 1 : 0], (uint8_t)level);
}

/* MPU-6000 (SPI) and MPU-6050 (I2C): a register file fed one sample of truth per quantum, which
 * it samples at its own rate; its data-ready pin changes are events. */
static void mpu_start(struct mcu_device *d, const struct sear_link_input *in, enum mpu6000_variant variant) {
  struct mpu6000_config c;
  mpu6000_default_config(&c, variant);
  c.seed = in->seed;
  if (variant == MPU6000_VARIANT_6050) c.i2c_address = (uint8_t)in->pins[0];
  if (in->param[0] >= 0) c.gyro.noise_density = in->param[0];
  if (in->param[1] >= 0)
    for (int a = 0; a < 3; ++a) c.gyro.turn_on_bias[a] = in->param[1];
  if (in->param[2] >= 0) c.accel.noise_density = in->param[2];
  c.self_test_error = in->param[3];
  mpu6000_init(&d->u.mpu, &c, 0);
}
static void mpu6000_start(struct mcu_device *d, const struct sear_link_input *in) { mpu_start(d, in, MPU6000_VARIANT_6000); }
static void mpu6050_start(struct mcu_device *d, const struct sear_link_input *in) { mpu_start(d, in, MPU6000_VARIANT_6050); }

static void mpu_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)in;
  mpu6000_set_truth(&d->u.mpu, s->time_ns, &s->value[0], &s->value[3]);
}

static void mpu_cs(struct mcu_device *d, const struct sear_link_input *in, uint8_t pin, uint8_t level, int64_t t_ns) {
  (void)in;
  (void)pin;
  mpu6000_spi_select(&d->u.mpu, level == 0, t_ns);
}

static int64_t mpu_next(const struct mcu_device *d) { return mpu6000_next_event_ns(&d->u.mpu); }

static void mpu_event(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns) {
  (void)in;
  mpu6000_advance(&d->u.mpu, now_ns);
}

static void mpu_drive(struct mcu_device *d, const struct sear_link_input *in) {
  put_level(d, in->pins[1], (uint8_t)mpu6000_int_level(&d->u.mpu));
}

static uint8_t mpu_spi(struct mcu_device *d, uint8_t mosi, uint32_t sck_hz, int64_t t_ns) {
  return mpu6000_spi_transfer(&d->u.mpu, mosi, sck_hz, t_ns);
}
static int mpu_i2c_write(struct mcu_device *d, const uint8_t *data, uint8_t length, int64_t t_ns) {
  return mpu6000_i2c_write(&d->u.mpu, data, length, t_ns);
}
static int mpu_i2c_read(struct mcu_device *d, uint8_t *data, uint8_t length, int64_t t_ns) {
  return mpu6000_i2c_read(&d->u.mpu, data, length, t_ns);
}

/* The compasses: register files on I2C fed the field in their own axes once a quantum. */
static void hmc_start(struct mcu_device *d, const struct sear_link_input *in) {
  struct hmc5883l_config c;
  hmc5883l_default_config(&c);
  c.seed = in->seed;
  hmc5883l_init(&d->u.hmc, &c, 0);
}
static void hmc_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)in;
  hmc5883l_set_truth(&d->u.hmc, s->time_ns, s->value);
}
static int64_t hmc_next(const struct mcu_device *d) { return hmc5883l_next_event_ns(&d->u.hmc); }
static void hmc_event(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns) {
  (void)in;
  hmc5883l_advance(&d->u.hmc, now_ns);
}

static void hmc_drive(struct mcu_device *d, const struct sear_link_input *in) {
  put_level(d, in->pins[1], (uint8_t)hmc5883l_drdy_level(&d->u.hmc));
}
static int hmc_i2c_write(struct mcu_device *d, const uint8_t *data, uint8_t length, int64_t t_ns) {
  return hmc5883l_i2c_write(&d->u.hmc, data, length, t_ns);
}
static int hmc_i2c_read(struct mcu_device *d, uint8_t *data, uint8_t length, int64_t t_ns) {
  return hmc5883l_i2c_read(&d->u.hmc, data, length, t_ns);
}

static void qmc_start(struct mcu_device *d, const struct sear_link_input *in) {
  struct qmc5883l_config c;
  qmc5883l_default_config(&c);
  c.seed = in->seed;
  qmc5883l_init(&d->u.qmc, &c, 0);
}
static void qmc_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)in;
  qmc5883l_set_truth(&d->u.qmc, s->time_ns, s->value);
}
static int qmc_i2c_write(struct mcu_device *d, const uint8_t *data, uint8_t length, int64_t t_ns) {
  return qmc5883l_i2c_write(&d->u.qmc, data, length, t_ns);
}
static int qmc_i2c_read(struct mcu_device *d, uint8_t *data, uint8_t length, int64_t t_ns) {
  return qmc5883l_i2c_read(&d->u.qmc, data, length, t_ns);
}

/* A simulator-hosted UART device on a soft UART's RX pin: each byte it sends arrives as a sample
 * at its start edge, and is played out on the pin bit by bit. */
static void line_start(struct mcu_device *d, const struct sear_link_input *in) {
  uart_pins_init(&d->u.line, in->param[0] != 0.0);
  put_level(d, in->pins[0], (uint8_t)uart_pins_idle_level(&d->u.line));
}

static void line_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  const double baud = s->value[1];
  if (!(baud >= 1 && baud <= 4e6) || !(s->value[0] >= 0 && s->value[0] <= 255)) return;
  put_level(d, in->pins[0], (uint8_t)uart_pins_start(&d->u.line, (uint8_t)s->value[0], (uint32_t)baud, s->time_ns));
}

static int64_t line_next(const struct mcu_device *d) { return uart_pins_next_edge_ns(&d->u.line); }

static void line_edge(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns) {
  (void)now_ns;
  put_level(d, in->pins[0], (uint8_t)uart_pins_take_edge(&d->u.line));
}

static const struct device_ops kinds[SEAR_INPUT_KIND_END] = {
    [SEAR_INPUT_GP2D12] = {.sample = gp2d12_take},
    [SEAR_INPUT_GP2D15] = {.init = gp2d15_start, .sample = gp2d15_take},
    [SEAR_INPUT_SWITCH] = {.sample = switch_take},
    [SEAR_INPUT_HCSR04] = {.listens = 1, .init = hcsr04_start, .sample = hcsr04_take, .pin_written = hcsr04_trig,
                           .next_event = hcsr04_next, .run_event = hcsr04_edge},
    [SEAR_INPUT_MAXBOTIX] = {.init = maxbotix_start, .sample = maxbotix_take, .next_event = maxbotix_next,
                             .run_event = maxbotix_event},
    [SEAR_INPUT_ENCODER] = {.init = encoder_start, .sample = encoder_take, .next_event = encoder_next,
                            .run_event = encoder_edge},
    [SEAR_INPUT_MPU6000] = {.listens = 1, .init = mpu6000_start, .sample = mpu_take, .pin_written = mpu_cs,
                            .next_event = mpu_next, .run_event = mpu_event, .spi_cs_slot = 0, .spi_transfer = mpu_spi,
                            .drive = mpu_drive},
    [SEAR_INPUT_MPU6050] = {.init = mpu6050_start, .sample = mpu_take, .next_event = mpu_next, .run_event = mpu_event,
                            .i2c_address_slot = 0, .i2c_write = mpu_i2c_write, .i2c_read = mpu_i2c_read,
                            .drive = mpu_drive},
    [SEAR_INPUT_HMC5883L] = {.init = hmc_start, .sample = hmc_take, .next_event = hmc_next, .run_event = hmc_event,
                             .i2c_address_slot = 0, .i2c_write = hmc_i2c_write, .i2c_read = hmc_i2c_read,
                             .drive = hmc_drive},
    [SEAR_INPUT_QMC5883L] = {.init = qmc_start, .sample = qmc_take, .i2c_address_slot = 0, .i2c_write = qmc_i2c_write,
                             .i2c_read = qmc_i2c_read},
    [SEAR_INPUT_UART_PINS] = {.init = line_start, .sample = line_take, .next_event = line_next, .run_event = line_edge},
};

/* The inputs on the SPI bus, in input order, listed once: an MPU-6000's burst is 14 bytes a
 * millisecond, and asking each of a dozen inputs whether it was on the bus was half of a byte's
 * cost in the firmware's process. */
static uint8_t spi_inputs[SEAR_LINK_MAX_INPUTS];
static uint32_t spi_input_count;

static uint32_t input_count(void) {
  const uint32_t n = link->input_count;
  return n < SEAR_LINK_MAX_INPUTS ? n : SEAR_LINK_MAX_INPUTS;
}

static const struct device_ops *ops_of(uint32_t input) {
  const uint32_t kind = link->inputs[input].kind;
  return kind < SEAR_INPUT_KIND_END ? &kinds[kind] : &kinds[0];
}

/* After every operation on a device (at t_ns): its output pins follow its state, its reading is
 * marked for publishing at the quantum's end, and its next event is kept here (the scheduler asks
 * for the earliest after nearly every HAL call) and brought into the scheduler's next look at
 * once, as a TRIG pulse's echo falls due within the same quantum. */
static void refresh(uint32_t i, int64_t t_ns) {
  struct mcu_device *d = &devices[i];
  if (ops_of(i)->drive) ops_of(i)->drive(d, &link->inputs[i]);
  mcu_readings_touch(i, t_ns);
  const int64_t before = d->next_ns;
  d->next_ns = ops_of(i)->next_event ? ops_of(i)->next_event(d) : MCU_TIME_NEVER;
  if (d->next_ns <= earliest_ns) earliest_ns = d->next_ns;
  else if (before == earliest_ns) earliest_stale = 1;
  if (d->next_ns != MCU_TIME_NEVER) board_device_event_at(d->next_ns);
}

void mcu_devices_init(struct sear_link *the_link) {
  link = the_link;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) pin_device[pin] = MCU_NO_DEVICE;
  spi_input_count = 0;
  for (uint32_t i = 0; i < input_count(); ++i) {
    const struct sear_link_input *in = &link->inputs[i];
    if (ops_of(i)->spi_transfer) spi_inputs[spi_input_count++] = (uint8_t)i;
    devices[i].out_level = MCU_FLOATING;
    if (ops_of(i)->init) ops_of(i)->init(&devices[i], in);
    refresh(i, 0);
    /* A device that listens to a pin the firmware drives is told of every level it writes there. */
    for (int p = 0; p < SEAR_LINK_INPUT_PINS; ++p)
      if ((ops_of(i)->listens >> p & 1) && in->pins[p] < SEAR_LINK_PINS) pin_device[in->pins[p]] = (uint8_t)i;
  }
}

int64_t mcu_devices_time_ns(void) { return operation_ns; }

void mcu_devices_sample(const struct sear_link_sample *s) {
  if (s->input >= input_count()) return;
  operation_ns = s->time_ns;
  if (ops_of(s->input)->sample) ops_of(s->input)->sample(&devices[s->input], &link->inputs[s->input], s);
  refresh(s->input, s->time_ns);
}

void mcu_devices_pin_written(uint8_t pin, uint8_t level, int64_t t_ns) {
  const uint8_t i = pin_device[pin];
  if (i == MCU_NO_DEVICE || i >= input_count() || !ops_of(i)->pin_written) return;
  operation_ns = t_ns;
  ops_of(i)->pin_written(&devices[i], &link->inputs[i], pin, level, t_ns);
  refresh(i, t_ns);
}

int64_t mcu_devices_next_event(void) {
  if (earliest_stale) {
    earliest_ns = MCU_TIME_NEVER;
    for (uint32_t i = 0; i < input_count(); ++i)
      if (devices[i].next_ns < earliest_ns) earliest_ns = devices[i].next_ns;
    earliest_stale = 0;
  }
  return earliest_ns;
}

void mcu_devices_run_due(int64_t now_ns) {
  for (int64_t t; (t = mcu_devices_next_event()) <= now_ns;) {
    uint32_t which = 0; /* the first device due then */
    while (which + 1 < input_count() && devices[which].next_ns != t) ++which;
    operation_ns = t;
    ops_of(which)->run_event(&devices[which], &link->inputs[which], t);
    refresh(which, t);
  }
}

int mcu_devices_spi_transfer(uint8_t mosi, uint32_t sck_hz, int64_t t_ns) {
  int miso = -1;
  operation_ns = t_ns;
  for (uint32_t k = 0; k < spi_input_count; ++k) {
    const uint32_t i = spi_inputs[k];
    const struct device_ops *ops = ops_of(i);
    if (!ops->spi_transfer) continue; /* a kind the firmware wrote over since the list was made */
    const uint32_t cs = link->inputs[i].pins[ops->spi_cs_slot];
    if (cs >= SEAR_LINK_PINS || !board_output_low((uint8_t)cs)) continue;
    link->usage.inputs_addressed |= 1u << i;
    /* Two selected devices drive MISO against each other: the bus reads their wired AND. */
    const uint8_t out = ops->spi_transfer(&devices[i], mosi, sck_hz, t_ns);
    refresh(i, t_ns);
    miso = miso < 0 ? out : (miso & out);
  }
  return miso;
}

struct sear_link *mcu_devices_link(void) { return link; }

const struct mcu_device *mcu_device_state(uint32_t i) { return &devices[i]; }

static int i2c_device(uint8_t address) {
  for (uint32_t i = 0; i < input_count(); ++i) {
    if (ops_of(i)->i2c_write && link->inputs[i].pins[ops_of(i)->i2c_address_slot] == address) {
      link->usage.inputs_addressed |= 1u << i;
      return (int)i;
    }
  }
  return -1;
}

int mcu_devices_i2c_write(uint8_t address, const uint8_t *data, uint8_t length, int64_t t_ns) {
  const int i = i2c_device(address);
  if (i < 0) return -1;
  operation_ns = t_ns;
  const int acknowledged = ops_of((uint32_t)i)->i2c_write(&devices[i], data, length, t_ns);
  refresh((uint32_t)i, t_ns);
  return acknowledged;
}

int mcu_devices_i2c_read(uint8_t address, uint8_t *data, uint8_t length, int64_t t_ns) {
  const int i = i2c_device(address);
  if (i < 0) return -1;
  operation_ns = t_ns;
  const int acknowledged = ops_of((uint32_t)i)->i2c_read(&devices[i], data, length, t_ns);
  refresh((uint32_t)i, t_ns);
  return acknowledged;
}

int mcu_devices_i2c_present(uint8_t address) { return i2c_device(address) >= 0; }
