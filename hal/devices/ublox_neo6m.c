/* NEO-6M talker: the epoch schedule on the UTC grid, the NMEA cycle and the UBX NAV messages of
 * each epoch from one solution, the UBX/PUBX input parsers, polls and ACK-ACK / ACK-NAK answers. */
#include "ublox_neo6m.h"

#include <stdlib.h>
#include <string.h>

#include "ubx_cfg.h"

#define UBX_SYNC1 0xB5
#define UBX_SYNC2 0x62
#define MON_VER 0x04

/* The banner a NEO-6M with firmware 7.03 prints at power-up (as logged from real modules). */
static const char *const banner[] = {
    "GPTXT,01,01,02,u-blox ag - www.u-blox.com",
    "GPTXT,01,01,02,HW  UBX-G60xx  00040007 FF7FFFFFp",
    "GPTXT,01,01,02,ROM CORE 7.03 (45969) Mar 17 2011 16:18:34",
    "GPTXT,01,01,02,ANTSUPERV=AC SD PDoS SR",
    "GPTXT,01,01,02,ANTSTATUS=DONTKNOW",
};

/* MON-VER of the same module: swVersion CH[30], hwVersion CH[10], then one 30-character block
 * holding the ROM version (the u-blox 6 spec's romVersion; drivers that read u-blox 7's layout
 * take it as the first extension string). NUL-padded. */
static const char mon_sw[] = "7.03 (45969)";
static const char mon_hw[] = "00040007";
#define MON_VER_LEN 70

static const struct nmea_style style = {2, 5, 3, 1, 0};

size_t ubx_frame(uint8_t cls, uint8_t id, const uint8_t *payload, uint16_t len, uint8_t *out) {
  out[0] = UBX_SYNC1;
  out[1] = UBX_SYNC2;
  out[2] = cls;
  out[3] = id;
  out[4] = (uint8_t)(len & 0xFF);
  out[5] = (uint8_t)(len >> 8);
  if (len) memcpy(out + 6, payload, len);
  uint8_t a = 0, b = 0;
  for (size_t i = 2; i < (size_t)len + 6; ++i) {
    a = (uint8_t)(a + out[i]);
    b = (uint8_t)(b + a);
  }
  out[len + 6] = a;
  out[len + 7] = b;
  return (size_t)len + 8;
}

static void output(void *talker);

void ublox_neo6m_defaults(struct ublox_neo6m_config *c) {
  c->rate_hz = 1.0;
  c->baud = UBLOX_DEFAULT_BAUD;
  c->utc_start_s = nmea_unix_s(2026, 1, 1, 0, 0, 0);
  gnss_error_defaults(&c->error);
}

void ublox_neo6m_init(struct ublox_neo6m *s, const struct ublox_neo6m_config *c, struct gnss_truth_source src,
                      int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->src = src;
  gnss_error_init(&s->error, &c->error);
  nmea_tx_init(&s->tx, ubx_cfg_baud_ok(c->baud) ? c->baud : UBLOX_DEFAULT_BAUD, UBLOX_TX_BUFFER);
  gnss_talker_init(&s->talker, power_on_ns, UBLOX_BOOT_NS, c->utc_start_s, c->rate_hz);
  s->time_ref = 1; /* u-blox 6 default: measurements aligned to GPS time */
  /* Factory default (u-blox 6 spec, CFG-MSG): GGA GLL GSA GSV RMC VTG on, the rest off, and no
   * UBX output until a driver asks for it. */
  for (int i = UBLOX_GGA; i <= UBLOX_VTG; ++i) s->rate[i] = 1;
  s->in_proto = UBX_PROTO_UBX | UBX_PROTO_NMEA;
  s->out_proto = UBX_PROTO_UBX | UBX_PROTO_NMEA;
  s->port_mode = UBX_MODE_8N1;
  ubx_cfg_defaults(s);
  s->talker.output = output;
  s->talker.output_delay_ns = UBLOX_OUTPUT_DELAY_NS;
}

uint32_t ublox_neo6m_baud(const struct ublox_neo6m *s) { return s->tx.baud; }

static void send_nmea(struct ublox_neo6m *s, int64_t ready, const char *text, size_t n) {
  if (n && (s->out_proto & UBX_PROTO_NMEA)) nmea_tx_queue(&s->tx, ready, text, n, 0);
}

/* A UBX message: periodic output (force 0) shares the output buffer with the NMEA sentences and
 * is dropped whole when it does not fit; answers to commands are forced. */
static void send_ubx(struct ublox_neo6m *s, int64_t ready, uint8_t cls, uint8_t id, const uint8_t *payload,
                     uint16_t len, int force) {
  if (!(s->out_proto & UBX_PROTO_UBX)) return;
  uint8_t frame[UBLOX_MAX_OUT_PAYLOAD + 8];
  const size_t n = ubx_frame(cls, id, payload, len, frame);
  nmea_tx_queue(&s->tx, ready, frame, n, force);
}

void ublox_neo6m_reply(struct ublox_neo6m *s, int64_t t, uint8_t cls, uint8_t id, const uint8_t *payload,
                       uint16_t len) {
  send_ubx(s, t + UBLOX_REPLY_DELAY_NS, cls, id, payload, len, 1);
}

void ublox_neo6m_acknowledge(struct ublox_neo6m *s, int64_t t, int ok) {
  const uint8_t which[2] = {s->ubx_class, s->ubx_id};
  ublox_neo6m_reply(s, t, UBX_CLASS_ACK, ok ? 0x01 : 0x00, which, 2);
  if (ok) ++s->acks;
  else ++s->naks;
}

/* What the NAV messages will say about the epoch at t whose solution is f. */
static void fill_epoch(struct ublox_neo6m *s, struct ubx_epoch *e, const struct nmea_solution *f, int64_t t) {
  const struct gnss_talker *g = &s->talker;
  e->fix = *f;
  ubx_gps_time(g->next_epoch_ms, &e->week, &e->itow_ms);
  const int64_t since_ms = (t - g->power_on_ns) / 1000000;
  e->msss = (uint32_t)(since_ms & 0xFFFFFFFF);
  if (f->valid && s->ttff_ms == 0) s->ttff_ms = (uint32_t)((t - g->start_ns) / 1000000);
  e->ttff_ms = s->ttff_ms;
  /* Accuracy estimates from the error model: horizontal RMS (HDOP x UERE, sqrt 2 of the per-axis
   * sigma), vertical sigma, 3D speed RMS (sqrt 3 of the per-axis sigma). */
  e->h_acc_m = 1.4142135623730951 * s->error.sigma_horizontal_m;
  e->v_acc_m = s->error.sigma_vertical_m;
  e->s_acc_mps = 1.7320508075688772 * s->error.config.velocity_sd_mps;
  e->sbas_enabled = s->sbas[0] & 1;
}

static void send_nav(struct ublox_neo6m *s, int64_t ready, enum ubx_nav_msg m, int force) {
  uint8_t payload[UBX_NAV_MAX_PAYLOAD];
  const uint16_t n = ubx_nav_payload(m, &s->last, payload);
  send_ubx(s, ready, UBX_CLASS_NAV, ubx_nav_id(m), payload, n, force);
}

/* The measurement: the solution at the epoch, kept for its output event. */
static void epoch(void *talker) {
  struct ublox_neo6m *s = talker;
  const struct gnss_talker *g = &s->talker;
  const int64_t t = gnss_talker_epoch_ns(g, g->next_epoch_ms);
  struct nmea_solution f;
  nmea_solve(&f, &s->error, s->src, t, g->power_on_ns, g->start_ns, g->next_epoch_ms, 0);
  fill_epoch(s, &s->pending, &f, t);
  s->pending_count = g->epoch_count;
}

static int due(const struct ublox_neo6m *s, uint8_t rate) { return rate && s->pending_count % rate == 0; }

/* UBLOX_OUTPUT_DELAY_NS later: the epoch's UBX messages first, in message-id order, then its NMEA
 * set, all from the one solution. */
static void output(void *talker) {
  struct ublox_neo6m *s = talker;
  const int64_t ready = s->talker.output_ns;
  s->last = s->pending;
  s->has_output = 1;
  const struct nmea_solution *f = &s->last.fix;
  for (int m = 0; m < UBX_NAV_MSGS; ++m)
    if (due(s, s->nav_rate[m])) send_nav(s, ready, (enum ubx_nav_msg)m, 0);
  char text[NMEA_MAX_SENTENCE + 1];
  /* The order a NEO-6M prints its default set in. */
  if (due(s, s->rate[UBLOX_RMC])) send_nmea(s, ready, text, nmea_rmc(text, sizeof text, &style, f));
  if (due(s, s->rate[UBLOX_VTG])) send_nmea(s, ready, text, nmea_vtg(text, sizeof text, &style, f));
  if (due(s, s->rate[UBLOX_GGA])) send_nmea(s, ready, text, nmea_gga(text, sizeof text, &style, f));
  if (due(s, s->rate[UBLOX_GSA])) send_nmea(s, ready, text, nmea_gsa(text, sizeof text, &style, f));
  if (due(s, s->rate[UBLOX_GSV]))
    for (int i = 0; i < nmea_gsv_count(f); ++i) send_nmea(s, ready, text, nmea_gsv(text, sizeof text, f, i));
  if (due(s, s->rate[UBLOX_GLL])) send_nmea(s, ready, text, nmea_gll(text, sizeof text, &style, f));
  if (due(s, s->rate[UBLOX_ZDA])) send_nmea(s, ready, text, nmea_zda(text, sizeof text, &style, f));
}

static void boot(void *talker) {
  struct ublox_neo6m *s = talker;
  char text[NMEA_MAX_SENTENCE + 1];
  for (size_t i = 0; i < sizeof banner / sizeof banner[0]; ++i) {
    const size_t n = nmea_finish(text, sizeof text, banner[i]);
    nmea_tx_queue(&s->tx, s->talker.power_on_ns + UBLOX_BOOT_NS, text, n, 1);
  }
}

static const struct gnss_talker_events events = {boot, epoch};

size_t ublox_neo6m_transmit(struct ublox_neo6m *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out,
                            size_t cap) {
  return gnss_talker_transmit(&s->talker, &events, s, &s->tx, now_ns, until_ns, out, cap);
}

/* ---- UBX input ---- */

/* A poll (empty payload) of MON-VER or of a NAV message; the NAV answer is the latest epoch's
 * (before the first epoch, the receiver has none and stays silent). */
static void poll(struct ublox_neo6m *s, int64_t t) {
  if (s->ubx_len != 0) return;
  if (s->ubx_class == UBX_CLASS_MON && s->ubx_id == MON_VER) {
    uint8_t p[MON_VER_LEN];
    memset(p, 0, sizeof p);
    memcpy(p, mon_sw, sizeof mon_sw);
    memcpy(p + 30, mon_hw, sizeof mon_hw);
    memcpy(p + 40, mon_sw, sizeof mon_sw);
    ublox_neo6m_reply(s, t, UBX_CLASS_MON, MON_VER, p, MON_VER_LEN);
  } else if (s->ubx_class == UBX_CLASS_NAV && ubx_nav_index(s->ubx_id) >= 0 && s->has_output) {
    send_nav(s, t + UBLOX_REPLY_DELAY_NS, (enum ubx_nav_msg)ubx_nav_index(s->ubx_id), 1);
  }
}

static void ubx_message(struct ublox_neo6m *s, int64_t t) {
  if (!(s->in_proto & UBX_PROTO_UBX)) return;
  if (s->ubx_class != UBX_CLASS_CFG) { /* only CFG is acknowledged; other classes answer polls */
    poll(s, t);
    return;
  }
  const int ok = ubx_cfg(s, t);
  if (ok >= 0) ublox_neo6m_acknowledge(s, t, ok);
}

static void ubx_byte(struct ublox_neo6m *s, uint8_t c, int64_t t) {
  if (s->ubx_state >= 2 && s->ubx_state <= 6) {
    s->ck_a = (uint8_t)(s->ck_a + c);
    s->ck_b = (uint8_t)(s->ck_b + s->ck_a);
  }
  switch (s->ubx_state) {
    case 0: s->ubx_state = c == UBX_SYNC1; break;
    case 1: s->ubx_state = c == UBX_SYNC2 ? 2 : c == UBX_SYNC1; break;
    case 2: s->ubx_class = c; s->ubx_state = 3; break;
    case 3: s->ubx_id = c; s->ubx_state = 4; break;
    case 4: s->ubx_len = c; s->ubx_state = 5; break;
    case 5:
      s->ubx_len = (uint16_t)(s->ubx_len | c << 8);
      s->ubx_got = 0;
      s->ubx_state = s->ubx_len ? 6 : 7;
      break;
    case 6:
      if (s->ubx_got < UBLOX_MAX_PAYLOAD) s->payload[s->ubx_got] = c;
      if (++s->ubx_got == s->ubx_len) s->ubx_state = 7;
      break;
    case 7: s->ubx_state = c == s->ck_a ? 8 : 0; break;
    default:
      if (c == s->ck_b) ubx_message(s, t);
      s->ubx_state = 0;
      break;
  }
  if (s->ubx_state == 2 && c == UBX_SYNC2) s->ck_a = s->ck_b = 0;
}

/* ---- NMEA (PUBX) input ---- */

static int parse_uint(const char *s, int base, unsigned long *v) {
  if (!*s) return 0;
  char *end;
  *v = strtoul(s, &end, base);
  return *end == '\0' && *s != '-';
}

/* $PUBX,40 (output rate of one NMEA message per port) and $PUBX,41 (port setup): u-blox 6 spec,
 * "Proprietary Messages". Neither is acknowledged. */
static void pubx(struct ublox_neo6m *s, char *body) {
  char *f[12];
  const int n = gnss_split_fields(body, f, 12);
  unsigned long v;
  if (n >= 5 && strcmp(f[1], "40") == 0) {
    static const char *const names[UBLOX_NMEA_IDS] = {"GGA", "GLL", "GSA", "GSV", "RMC", "VTG", "", "", "ZDA"};
    for (int i = 0; i < UBLOX_NMEA_IDS; ++i)
      if (names[i][0] && strcmp(f[2], names[i]) == 0 && parse_uint(f[4], 10, &v) && v <= 255)
        s->rate[i] = (uint8_t)v; /* f[3] is the DDC port, f[4] UART1 */
  } else if (n >= 6 && strcmp(f[1], "41") == 0) {
    unsigned long port, in, outp, baud;
    if (parse_uint(f[2], 10, &port) && port == UBX_UART1 && parse_uint(f[3], 16, &in) &&
        parse_uint(f[4], 16, &outp) && parse_uint(f[5], 10, &baud) && baud <= 0xFFFFFFFFul &&
        ubx_cfg_baud_ok((uint32_t)baud)) {
      s->in_proto = (uint16_t)(in & 0xFFFF);
      s->out_proto = (uint16_t)(outp & 0xFFFF);
      s->tx.baud = (uint32_t)baud;
    }
  }
}

static void nmea_byte(struct ublox_neo6m *s, uint8_t c) {
  char text[UBLOX_MAX_LINE];
  if (gnss_line_byte(s->line, &s->line_len, UBLOX_MAX_LINE, (char)c, text) && (s->in_proto & UBX_PROTO_NMEA) &&
      strncmp(text, "PUBX,", 5) == 0)
    pubx(s, text);
  /* Anything else ($PMTK..., standard sentences) the module ignores. */
}

void ublox_neo6m_receive(struct ublox_neo6m *s, const struct serial_byte *b) {
  /* Everything the module did up to this byte happens first, so an answer follows the output
   * already on the line. */
  gnss_talker_catch_up(&s->talker, &events, s, b->end_ns);
  if (b->baud != s->tx.baud) { /* garbled at this rate: a framing error resets both parsers */
    s->ubx_state = 0;
    s->line_len = 0;
    return;
  }
  ubx_byte(s, b->value, b->end_ns);
  nmea_byte(s, b->value);
}
