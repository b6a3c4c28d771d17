/* The firmware-side half of each device kind (see devices.h): a table of what each kind does
 * with its samples, with pins the firmware drives, and with its own timed events. Kinds without
 * an entry for an operation simply have no such behaviour. */
#include "devices.h"


#include "devices/sharp_gp2d12.h"
#include "pins.h"

struct device_ops {
  void (*init)(struct mcu_device *d, const struct sear_link_input *in);
  void (*sample)(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s);
  void (*pin_written)(struct mcu_device *d, const struct sear_link_input *in, uint8_t pin, uint8_t level, int64_t t_ns);
  int64_t (*next_event)(const struct mcu_device *d);
  void (*run_event)(struct mcu_device *d, const struct sear_link_input *in, int64_t now_ns);
};

static void gp2d12_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)d;
  sear_mcu.analog_v[in->pins[0]] = gp2d12_sample_v(s->value[0], in->seed, s->index, in->param[0]);
}

static void gp2d15_start(struct mcu_device *d, const struct sear_link_input *in) {
  gp2d15_init(&d->u.gp2d15, in->param[0], in->param[1]);
}

static void gp2d15_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  mcu_set_driven((uint8_t)in->pins[0], (uint8_t)gp2d15_update(&d->u.gp2d15, s->value[0]));
}

static void switch_take(struct mcu_device *d, const struct sear_link_input *in, const struct sear_link_sample *s) {
  (void)d;
  /* A closed contact pulls the pin to ground; an open one leaves it to the pull-up. */
  mcu_set_driven((uint8_t)in->pins[0], s->value[0] != 0.0 ? 0 : MCU_FLOATING);
}

static const struct device_ops kinds[SEAR_INPUT_KIND_END] = {
    [SEAR_INPUT_GP2D12] = {.sample = gp2d12_take},
    [SEAR_INPUT_GP2D15] = {.init = gp2d15_start, .sample = gp2d15_take},
    [SEAR_INPUT_SWITCH] = {.sample = switch_take},
};

static uint32_t input_count(void) {
  const uint32_t n = sear_mcu.link->input_count;
  return n < SEAR_LINK_MAX_INPUTS ? n : SEAR_LINK_MAX_INPUTS;
}

static const struct device_ops *ops_of(uint32_t input) {
  const uint32_t kind = sear_mcu.link->inputs[input].kind;
  return kind < SEAR_INPUT_KIND_END ? &kinds[kind] : &kinds[0];
}

void mcu_devices_init(void) {
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) sear_mcu.pin_device[pin] = MCU_NO_DEVICE;
  for (uint32_t i = 0; i < input_count(); ++i) {
    const struct sear_link_input *in = &sear_mcu.link->inputs[i];
    if (ops_of(i)->init) ops_of(i)->init(&sear_mcu.devices[i], in);
    /* A device that listens to a pin the firmware drives is told of every level it writes there. */
    if (ops_of(i)->pin_written)
      for (int p = 0; p < SEAR_LINK_INPUT_PINS; ++p)
        if (in->pins[p] < SEAR_LINK_PINS) sear_mcu.pin_device[in->pins[p]] = (uint8_t)i;
  }
}

void mcu_devices_sample(const struct sear_link_sample *s) {
  if (s->input >= input_count()) return;
  if (ops_of(s->input)->sample) ops_of(s->input)->sample(&sear_mcu.devices[s->input], &sear_mcu.link->inputs[s->input], s);
}

void mcu_devices_pin_written(uint8_t pin, uint8_t level, int64_t t_ns) {
  const uint8_t i = sear_mcu.pin_device[pin];
  if (i == MCU_NO_DEVICE || i >= input_count() || !ops_of(i)->pin_written) return;
  ops_of(i)->pin_written(&sear_mcu.devices[i], &sear_mcu.link->inputs[i], pin, level, t_ns);
}

int64_t mcu_devices_next_event(void) {
  int64_t t = MCU_TIME_NEVER;
  for (uint32_t i = 0; i < input_count(); ++i) {
    if (!ops_of(i)->next_event) continue;
    const int64_t e = ops_of(i)->next_event(&sear_mcu.devices[i]);
    if (e < t) t = e;
  }
  return t;
}

void mcu_devices_run_due(int64_t now_ns) {
  for (;;) {
    int64_t t = MCU_TIME_NEVER;
    uint32_t which = 0;
    for (uint32_t i = 0; i < input_count(); ++i) {
      if (!ops_of(i)->next_event) continue;
      const int64_t e = ops_of(i)->next_event(&sear_mcu.devices[i]);
      if (e < t) {
        t = e;
        which = i;
      }
    }
    if (t > now_ns) return;
    ops_of(which)->run_event(&sear_mcu.devices[which], &sear_mcu.link->inputs[which], t);
  }
}
