/* MT3339 talker: epochs on the UTC grid, the MTK NMEA cycle, and the PMTK command parser. */
#include "mtk3339.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const uint32_t bauds[] = {4800, 9600, 14400, 19200, 38400, 57600, 115200};

static int baud_ok(uint32_t b) { return gnss_baud_listed(bauds, sizeof bauds / sizeof bauds[0], b); }

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

void mtk3339_init(struct mtk3339 *s, const struct mtk3339_config *c, struct gnss_truth_source src, int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->src = src;
  gnss_error_init(&s->error, &c->error);
  nmea_tx_init(&s->tx, baud_ok(c->baud) ? c->baud : MTK_DEFAULT_BAUD, MTK_TX_BUFFER);
  gnss_talker_init(&s->talker, power_on_ns, MTK_BOOT_NS, c->utc_start_s, c->rate_hz);
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

static void epoch(void *talker) {
  struct mtk3339 *s = talker;
  const struct gnss_talker *g = &s->talker;
  const int64_t t = gnss_talker_epoch_ns(g, g->next_epoch_ms);
  const int fix = gnss_error_has_fix(&s->error, t - g->start_ns);
  const int64_t shown_ms = fix ? g->next_epoch_ms : g->next_epoch_ms - g->utc_start_ms + RTC_RESET_S * 1000;
  struct nmea_solution f;
  nmea_solve(&f, &s->error, s->src, t, g->power_on_ns, g->start_ns, shown_ms, 1);
  const int64_t ready = t + MTK_OUTPUT_DELAY_NS;
  char text[NMEA_MAX_SENTENCE + 1];
#define DUE(id) gnss_talker_due(g, s->rate[id])
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
}

static void boot(void *talker) {
  struct mtk3339 *s = talker;
  const int64_t t = s->talker.power_on_ns + MTK_BOOT_NS;
  say(s, t, "PMTK011,MTKGPS");
  say(s, t, "PMTK010,001"); /* system message: startup */
}

static const struct gnss_talker_events events = {boot, epoch};

size_t mtk3339_transmit(struct mtk3339 *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out, size_t cap) {
  return gnss_talker_transmit(&s->talker, &events, s, &s->tx, now_ns, until_ns, out, cap);
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
  const int n = gnss_split_fields(body, f, 24);
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
        gnss_talker_set_period(&s->talker, v, t);
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
      s->talker.start_ns = t + (int64_t)((wanted_s - ttff_s) * 1e9);
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
  gnss_talker_catch_up(&s->talker, &events, s, b->end_ns);
  if (b->baud != s->tx.baud) {
    s->line_len = 0;
    return;
  }
  char text[MTK_MAX_LINE];
  if (gnss_line_byte(s->line, &s->line_len, MTK_MAX_LINE, (char)b->value, text) > 4 && strncmp(text, "PMTK", 4) == 0)
    pmtk(s, text, b->end_ns);
}
