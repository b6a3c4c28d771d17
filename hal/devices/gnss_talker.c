/* The GPS talkers' shared epoch schedule, transmit loop and command-line assembly. */
#include "gnss_talker.h"

#include <string.h>

/* The first epoch on the period's grid after utc_ms. */
static int64_t next_on_grid(int64_t utc_ms, int64_t period_ms) { return (utc_ms / period_ms + 1) * period_ms; }

void gnss_talker_init(struct gnss_talker *g, int64_t power_on_ns, int64_t boot_ns, int64_t utc_start_s,
                      double rate_hz) {
  memset(g, 0, sizeof *g);
  g->power_on_ns = g->start_ns = power_on_ns;
  g->boot_ns = boot_ns;
  g->utc_start_ms = utc_start_s * 1000;
  double hz = rate_hz;
  if (!(hz >= 1.0)) hz = 1.0;
  if (hz > 10.0) hz = 10.0;
  g->period_ms = (int64_t)(1000.0 / hz + 0.5);
  g->next_epoch_ms = next_on_grid(g->utc_start_ms + boot_ns / 1000000, g->period_ms);
}

int64_t gnss_talker_epoch_ns(const struct gnss_talker *g, int64_t utc_ms) {
  return g->power_on_ns + (utc_ms - g->utc_start_ms) * 1000000;
}

void gnss_talker_set_period(struct gnss_talker *g, int64_t period_ms, int64_t t_ns) {
  g->period_ms = period_ms;
  const int64_t now_ms = g->utc_start_ms + (t_ns - g->power_on_ns) / 1000000;
  g->next_epoch_ms = next_on_grid(g->booted ? now_ms : g->utc_start_ms + g->boot_ns / 1000000, period_ms);
}

int gnss_talker_due(const struct gnss_talker *g, uint8_t rate) { return rate && g->epoch_count % rate == 0; }

static int64_t next_scheduled_ns(const struct gnss_talker *g) {
  return g->booted ? gnss_talker_epoch_ns(g, g->next_epoch_ms) : g->power_on_ns + g->boot_ns;
}

static int64_t next_event_ns(const struct gnss_talker *g) {
  const int64_t t = next_scheduled_ns(g);
  return g->output_pending && g->output_ns <= t ? g->output_ns : t;
}

static void run_event(struct gnss_talker *g, const struct gnss_talker_events *ev, void *talker) {
  if (g->output_pending && g->output_ns <= next_scheduled_ns(g)) {
    g->output_pending = 0;
    g->output(talker);
    return;
  }
  if (!g->booted) {
    g->booted = 1;
    ev->boot(talker);
    return;
  }
  ev->epoch(talker);
  if (g->output) {
    g->output_pending = 1;
    g->output_ns = gnss_talker_epoch_ns(g, g->next_epoch_ms) + g->output_delay_ns;
  }
  ++g->epoch_count;
  g->next_epoch_ms += g->period_ms;
}

void gnss_talker_catch_up(struct gnss_talker *g, const struct gnss_talker_events *ev, void *talker, int64_t t_ns) {
  while (next_event_ns(g) <= t_ns) run_event(g, ev, talker);
}

size_t gnss_talker_transmit(struct gnss_talker *g, const struct gnss_talker_events *ev, void *talker,
                            struct nmea_tx *tx, int64_t now_ns, int64_t until_ns, struct serial_byte *out,
                            size_t cap) {
  nmea_tx_window(tx, now_ns, until_ns);
  size_t n = nmea_tx_take(tx, out, cap);
  while (n < cap && next_event_ns(g) < until_ns) {
    run_event(g, ev, talker);
    n += nmea_tx_take(tx, out + n, cap - n);
  }
  return n;
}

int gnss_baud_listed(const uint32_t *bauds, size_t count, uint32_t baud) {
  for (size_t i = 0; i < count; ++i)
    if (bauds[i] == baud) return 1;
  return 0;
}

size_t gnss_line_byte(char *line, size_t *len, size_t max, char c, char *body) {
  if (c == '$') *len = 0;
  if (*len >= max - 1) {
    *len = 0;
    return 0;
  }
  line[(*len)++] = c;
  if (c != '\n') return 0;
  const char *framed;
  size_t n = 0;
  if (line[0] == '$' && nmea_parse_frame(line, *len, &framed, &n)) {
    memcpy(body, framed, n);
    body[n] = '\0';
  }
  *len = 0;
  return n;
}

int gnss_split_fields(char *body, char **fields, int max) {
  int n = 0;
  fields[n++] = body;
  for (char *c = body; *c && n < max; ++c)
    if (*c == ',') {
      *c = '\0';
      fields[n++] = c + 1;
    }
  return n;
}
