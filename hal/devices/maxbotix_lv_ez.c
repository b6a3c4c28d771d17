/* LV-MaxSonar-EZ1: one reading per cycle, shown on PW, AN and TX on the datasheet's timing. */
#include "maxbotix_lv_ez.h"

#include <math.h>

#include "noise.h"

#define NONE INT64_MAX
#define METRES_PER_INCH 0.0254

int maxbotix_reading_inches(double distance_m, uint64_t seed, uint64_t k, double noise_sd_m) {
  if (!(distance_m >= 0.0) || isinf(distance_m)) return MAXBOTIX_NO_TARGET_INCHES;
  double d = distance_m;
  if (noise_sd_m > 0.0) d += noise_sd_m * noise_gaussian(seed, k);
  const double inches = floor(d / METRES_PER_INCH);
  if (inches > MAXBOTIX_MAX_INCHES) return MAXBOTIX_NO_TARGET_INCHES;
  if (inches < MAXBOTIX_MIN_INCHES) return MAXBOTIX_MIN_INCHES;
  return (int)inches;
}

int64_t maxbotix_cycle_start_ns(uint64_t k) {
  return MAXBOTIX_POWER_UP_NS + MAXBOTIX_CYCLE_NS + (int64_t)k * MAXBOTIX_CYCLE_NS;
}

size_t maxbotix_serial_frame(int inches, uint8_t out[5]) {
  if (inches < 0) inches = 0;
  if (inches > 255) inches = 255;
  out[0] = 'R';
  out[1] = (uint8_t)('0' + inches / 100);
  out[2] = (uint8_t)('0' + inches / 10 % 10);
  out[3] = (uint8_t)('0' + inches % 10);
  out[4] = '\r';
  return 5;
}

/* ---- schedule ---- */

void maxbotix_schedule_init(struct maxbotix_schedule *c) {
  c->boundary_ns = MAXBOTIX_POWER_UP_NS; /* not ready for RX before this */
  c->rx_rise_ns = 0;                     /* the internal pull-up holds RX high from power-up */
  c->rx_level = 1;
  c->calibrated = 0;
  c->next_k = 0;
}

void maxbotix_schedule_set_rx(struct maxbotix_schedule *c, int level, int64_t t_ns) {
  level = level != 0;
  if (level == c->rx_level) return;
  c->rx_level = level;
  if (level) c->rx_rise_ns = t_ns;
}

int64_t maxbotix_schedule_next_ns(const struct maxbotix_schedule *c, uint64_t *k) {
  if (k) *k = c->next_k;
  if (!c->rx_level) return NONE;
  /* High at the end-of-cycle check: the next cycle follows at once. Raised later, while idle:
   * it starts once RX has been high for 20 us. */
  int64_t start = c->rx_rise_ns <= c->boundary_ns ? c->boundary_ns : c->rx_rise_ns + MAXBOTIX_RX_COMMAND_NS;
  /* The first command after power-up runs the calibration cycle first, then the reading
   * without checking RX in between ("will first run a calibration cycle (49mS), and then it
   * will take a range reading"). */
  if (!c->calibrated) start += MAXBOTIX_CYCLE_NS;
  return start;
}

void maxbotix_schedule_take(struct maxbotix_schedule *c) {
  const int64_t start = maxbotix_schedule_next_ns(c, NULL);
  if (start == NONE) return;
  c->calibrated = 1;
  c->boundary_ns = start + MAXBOTIX_CYCLE_NS;
  c->next_k++;
}

/* ---- PW and AN, in the firmware's process ---- */

void maxbotix_lv_ez_init(struct maxbotix_lv_ez *s) {
  maxbotix_schedule_init(&s->schedule);
  s->pw_level = 0;
  s->pw_rise_ns = s->pw_fall_ns = NONE;
  s->an_from_inches = s->an_to_inches = 0;
  s->an_ramp_start_ns = s->an_ramp_end_ns = 0;
}

void maxbotix_lv_ez_set_rx_level(struct maxbotix_lv_ez *s, int level, int64_t t_ns) {
  maxbotix_schedule_set_rx(&s->schedule, level, t_ns);
}

int64_t maxbotix_lv_ez_next_cycle_ns(const struct maxbotix_lv_ez *s, uint64_t *k) {
  return maxbotix_schedule_next_ns(&s->schedule, k);
}

/* Inches shown on AN at t: the ramp of the latest reading, or where it started. */
static double analog_inches(const struct maxbotix_lv_ez *s, int64_t t_ns) {
  if (t_ns <= s->an_ramp_start_ns) return s->an_from_inches;
  if (t_ns >= s->an_ramp_end_ns) return s->an_to_inches;
  const double f = (double)(t_ns - s->an_ramp_start_ns) / (double)(s->an_ramp_end_ns - s->an_ramp_start_ns);
  return s->an_from_inches + f * (s->an_to_inches - s->an_from_inches);
}

int maxbotix_lv_ez_shown_inches(const struct maxbotix_lv_ez *s, int64_t t_ns) {
  return t_ns >= s->an_ramp_end_ns ? s->an_to_inches : s->an_from_inches;
}

void maxbotix_lv_ez_take_reading(struct maxbotix_lv_ez *s, int inches, int64_t t_cycle_ns) {
  maxbotix_schedule_take(&s->schedule);
  if (inches < 0) inches = 0;
  if (inches > MAXBOTIX_NO_TARGET_INCHES) inches = MAXBOTIX_NO_TARGET_INCHES;
  /* A PW pulse still pending (cycles never overlap, so only if the caller skipped edges) is
   * finished first: the pin goes low before the new burst. */
  s->pw_rise_ns = t_cycle_ns + MAXBOTIX_PW_RISE_NS;
  s->pw_fall_ns = s->pw_rise_ns + (int64_t)inches * MAXBOTIX_PW_NS_PER_INCH;
  /* The ramp starts from wherever AN stands when it starts (the previous reading by then). */
  const double shown = analog_inches(s, t_cycle_ns + MAXBOTIX_AN_RAMP_START_NS);
  s->an_from_inches = (int)lround(shown);
  s->an_to_inches = inches;
  s->an_ramp_start_ns = t_cycle_ns + MAXBOTIX_AN_RAMP_START_NS;
  s->an_ramp_end_ns = t_cycle_ns + MAXBOTIX_AN_RAMP_END_NS;
}

int64_t maxbotix_lv_ez_next_edge_ns(const struct maxbotix_lv_ez *s) {
  if (s->pw_level) return s->pw_fall_ns;
  return s->pw_rise_ns;
}

int maxbotix_lv_ez_take_edge(struct maxbotix_lv_ez *s) {
  if (s->pw_level) {
    if (s->pw_fall_ns != NONE) {
      s->pw_level = 0;
      s->pw_fall_ns = NONE;
    }
  } else if (s->pw_rise_ns != NONE) {
    s->pw_level = 1;
    s->pw_rise_ns = NONE;
  }
  return s->pw_level;
}

double maxbotix_lv_ez_analog_v(const struct maxbotix_lv_ez *s, int64_t t_ns, double vcc_v) {
  return analog_inches(s, t_ns) * vcc_v / MAXBOTIX_AN_STEPS_PER_VCC;
}

/* ---- TX, in the simulator's process ---- */

void maxbotix_lv_ez_serial_init(struct maxbotix_lv_ez_serial *s, uint64_t seed, double noise_sd_m) {
  maxbotix_schedule_init(&s->schedule);
  s->seed = seed;
  s->noise_sd_m = noise_sd_m;
  s->distance_m = INFINITY;
  s->distance_t_ns = INT64_MIN;
  s->frame_count = 0;
  s->next_byte = 0;
}

void maxbotix_lv_ez_serial_set_distance(struct maxbotix_lv_ez_serial *s, double distance_m, int64_t t_ns) {
  s->distance_m = distance_m;
  s->distance_t_ns = t_ns;
  for (int f = 0; f < s->frame_count; ++f) {
    if (f == 0 && s->next_byte > 0) continue; /* already on the line */
    if (t_ns > s->frame_cycle_ns[f] || t_ns < s->frame_distance_t_ns[f]) continue;
    const int inches = maxbotix_reading_inches(distance_m, s->seed, s->frame_k[f], s->noise_sd_m);
    maxbotix_serial_frame(inches, s->frame[f]);
    s->frame_distance_t_ns[f] = t_ns;
  }
}

void maxbotix_lv_ez_serial_set_rx_level(struct maxbotix_lv_ez_serial *s, int level, int64_t t_ns) {
  maxbotix_schedule_set_rx(&s->schedule, level, t_ns);
}

static int64_t byte_end_ns(const struct maxbotix_lv_ez_serial *s, int i) {
  return s->frame_start_ns[0] + (int64_t)(i + 1) * serial_frame_ns(MAXBOTIX_BAUD);
}

size_t maxbotix_lv_ez_serial_transmit(struct maxbotix_lv_ez_serial *s, int64_t now_ns, int64_t until_ns,
                                      struct serial_byte *out, size_t cap) {
  (void)now_ns; /* bytes go out at the part's own times; a frame in flight at now_ns started earlier */
  size_t n = 0;
  for (;;) {
    /* Measure every cycle that has started, so its reading uses the distance of its start. */
    uint64_t k;
    const int64_t start = maxbotix_schedule_next_ns(&s->schedule, &k);
    if (start < until_ns && s->frame_count < 2) {
      maxbotix_schedule_take(&s->schedule);
      const int inches = maxbotix_reading_inches(s->distance_m, s->seed, k, s->noise_sd_m);
      const int f = s->frame_count++;
      maxbotix_serial_frame(inches, s->frame[f]);
      s->frame_start_ns[f] = start + MAXBOTIX_SERIAL_START_NS;
      s->frame_cycle_ns[f] = start;
      s->frame_k[f] = k;
      s->frame_distance_t_ns[f] = s->distance_t_ns;
      continue;
    }
    if (s->frame_count == 0 || n == cap) break;
    const int64_t end = byte_end_ns(s, s->next_byte);
    if (end >= until_ns) break;
    out[n].end_ns = end;
    out[n].baud = MAXBOTIX_BAUD;
    out[n].value = s->frame[0][s->next_byte];
    out[n].reserved[0] = out[n].reserved[1] = out[n].reserved[2] = 0;
    n++;
    if (++s->next_byte == 5) {
      s->next_byte = 0;
      s->frame_count--;
      if (s->frame_count) {
        for (int i = 0; i < 5; ++i) s->frame[0][i] = s->frame[1][i];
        s->frame_start_ns[0] = s->frame_start_ns[1];
        s->frame_cycle_ns[0] = s->frame_cycle_ns[1];
        s->frame_k[0] = s->frame_k[1];
        s->frame_distance_t_ns[0] = s->frame_distance_t_ns[1];
      }
    }
  }
  return n;
}
