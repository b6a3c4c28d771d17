/* The Arduino Mega's pins on the simulated ATmega2560: the board interface the device entries
 * talk to (devices.h), the firmware's outputs as link events at their cycle, and the timer
 * outputs (PWM duty, servo pulses) read from the timer registers, since simavr 1.6 makes no
 * edges for them. */
#include <stdint.h>
#include <string.h>

#include <avr_adc.h>
#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_io.h>

#include <hal/gpio.h>

#include "devices.h"
#include "engine.h"

/* Ports in port_names order; each pin's port and bit (ATmega2560 datasheet, Arduino Mega 2560
 * schematic). */
static const char port_names[11] = {'A', 'B', 'C', 'D', 'E', 'F', 'G', 'H', 'J', 'K', 'L'};
enum { PA, PB, PC, PD, PE, PF, PG, PH, PJ, PK, PL };
#define P(port, bit) (uint8_t)((port) << 3 | (bit))
static const uint8_t pin_port_bit[SEAR_LINK_PINS] = {
    P(PE, 0), P(PE, 1), P(PE, 4), P(PE, 5), P(PG, 5), P(PE, 3), P(PH, 3), P(PH, 4), P(PH, 5), P(PH, 6), /* 0..9 */
    P(PB, 4), P(PB, 5), P(PB, 6), P(PB, 7), P(PJ, 1), P(PJ, 0), P(PH, 1), P(PH, 0), P(PD, 3), P(PD, 2), /* 10..19 */
    P(PD, 1), P(PD, 0), P(PA, 0), P(PA, 1), P(PA, 2), P(PA, 3), P(PA, 4), P(PA, 5), P(PA, 6), P(PA, 7), /* 20..29 */
    P(PC, 7), P(PC, 6), P(PC, 5), P(PC, 4), P(PC, 3), P(PC, 2), P(PC, 1), P(PC, 0), P(PD, 7), P(PG, 2), /* 30..39 */
    P(PG, 1), P(PG, 0), P(PL, 7), P(PL, 6), P(PL, 5), P(PL, 4), P(PL, 3), P(PL, 2), P(PL, 1), P(PL, 0), /* 40..49 */
    P(PB, 3), P(PB, 2), P(PB, 1), P(PB, 0), P(PF, 0), P(PF, 1), P(PF, 2), P(PF, 3), P(PF, 4), P(PF, 5), /* 50..59 */
    P(PF, 6), P(PF, 7), P(PK, 0), P(PK, 1), P(PK, 2), P(PK, 3), P(PK, 4), P(PK, 5), P(PK, 6), P(PK, 7), /* 60..69 */
};
#define NO_PIN 0xFF

static struct {
  uint8_t ddr, port;           /* as last written by the firmware */
  uint8_t driven_mask, driven; /* the bits devices drive, and their levels */
  uint8_t pin_of_bit[8];       /* the board's pin on each bit, NO_PIN if none */
  avr_irq_t *irq;              /* the port's IRQs, IOPORT_IRQ_PIN0.. */
} ports[11];

static uint8_t mode[SEAR_LINK_PINS];
static uint8_t pwm_on[SEAR_LINK_PINS]; /* 1 while a timer output drives the pin */

static uint8_t output_level(int p, int bit) { return (uint8_t)(ports[p].port >> bit & 1); }

/* What an input reads: a device's level, else the pull-up; a floating input reads LOW, as in
 * the native engine (pins.c there). */
static uint8_t input_level(int p, int bit) {
  if (ports[p].driven_mask >> bit & 1) return (uint8_t)(ports[p].driven >> bit & 1);
  return output_level(p, bit);
}

static uint8_t level_of(uint8_t pin) {
  const int p = pin_port_bit[pin] >> 3, bit = pin_port_bit[pin] & 7;
  return (ports[p].ddr >> bit & 1) ? output_level(p, bit) : input_level(p, bit);
}

/* The port's default input levels are the devices' (simavr re-raises them on every PORT or
 * DDR write, where it would otherwise put the pull-up back over a device holding a pin low). */
static void tell_port_external(int p) {
  avr_ioport_external_t e;
  memset(&e, 0, sizeof e);
  e.name = (unsigned long)port_names[p] & 0x7F;
  e.mask = ports[p].driven_mask;
  e.value = ports[p].driven;
  avr_ioctl(engine.avr, AVR_IOCTL_IOPORT_SET_EXTERNAL(port_names[p]), &e);
}

/* As in the native engine (hal/runtime/pins.c), a change of what a device drives reaches the
 * simulator at the device's own time, for the waveforms. */
void board_drive_pin(uint8_t pin, uint8_t level) {
  if (pin >= SEAR_LINK_PINS) return;
  const int p = pin_port_bit[pin] >> 3, bit = pin_port_bit[pin] & 7;
  const uint8_t m = (uint8_t)(1u << bit);
  const uint8_t was = (uint8_t)((ports[p].driven_mask & m) ? ports[p].driven >> bit & 1 : MCU_FLOATING);
  if (was != level) engine_emit(SEAR_EVENT_PIN_DRIVEN, pin, level == MCU_FLOATING ? 2u : level, mcu_devices_time_ns());
  if (level == MCU_FLOATING) {
    ports[p].driven_mask = (uint8_t)(ports[p].driven_mask & ~m);
  } else {
    ports[p].driven_mask |= m;
    ports[p].driven = (uint8_t)(level ? ports[p].driven | m : ports[p].driven & ~m);
  }
  tell_port_external(p);
  if (!(ports[p].ddr & m)) avr_raise_irq(ports[p].irq + bit, input_level(p, bit));
}

int board_output_low(uint8_t pin) {
  if (pin >= SEAR_LINK_PINS) return 0;
  const int p = pin_port_bit[pin] >> 3, bit = pin_port_bit[pin] & 7;
  return (ports[p].ddr >> bit & 1) && !output_level(p, bit);
}

/* The ADC's inputs, in millivolts as simavr takes them. */
void board_set_analog(uint8_t channel, double volts) {
  if (channel >= SEAR_LINK_ADC_CHANNELS) return;
  avr_irq_t *irq = avr_io_getirq(engine.avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0 + channel);
  if (irq) avr_raise_irq(irq, (uint32_t)(volts > 0 ? volts * 1000.0 + 0.5 : 0));
}

/* The firmware changed a port's DDR or PORT: each pin on it whose mode or level moved becomes
 * events, and the device listening to it is told, as the native engine's gpio does. */
static void port_changed(int p, uint8_t ddr, uint8_t port) {
  const int64_t now = engine_now_ns();
  const uint8_t old_ddr = ports[p].ddr, old_port = ports[p].port;
  ports[p].ddr = ddr;
  ports[p].port = port;
  for (int bit = 0; bit < 8; ++bit) {
    const uint8_t pin = ports[p].pin_of_bit[bit];
    if (pin == NO_PIN) continue;
    const int was_out = old_ddr >> bit & 1, out = ddr >> bit & 1;
    const uint8_t new_mode = out ? OUTPUT : (port >> bit & 1) ? INPUT_PULLUP : INPUT;
    if (new_mode != mode[pin]) {
      mode[pin] = new_mode;
      engine_emit(SEAR_EVENT_PIN_MODE, pin, new_mode, now);
    }
    if (out && (!was_out || ((old_port ^ port) >> bit & 1))) {
      if (!pwm_on[pin]) engine_emit(SEAR_EVENT_PIN, pin, output_level(p, bit), now);
      mcu_devices_pin_written(pin, output_level(p, bit), now);
    } else if (!out && was_out) {
      mcu_devices_pin_written(pin, input_level(p, bit), now);
    }
  }
}

static void on_ddr(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  const int p = (int)(intptr_t)param;
  port_changed(p, (uint8_t)value, ports[p].port);
}

static void on_port(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  const int p = (int)(intptr_t)param;
  port_changed(p, ports[p].ddr, (uint8_t)value);
}

void avr_pins_init(void) {
  memset(ports, 0, sizeof ports);
  for (int p = 0; p < 11; ++p) {
    memset(ports[p].pin_of_bit, NO_PIN, sizeof ports[p].pin_of_bit);
    ports[p].irq = avr_io_getirq(engine.avr, AVR_IOCTL_IOPORT_GETIRQ(port_names[p]), IOPORT_IRQ_PIN0);
    if (!ports[p].irq) engine_fatal("libsimavr's ATmega2560 has no port %c", port_names[p]);
    avr_irq_register_notify(ports[p].irq + IOPORT_IRQ_DIRECTION_ALL, on_ddr, (void *)(intptr_t)p);
    avr_irq_register_notify(ports[p].irq + IOPORT_IRQ_REG_PORT, on_port, (void *)(intptr_t)p);
  }
  for (uint8_t pin = 0; pin < SEAR_LINK_PINS; ++pin) ports[pin_port_bit[pin] >> 3].pin_of_bit[pin_port_bit[pin] & 7] = pin;
}

uint8_t avr_pin_at(int port, int bit) {
  return port >= 0 && port < 11 && bit >= 0 && bit < 8 ? ports[port].pin_of_bit[bit] : NO_PIN;
}

/* Timer outputs. Register data addresses from the ATmega2560 datasheet's register summary. */
struct timer_regs {
  uint16_t tccra, tccrb, icr, ocr[3];
  uint8_t wide; /* 16-bit */
};
static const struct timer_regs timers[6] = {
    {0x44, 0x45, 0, {0x47, 0x48, 0}, 0},              /* timer0 */
    {0x80, 0x81, 0x86, {0x88, 0x8A, 0x8C}, 1},        /* timer1 */
    {0xB0, 0xB1, 0, {0xB3, 0xB4, 0}, 0},              /* timer2 */
    {0x90, 0x91, 0x96, {0x98, 0x9A, 0x9C}, 1},        /* timer3 */
    {0xA0, 0xA1, 0xA6, {0xA8, 0xAA, 0xAC}, 1},        /* timer4 */
    {0x120, 0x121, 0x126, {0x128, 0x12A, 0x12C}, 1},  /* timer5 */
};
/* The pins wired to a timer's compare outputs on the Mega: timer << 4 | channel. */
static const struct {
  uint8_t pin, timer, channel;
} timer_pins[] = {{2, 3, 1}, {3, 3, 2}, {4, 0, 1},  {5, 3, 0},  {6, 4, 0},  {7, 4, 1},  {8, 4, 2}, {9, 2, 1},
                  {10, 2, 0}, {11, 1, 0}, {12, 1, 1}, {13, 0, 0}, {44, 5, 2}, {45, 5, 1}, {46, 5, 0}};
static uint32_t shown[SEAR_LINK_PINS]; /* kind << 16 | value last sent, 0 for none */

static uint16_t reg16(uint16_t low) { return (uint16_t)(engine.avr->data[low] | engine.avr->data[low + 1] << 8); }

/* The output's share of high time, and its period in cycles; 0 when the channel makes no PWM. */
static int waveform(const struct timer_regs *t, int channel, double *duty, uint64_t *period) {
  const uint8_t *d = engine.avr->data;
  const int com = d[t->tccra] >> (6 - 2 * channel) & 3;
  static const uint16_t prescale[8] = {0, 1, 8, 64, 256, 1024, 0, 0};
  const uint16_t div = prescale[d[t->tccrb] & 7];
  if (com < 2 || div == 0) return 0;
  int fast;
  uint32_t top;
  const uint32_t ocr = t->wide ? reg16(t->ocr[channel]) : d[t->ocr[channel]];
  if (t->wide) {
    const int wgm = (d[t->tccra] & 3) | (d[t->tccrb] >> 3 & 3) << 2;
    static const int16_t tops[16] = {-1, 255, 511, 1023, -1, 255, 511, 1023, -2, -3, -2, -3, -1, -1, -2, -3};
    static const uint8_t is_fast[16] = {0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 1, 1};
    if (tops[wgm] == -1) return 0;
    top = tops[wgm] == -2 ? reg16(t->icr) : tops[wgm] == -3 ? reg16(t->ocr[0]) : (uint32_t)tops[wgm];
    fast = is_fast[wgm];
  } else {
    const int wgm = (d[t->tccra] & 3) | (d[t->tccrb] >> 3 & 1) << 2;
    if (wgm != 1 && wgm != 3 && wgm != 5 && wgm != 7) return 0;
    top = wgm >= 5 ? d[t->ocr[0]] : 255u;
    fast = wgm == 3 || wgm == 7;
  }
  if (top == 0) return 0;
  double high = fast ? (ocr >= top ? 1.0 : (double)(ocr + 1) / (top + 1)) : (ocr >= top ? 1.0 : (double)ocr / top);
  if (com == 3) high = 1.0 - high; /* inverting */
  *duty = high;
  *period = (uint64_t)(fast ? top + 1 : 2 * top) * div;
  return 1;
}

void avr_pins_poll_pwm(void) {
  const int64_t now = engine_now_ns();
  for (size_t i = 0; i < sizeof timer_pins / sizeof timer_pins[0]; ++i) {
    const uint8_t pin = timer_pins[i].pin;
    double duty = 0;
    uint64_t period = 0;
    const int on = waveform(&timers[timer_pins[i].timer], timer_pins[i].channel, &duty, &period) &&
                   mode[pin] == OUTPUT;
    if (!on) {
      if (pwm_on[pin]) {
        /* The timer let go: the pin shows its PORT latch again. */
        pwm_on[pin] = 0;
        shown[pin] = 0;
        engine_emit(SEAR_EVENT_PIN, pin, level_of(pin), now);
      }
      continue;
    }
    pwm_on[pin] = 1;
    /* A frame of 10..30 ms is a servo's: its pulse width matters, not its duty. */
    const double period_s = (double)period / (double)engine.clock_hz;
    uint32_t kind, value;
    if (period_s >= 0.010 && period_s <= 0.030) {
      kind = SEAR_EVENT_SERVO;
      value = (uint32_t)(duty * period_s * 1e6 + 0.5);
    } else {
      kind = SEAR_EVENT_PWM;
      value = (uint32_t)(duty * 255.0 + 0.5);
    }
    const uint32_t code = kind << 16 | value;
    if (code == shown[pin]) continue;
    shown[pin] = code;
    engine_emit((enum sear_event_kind)kind, pin, value, now);
  }
}
