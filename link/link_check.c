/* Checks of everything a firmware could have written into the link (see link_check.h). Every
 * value is read exactly once, so a firmware still writing cannot change it between the check and
 * its use. */
#include "link_check.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The longest a byte can stay in a UART's path: 66 bytes queued (shift register, data register,
 * 64-byte ring) at the slowest rate the HAL accepts, 300 baud, 10 bits each: 2.2 s. */
#define MAX_TX_AHEAD_NS 2200000000ll

#define FAIL(...)                               \
  do {                                          \
    snprintf(why, why_size, __VA_ARGS__);       \
    return -1;                                  \
  } while (0)

void sear_link_watch_init(struct sear_link_watch *w, int64_t call_cost_ns) {
  memset(w, 0, sizeof *w);
  w->call_cost_ns = call_cost_ns;
}

static uint32_t load32(const uint32_t *p) { return __atomic_load_n(p, __ATOMIC_ACQUIRE); }
static int64_t load64(const int64_t *p) { return __atomic_load_n(p, __ATOMIC_ACQUIRE); }

int sear_link_check_turn(const struct sear_link *link, int handed_back, struct sear_link_watch *w,
                         struct sear_link_turn *t, char *why, size_t why_size) {
  memset(t, 0, sizeof *t);
  const uint32_t magic = load32(&link->magic), version = load32(&link->version);
  if (magic != SEAR_LINK_MAGIC || version != SEAR_LINK_VERSION)
    FAIL("magic/version (0x%08x/%u instead of 0x%08x/%u)", magic, version, SEAR_LINK_MAGIC, SEAR_LINK_VERSION);
  const uint64_t front = __atomic_load_n(&link->guard_front, __ATOMIC_ACQUIRE);
  const uint64_t back = __atomic_load_n(&link->guard_back, __ATOMIC_ACQUIRE);
  if (front != SEAR_LINK_GUARD) FAIL("guard_front (0x%016llx)", (unsigned long long)front);
  if (back != SEAR_LINK_GUARD) FAIL("guard_back (0x%016llx)", (unsigned long long)back);
  t->request = load32(&link->request);
  if (t->request > SEAR_REQUEST_FATAL) FAIL("request (%u, not a request the HAL makes)", t->request);
  t->clock_ns = load64(&link->clock_ns);
  if (t->clock_ns < w->clock_ns)
    FAIL("clock_ns (%lld ns, earlier than the %lld ns it had already reached)", (long long)t->clock_ns,
         (long long)w->clock_ns);
  /* The HAL hands over as soon as a call finds the quantum's end reached, so its clock is at most
   * one call's cost past it; a quantum done must have reached it. */
  const int64_t latest = w->quantum_end_ns + w->call_cost_ns;
  if (t->clock_ns > latest)
    FAIL("clock_ns (%lld ns, past the quantum ending at %lld ns)", (long long)t->clock_ns,
         (long long)w->quantum_end_ns);
  if (handed_back && t->request == SEAR_REQUEST_QUANTUM_DONE && t->clock_ns < w->quantum_end_ns)
    FAIL("clock_ns (%lld ns, short of the quantum's end at %lld ns)", (long long)t->clock_ns,
         (long long)w->quantum_end_ns);
  const uint64_t calls = __atomic_load_n(&link->calls, __ATOMIC_ACQUIRE);
  if (calls < w->calls)
    FAIL("calls (%llu, fewer than the %llu already made)", (unsigned long long)calls, (unsigned long long)w->calls);
  t->last_call = load32(&link->last_call);
  if (t->last_call >= SEAR_CALL_COUNT) FAIL("last_call (%u, not a HAL call)", t->last_call);
  t->event_count = load32(&link->event_count);
  if (t->event_count > SEAR_LINK_MAX_EVENTS)
    FAIL("event_count (%u, more than the %u the queue holds)", t->event_count, SEAR_LINK_MAX_EVENTS);
  t->exit_code = link->exit_code;
  /* Only what a report can print: the text ends within its field, in plain ASCII. Each byte is
   * read once, into the copy. */
  for (size_t i = 0; i + 1 < sizeof t->fatal; ++i) {
    const char c = __atomic_load_n(&link->fatal[i], __ATOMIC_RELAXED);
    if (!c) break;
    t->fatal[i] = c >= 0x20 && c < 0x7f ? c : '?';
  }
  t->halt = load32(&link->halt);
  t->halted_ns = load64(&link->halted_ns);
  if (t->halt > SEAR_HALT_EMPTY_LOOP_IRQ_OFF) FAIL("halt (%u, not a halt the firmware's side reports)", t->halt);
  if (w->halt && (t->halt != w->halt || t->halted_ns != w->halted_ns))
    FAIL("halt (%u at %lld ns, after it halted (%u) at %lld ns)", t->halt, (long long)t->halted_ns, w->halt,
         (long long)w->halted_ns);
  if (t->halt && (t->halted_ns < w->turn_clock_ns && !w->halt))
    FAIL("halted_ns (%lld ns, before the turn began at %lld ns)", (long long)t->halted_ns, (long long)w->turn_clock_ns);
  if (t->halt && t->halted_ns > t->clock_ns)
    FAIL("halted_ns (%lld ns, after the clock at %lld ns)", (long long)t->halted_ns, (long long)t->clock_ns);
  w->clock_ns = t->clock_ns;
  w->halt = t->halt;
  w->halted_ns = t->halted_ns;
  w->calls = calls;
  w->last_call = t->last_call;
  return 0;
}

static int check_time_order(int64_t time_ns, int64_t *last, const char *what, uint32_t i, char *why,
                            size_t why_size) {
  if (time_ns < *last)
    FAIL("events[%u].time_ns (%s at %lld ns, before the one at %lld ns)", i, what, (long long)time_ns,
         (long long)*last);
  *last = time_ns;
  return 0;
}

int sear_link_check_event(const struct sear_link *link, uint32_t i, struct sear_link_watch *w,
                          struct sear_event *e, char *why, size_t why_size) {
  memcpy(e, &link->events[i], sizeof *e);
  const int64_t clock = w->clock_ns;
  switch (e->kind) {
    case SEAR_EVENT_PIN:
    case SEAR_EVENT_PIN_MODE:
    case SEAR_EVENT_PWM:
    case SEAR_EVENT_SERVO:
    case SEAR_EVENT_PIN_DRIVEN:
      if (e->index >= SEAR_LINK_PINS) FAIL("events[%u].index (pin %u; the board has 0..%d)", i, e->index, SEAR_LINK_PINS - 1);
      break;
    case SEAR_EVENT_UART_BEGIN:
    case SEAR_EVENT_UART_TX:
    case SEAR_EVENT_UART_RX:
      if (e->index >= SEAR_LINK_UARTS) FAIL("events[%u].index (port %u; the chip has 0..%d)", i, e->index, SEAR_LINK_UARTS - 1);
      break;
    case SEAR_EVENT_CAN_BEGIN:
    case SEAR_EVENT_CAN_TX:
    case SEAR_EVENT_CAN_DATA:
      break;
    default:
      FAIL("events[%u].kind (%u, not an event the HAL writes)", i, e->kind);
  }
  /* A frame's data follows its CAN_TX at once, in order, even across a drain. */
  if (w->can_data_due && (e->kind != SEAR_EVENT_CAN_DATA || e->index != 2 - w->can_data_due))
    FAIL("events[%u] (kind %u index %u where the data of a CAN frame was due)", i, e->kind, e->index);
  if (e->kind == SEAR_EVENT_CAN_DATA && !w->can_data_due)
    FAIL("events[%u] (CAN data with no frame before it)", i);
  if (e->kind == SEAR_EVENT_CAN_TX) {
    const unsigned dlc = e->index & 15u, flags = e->index >> 4;
    const uint32_t top = flags & SEAR_CAN_EXTENDED ? 0x1FFFFFFFu : 0x7FFu;
    if (dlc > 8 || flags > 3 || e->value > top)
      FAIL("events[%u] (a CAN frame with id 0x%x, dlc %u, flags %u)", i, e->value, dlc, flags);
    w->can_data_due = 2;
  } else if (e->kind == SEAR_EVENT_CAN_DATA) {
    w->can_data_due--;
  }
  if (e->kind == SEAR_EVENT_CAN_BEGIN && e->index != 0) FAIL("events[%u].index (%u, CAN has one controller)", i, e->index);
  const uint32_t v = e->value;
  if ((e->kind == SEAR_EVENT_PIN && v > 1) || (e->kind == SEAR_EVENT_PIN_MODE && v > 2) ||
      (e->kind == SEAR_EVENT_PIN_DRIVEN && v > 2) ||
      (e->kind == SEAR_EVENT_PWM && v > 255) || (e->kind == SEAR_EVENT_SERVO && v > 2600) ||
      (e->kind == SEAR_EVENT_UART_BEGIN && (v < 300 || v > 2000000)) ||
      (e->kind == SEAR_EVENT_CAN_BEGIN && (v < 10000 || v > 1000000)) ||
      ((e->kind == SEAR_EVENT_UART_TX || e->kind == SEAR_EVENT_UART_RX) && v > 255))
    FAIL("events[%u].value (%u, out of range for its kind %u)", i, v, e->kind);
  if (e->time_ns < 0) FAIL("events[%u].time_ns (%lld ns, negative)", i, (long long)e->time_ns);
  switch (e->kind) {
    case SEAR_EVENT_UART_TX:
      /* Stamped with the end of its stop bit: after the call that sent it, at most the whole
       * UART path ahead of the clock. */
      if (e->time_ns > clock + MAX_TX_AHEAD_NS)
        FAIL("events[%u].time_ns (a byte sent at %lld ns, further ahead of the clock at %lld ns than a UART holds)", i,
             (long long)e->time_ns, (long long)clock);
      return check_time_order(e->time_ns, &w->last_tx_ns[e->index], "a byte sent", i, why, why_size);
    case SEAR_EVENT_PIN_DRIVEN:
      /* A device's edge, made by the time the firmware's clock reached it (a sample's from the
       * quantum's start on, which may lie before the turn's first clock). */
      if (e->time_ns > clock)
        FAIL("events[%u].time_ns (a device's edge at %lld ns, after the clock at %lld ns)", i, (long long)e->time_ns,
             (long long)clock);
      return check_time_order(e->time_ns, &w->last_driven_ns, "a device's edge", i, why, why_size);
    case SEAR_EVENT_UART_RX:
      if (e->time_ns > clock)
        FAIL("events[%u].time_ns (a byte received at %lld ns, after the clock at %lld ns)", i, (long long)e->time_ns,
             (long long)clock);
      return check_time_order(e->time_ns, &w->last_rx_ns[e->index], "a byte received", i, why, why_size);
    default:
      /* Stamped with the time of the call, which lies within this turn. */
      if (e->time_ns < w->turn_clock_ns || e->time_ns > clock)
        FAIL("events[%u].time_ns (%lld ns, outside the turn from %lld to %lld ns)", i, (long long)e->time_ns,
             (long long)w->turn_clock_ns, (long long)clock);
      return check_time_order(e->time_ns, &w->last_event_ns, "an event", i, why, why_size);
  }
}

uint32_t sear_link_reading_values(uint32_t kind) {
  static const uint8_t counts[SEAR_INPUT_KIND_END] = {SEAR_LINK_READING_VALUES_BY_KIND};
  return kind < SEAR_INPUT_KIND_END ? counts[kind] : 0;
}

/* The widest a model's output can honestly be, by kind: outputs within the rails (with room for
 * an AVCC up to 10 V), levels 0 or 1, an echo no longer than the 38 ms of no echo, an encoder no
 * further than 1e12 counts (a shaft at 10^4 rad/s for a simulated year, at 10^4 counts per
 * cycle), accelerations and rates within 16 g and 2000 deg/s (the widest full scales), fields
 * within 18 G; a little beyond each for rounding. */
static int plausible(uint32_t kind, uint32_t k, double v) {
  switch (kind) {
    case SEAR_INPUT_GP2D12: return v >= 0.0 && v <= 10.0;
    case SEAR_INPUT_GP2D15:
    case SEAR_INPUT_SWITCH: return v == 0.0 || v == 1.0;
    case SEAR_INPUT_HCSR04: return v >= 0.0 && v <= (k == 0 ? 0.04 : 7.0);
    case SEAR_INPUT_MAXBOTIX: return v >= 0.0 && v <= (k == 0 ? 10.0 : 1000.0);
    case SEAR_INPUT_ENCODER: return fabs(v) <= 1e13 && (k != 0 || v == floor(v));
    case SEAR_INPUT_MPU6000:
    case SEAR_INPUT_MPU6050: return fabs(v) <= (k < 3 ? 16.1 * 9.80665 : 2001.0 * 3.14159265358979 / 180.0);
    case SEAR_INPUT_HMC5883L:
    case SEAR_INPUT_QMC5883L: return fabs(v) <= 1.8e-3; /* the HMC's overflow code, -4096, at 230 LSB/G */
    default: return 0;
  }
}

int sear_link_check_reading(const struct sear_link *link, uint32_t i, uint32_t kind, int64_t clock_ns,
                            struct sear_reading_watch *w, struct sear_link_reading *r, char *why,
                            size_t why_size) {
  if (i >= SEAR_LINK_MAX_INPUTS) FAIL("readings[%u] (no such input)", i);
  const uint32_t count = load32(&link->readings[i].count);
  if (count == w->count[i]) return 0;
  memcpy(r, &link->readings[i], sizeof *r);
  r->count = count;
  const uint32_t n = sear_link_reading_values(kind);
  if (!n) FAIL("readings[%u].count (%u, for an input whose kind %u gives no readings)", i, count, kind);
  if (r->time_ns < w->time_ns[i] || r->time_ns > clock_ns || r->time_ns < 0)
    FAIL("readings[%u].time_ns (%lld ns, outside %lld..%lld ns)", i, (long long)r->time_ns, (long long)w->time_ns[i],
         (long long)clock_ns);
  for (uint32_t k = 0; k < n; ++k)
    if (!isfinite(r->value[k]) || !plausible(kind, k, r->value[k]))
      FAIL("readings[%u].value[%u] (%g, not a reading input kind %u gives)", i, k, r->value[k], kind);
  w->count[i] = count;
  w->time_ns[i] = r->time_ns;
  return 1;
}
