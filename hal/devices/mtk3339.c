/* MT3339 talker: epochs on the UTC grid, the MTK NMEA cycle, and the PMTK command parser. */
#include "mtk3339.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const uint32_t bauds[] = {4800, 9600, 14400, 19200, 38400, 57600, 115200};

static int baud_ok(uint32_t b) {
  for (size_t i = 0; i < sizeof bauds / sizeof bauds[0]; ++i)
    if (bauds[i] == b) return 1;
  return 0;
}

static const struct nmea_style style = {3, 4, 2, 0, 1};

/* Before its first fix an MT3339 without backup power counts from its RTC's reset value, the
 * GPS epoch 1980-01-06 00:00:00, which is what its RMC shows as "060180". */
#define RTC_RESET_S INT64_C(315964800)

void mtk3339_defaults(struct mtk3339_config *c) {
  c->rate_hz = 1.0;
  c->baud = MTK_DEFAULT_BAUD;
  c->utc_start_s = nmea_unix_s(2026, 1, 1, 0, 0, 0);
  gnss_error_defaults(&c->error);
  c->error.ttff_s = 35.0; /* PA6H datasheet, TTFF: cold start 35 s */
}

/* Default output: RMC VTG GGA GSA every fix, GSV every fifth (our reading of the PA6H
 * datasheet's default NMEA output); GLL and ZDA off. */
static void default_rates(struct mtk3339 *s) {
  memset(s->rate, 0, sizeof s->rate);
  s->rate[MTK_RMC] = s->rate[MTK_VTG] = s->rate[MTK_GGA] = s->rate[MTK_GSA] = 1;
  s->rate[MTK_GSV] = 5;
}

static int64_t epoch_ns(const struct mtk3339 *s, int64_t utc_ms) {
  return s->power_on_ns + (utc_ms - s->utc_start_ms) * 1000000;
}

static int64_t next_on_grid(int64_t utc_ms, int64_t period_ms) { return (utc_ms / period_ms + 1) * period_ms; }

void mtk3339_init(struct mtk3339 *s, const struct mtk3339_config *c, struct gnss_truth_source src, int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->src = src;
  gnss_error_init(&s->error, &c->error);
  nmea_tx_init(&s->tx, baud_ok(c->baud) ? c->baud : MTK_DEFAULT_BAUD, MTK_TX_BUFFER);
  s->power_on_ns = s->start_ns = power_on_ns;
  s->utc_start_ms = c->utc_start_s * 1000;
  double hz = c->rate_hz;
  if (!(hz >= 1.0)) hz = 1.0;
  if (hz > 10.0) hz = 10.0;
  s->period_ms = (int64_t)(1000.0 / hz + 0.5);
  s->next_epoch_ms = next_on_grid(s->utc_start_ms + MTK_BOOT_NS / 1000000, s->period_ms);
  default_rates(s);
}

uint32_t mtk3339_baud(const struct mtk3339 *s) { return s->tx.baud; }

static void send(struct mtk3339 *s, int64_t ready, const char *text, size_t n, int force) {
  if (n) nmea_tx_queue(&s->tx, ready, text, n, force);
}

static void say(struct mtk3339 *s, int64_t ready, const char *body) {
  char text[NMEA_MAX_SENTENCE + 1];
  send(s, ready, text, nmea_finish(text, sizeof text, body), 1);
}

static void epoch(struct mtk3339 *s) {
  const int64_t t = epoch_ns(s, s->next_epoch_ms);
  const int fix = gnss_error_has_fix(&s->error, t - s->start_ns);
  const int64_t shown_ms = fix ? s->next_epoch_ms : s->next_epoch_ms - s->utc_start_ms + RTC_RESET_S * 1000;
  struct nmea_solution f;
  nmea_solve(&f, &s->error, s->src, t, s->power_on_ns, s->start_ns, shown_ms, 1);
  const int64_t ready = t + MTK_OUTPUT_DELAY_NS;
  char text[NMEA_MAX_SENTENCE + 1];
  const uint64_t k = s->epoch_count;
#define DUE(id) (s->rate[id] && k % s->rate[id] == 0)
  /* The order MTK firmware prints in. */
  if (DUE(MTK_GGA)) send(s, ready, text, nmea_gga(text, sizeof text, &style, &f), 0);
  if (DUE(MTK_GLL)) send(s, ready, text, nmea_gll(text, sizeof text, &style, &f), 0);
  if (DUE(MTK_GSA)) send(s, ready, text, nmea_gsa(text, sizeof text, &style, &f), 0);
  if (DUE(MTK_GSV))
    for (int i = 0; i < nmea_gsv_count(&f); ++i) send(s, ready, text, nmea_gsv(text, sizeof text, &f, i), 0);
  if (DUE(MTK_RMC)) send(s, ready, text, nmea_rmc(text, sizeof text, &style, &f), 0);
  if (DUE(MTK_VTG)) send(s, ready, text, nmea_vtg(text, sizeof text, &style, &f), 0);
  if (DUE(MTK_ZDA)) send(s, ready, text, nmea_zda(text, sizeof text, &style, &f), 0);
#undef DUE
  ++s->epoch_count;
  s->next_epoch_ms += s->period_ms;
}

static int64_t next_event_ns(const struct mtk3339 *s) {
  return s->booted ? epoch_ns(s, s->next_epoch_ms) : s->power_on_ns + MTK_BOOT_NS;
}

static void run_event(struct mtk3339 *s) {
  if (s->booted) {
    epoch(s);
    return;
  }
  s->booted = 1;
  say(s, s->power_on_ns + MTK_BOOT_NS, "PMTK011,MTKGPS");
  say(s, s->power_on_ns + MTK_BOOT_NS, "PMTK010,001"); /* system message: startup */
}

size_t mtk3339_transmit(struct mtk3339 *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out, size_t cap) {
  nmea_tx_window(&s->tx, now_ns, until_ns);
  size_t n = nmea_tx_take(&s->tx, out, cap);
  while (n < cap && next_event_ns(s) < until_ns) {
    run_event(s);
    n += nmea_tx_take(&s->tx, out + n, cap - n);
  }
  return n;
}

/* ---- PMTK commands (MTK NMEA packet user manual) ---- */

static void ack(struct mtk3339 *s, int64_t t, int command, int flag) {
  char body[32];
  snprintf(body, sizeof body, "PMTK001,%d,%d", command, flag); /* 0 invalid, 1 unsupported, 2 failed, 3 done */
  say(s, t + MTK_REPLY_DELAY_NS, body);
  ++s->acks;
}

static int number(const char *f, long lo, long hi, long *v) {
  if (!*f) return 0;
  char *end;
  *v = strtol(f, &end, 10);
  return *end == '\0' && *v >= lo && *v <= hi;
}

static void pmtk(struct mtk3339 *s, char *body, int64_t t) {
  char *f[24];
  int n = 0;
  f[n++] = body;
  for (char *c = body; *c && n < 24; ++c)
    if (*c == ',') {
      *c = '\0';
      f[n++] = c + 1;
    }
  long command;
  if (!number(f[0] + 4, 0, 999, &command)) return;
  long v;
  switch (command) {
    case 220: /* fix interval, ms */
      if (n != 2 || !number(f[1], 0, 100000, &v)) {
        ack(s, t, 220, 0);
      } else if (v < 100 || v > 10000) {
        ack(s, t, 220, 2);
      } else {
        s->period_ms = v;
        const int64_t now_ms = s->utc_start_ms + (t - s->power_on_ns) / 1000000;
        s->next_epoch_ms = next_on_grid(s->booted ? now_ms : s->utc_start_ms + MTK_BOOT_NS / 1000000, v);
        ack(s, t, 220, 3);
      }
      return;
    case 314: { /* sentence rates: every n-th fix, 0 off */
      if (n == 2 && strcmp(f[1], "-1") == 0) {
        default_rates(s);
        ack(s, t, 314, 3);
        return;
      }
      uint8_t r[MTK_NMEA_IDS] = {0};
      if (n < 2 || n > 21) {
        ack(s, t, 314, 0);
        return;
      }
      for (int i = 1; i < n; ++i) {
        if (!number(f[i], 0, 5, &v)) {
          ack(s, t, 314, 0);
          return;
        }
        if (i - 1 < MTK_NMEA_IDS) r[i - 1] = (uint8_t)v;
      }
      memcpy(s->rate, r, sizeof r);
      ack(s, t, 314, 3);
      return;
    }
    case 251: /* baud: no acknowledgement, the port simply switches after what is queued */
      if (n == 2 && number(f[1], 0, 115200, &v) && (v == 0 || baud_ok((uint32_t)v)))
        s->tx.baud = v == 0 ? MTK_DEFAULT_BAUD : (uint32_t)v;
      return;
    case 101: case 102: case 103: case 104: { /* hot, warm, cold, full cold restart */
      const double ttff_s = s->error.config.ttff_s;
      const double wanted_s = command == 101 && MTK_HOT_START_TTFF_S < ttff_s ? MTK_HOT_START_TTFF_S : ttff_s;
      /* The fix comes wanted_s after the restart: start_ns is where ttff_s would end then. */
      s->start_ns = t + (int64_t)((wanted_s - ttff_s) * 1e9);
      if (command == 104) default_rates(s); /* full cold start: factory settings too */
      say(s, t + MTK_BOOT_NS, "PMTK010,001");
      return;
    }
    case 605: /* firmware query */
      say(s, t + MTK_REPLY_DELAY_NS, "PMTK705,AXN_2.10_3339_2012072601,5223,PA6H,1.0");
      return;
    default:
      ack(s, t, (int)command, 1);
      return;
  }
}

void mtk3339_receive(struct mtk3339 *s, const struct serial_byte *b) {
  while (next_event_ns(s) <= b->end_ns) run_event(s);
  if (b->baud != s->tx.baud) {
    s->line_len = 0;
    return;
  }
  const char c = (char)b->value;
  if (c == '$') s->line_len = 0;
  if (s->line_len >= MTK_MAX_LINE - 1) {
    s->line_len = 0;
    return;
  }
  s->line[s->line_len++] = c;
  if (c != '\n') return;
  const char *body;
  size_t n;
  if (s->line[0] == '$' && nmea_parse_frame(s->line, s->line_len, &body, &n) && n > 4 &&
      strncmp(body, "PMTK", 4) == 0) {
    char text[MTK_MAX_LINE];
    memcpy(text, body, n);
    text[n] = '\0';
    pmtk(s, text, b->end_ns);
  }
  s->line_len = 0;
}
