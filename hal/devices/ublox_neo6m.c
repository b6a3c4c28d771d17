/* NEO-6M talker: the epoch schedule on the UTC grid, the NMEA cycle, and the UBX/PUBX
 * configuration parsers with their ACK-ACK / ACK-NAK answers. */
#include "ublox_neo6m.h"

#include <stdlib.h>
#include <string.h>

#define UBX_SYNC1 0xB5
#define UBX_SYNC2 0x62
#define UBX_CLASS_ACK 0x05
#define UBX_CLASS_CFG 0x06
#define UBX_CFG_PRT 0x00
#define UBX_CFG_MSG 0x01
#define UBX_CFG_RATE 0x08
#define UBX_CFG_CFG 0x09
#define UBX_CFG_NAV5 0x24
#define UBX_NMEA_CLASS 0xF0
#define UART1 1 /* CFG-PRT portID of the module's only UART pins (u-blox 6 spec, "Port Numbers") */
#define PROTO_UBX 1u
#define PROTO_NMEA 2u
#define MODE_8N1 0x08D0u /* charLen 11 (8 bit), parity 100 (none), nStopBits 00 (1) */

static const uint32_t bauds[] = {4800, 9600, 19200, 38400, 57600, 115200};

static int baud_ok(uint32_t b) { return gnss_baud_listed(bauds, sizeof bauds / sizeof bauds[0], b); }

/* The banner a NEO-6M with firmware 7.03 prints at power-up (as logged from real modules). */
static const char *const banner[] = {
    "GPTXT,01,01,02,u-blox ag - www.u-blox.com",
    "GPTXT,01,01,02,HW  UBX-G60xx  00040007 FF7FFFFFp",
    "GPTXT,01,01,02,ROM CORE 7.03 (45969) Mar 17 2011 16:18:34",
    "GPTXT,01,01,02,ANTSUPERV=AC SD PDoS SR",
    "GPTXT,01,01,02,ANTSTATUS=DONTKNOW",
};

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
  nmea_tx_init(&s->tx, baud_ok(c->baud) ? c->baud : UBLOX_DEFAULT_BAUD, UBLOX_TX_BUFFER);
  gnss_talker_init(&s->talker, power_on_ns, UBLOX_BOOT_NS, c->utc_start_s, c->rate_hz);
  s->time_ref = 1; /* u-blox 6 default: measurements aligned to GPS time */
  /* Factory default (u-blox 6 spec, CFG-MSG): GGA GLL GSA GSV RMC VTG on, the rest off. */
  for (int i = UBLOX_GGA; i <= UBLOX_VTG; ++i) s->rate[i] = 1;
  s->in_proto = PROTO_UBX | PROTO_NMEA;
  s->out_proto = PROTO_UBX | PROTO_NMEA;
  s->port_mode = MODE_8N1;
}

uint32_t ublox_neo6m_baud(const struct ublox_neo6m *s) { return s->tx.baud; }

static void send_nmea(struct ublox_neo6m *s, int64_t ready, const char *text, size_t n) {
  if (n && (s->out_proto & PROTO_NMEA)) nmea_tx_queue(&s->tx, ready, text, n, 0);
}

static void epoch(void *talker) {
  struct ublox_neo6m *s = talker;
  const struct gnss_talker *g = &s->talker;
  const int64_t t = gnss_talker_epoch_ns(g, g->next_epoch_ms);
  struct nmea_solution f;
  nmea_solve(&f, &s->error, s->src, t, g->power_on_ns, g->start_ns, g->next_epoch_ms, 0);
  const int64_t ready = t + UBLOX_OUTPUT_DELAY_NS;
  char text[NMEA_MAX_SENTENCE + 1];
#define DUE(id) gnss_talker_due(g, s->rate[id])
  /* The order a NEO-6M prints its default set in. */
  if (DUE(UBLOX_RMC)) send_nmea(s, ready, text, nmea_rmc(text, sizeof text, &style, &f));
  if (DUE(UBLOX_VTG)) send_nmea(s, ready, text, nmea_vtg(text, sizeof text, &style, &f));
  if (DUE(UBLOX_GGA)) send_nmea(s, ready, text, nmea_gga(text, sizeof text, &style, &f));
  if (DUE(UBLOX_GSA)) send_nmea(s, ready, text, nmea_gsa(text, sizeof text, &style, &f));
  if (DUE(UBLOX_GSV))
    for (int i = 0; i < nmea_gsv_count(&f); ++i) send_nmea(s, ready, text, nmea_gsv(text, sizeof text, &f, i));
  if (DUE(UBLOX_GLL)) send_nmea(s, ready, text, nmea_gll(text, sizeof text, &style, &f));
  if (DUE(UBLOX_ZDA)) send_nmea(s, ready, text, nmea_zda(text, sizeof text, &style, &f));
#undef DUE
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

/* ---- configuration input ---- */

static uint16_t u16_at(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static uint32_t u32_at(const uint8_t *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static void put16(uint8_t *p, uint32_t v) {
  p[0] = (uint8_t)(v & 0xFF);
  p[1] = (uint8_t)(v >> 8 & 0xFF);
}
static void put32(uint8_t *p, uint32_t v) {
  put16(p, v & 0xFFFF);
  put16(p + 2, v >> 16);
}

static void send_ubx(struct ublox_neo6m *s, int64_t t, uint8_t cls, uint8_t id, const uint8_t *payload, uint16_t len) {
  if (!(s->out_proto & PROTO_UBX)) return;
  uint8_t frame[UBLOX_MAX_PAYLOAD + 8];
  const size_t n = ubx_frame(cls, id, payload, len, frame);
  nmea_tx_queue(&s->tx, t + UBLOX_REPLY_DELAY_NS, frame, n, 1);
}

static void acknowledge(struct ublox_neo6m *s, int64_t t, int ok) {
  const uint8_t which[2] = {s->ubx_class, s->ubx_id};
  send_ubx(s, t, UBX_CLASS_ACK, ok ? 0x01 : 0x00, which, 2);
  if (ok) ++s->acks;
  else ++s->naks;
}

static void port_payload(const struct ublox_neo6m *s, uint8_t *p) {
  memset(p, 0, 20);
  p[0] = UART1;
  put32(p + 4, s->port_mode);
  put32(p + 8, s->tx.baud);
  put16(p + 12, s->in_proto);
  put16(p + 14, s->out_proto);
}

/* Applies a port setting the way the module does: what is queued leaves at the old rate, the
 * acknowledgement too, and the new rate starts after it (our reading of the u-blox 6 spec; some
 * drivers do not wait for this ACK at all). */
static int cfg_prt(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len == 0 || (len == 1 && p[0] == UART1)) {
    uint8_t reply[20];
    port_payload(s, reply);
    send_ubx(s, t, UBX_CLASS_CFG, UBX_CFG_PRT, reply, 20);
    return 1;
  }
  if (len != 20) return 0;
  if (p[0] != UART1) return p[0] <= 4; /* DDC, UART2, USB, SPI exist on the chip; not modelled */
  const uint32_t mode = u32_at(p + 4), baud = u32_at(p + 8);
  /* Only 8N1 is modelled, as serial_byte carries only 8N1 frames. */
  if ((mode & 0x3FC0u) != (MODE_8N1 & 0x3FC0u) && (mode & 0x3FC0u) != 0x0AC0u) return 0;
  if (!baud_ok(baud)) return 0;
  acknowledge(s, t, 1);
  s->in_proto = u16_at(p + 12);
  s->out_proto = u16_at(p + 14);
  s->port_mode = mode;
  s->tx.baud = baud;
  return -1; /* already acknowledged */
}

static int cfg_msg(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len < 2 || p[0] != UBX_NMEA_CLASS || p[1] >= UBLOX_NMEA_IDS || p[1] == UBLOX_GRS || p[1] == UBLOX_GST)
    return 0; /* only the NMEA messages this model prints; UBX NAV output is not modelled */
  if (len == 2) {
    uint8_t reply[8] = {p[0], p[1], 0, s->rate[p[1]], 0, 0, 0, 0};
    send_ubx(s, t, UBX_CLASS_CFG, UBX_CFG_MSG, reply, 8);
    return 1;
  }
  if (len == 3) s->rate[p[1]] = p[2]; /* the rate on the port the command came in on */
  else if (len == 8) s->rate[p[1]] = p[3]; /* rates per port I2C, UART1, ... */
  else return 0;
  return 1;
}

static int cfg_rate(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len == 0) {
    uint8_t reply[6];
    put16(reply, (uint32_t)s->talker.period_ms);
    put16(reply + 2, 1);
    put16(reply + 4, s->time_ref);
    send_ubx(s, t, UBX_CLASS_CFG, UBX_CFG_RATE, reply, 6);
    return 1;
  }
  if (len != 6) return 0;
  const uint16_t meas = u16_at(p), nav = u16_at(p + 2), ref = u16_at(p + 4);
  /* 10 Hz is the fastest this model offers; u-blox 6 fixes navRate at 1 and knows timeRef 0/1. */
  if (meas < 100 || nav != 1 || ref > 1) return 0;
  gnss_talker_set_period(&s->talker, meas, t);
  s->time_ref = ref;
  return 1;
}

static void ubx_message(struct ublox_neo6m *s, int64_t t) {
  if (!(s->in_proto & PROTO_UBX) || s->ubx_class != UBX_CLASS_CFG) return; /* only CFG is answered */
  const uint8_t *p = s->payload;
  const uint16_t len = s->ubx_len;
  if (len > UBLOX_MAX_PAYLOAD) {
    acknowledge(s, t, 0);
    return;
  }
  int ok;
  switch (s->ubx_id) {
    case UBX_CFG_PRT: ok = cfg_prt(s, t, p, len); break;
    case UBX_CFG_MSG: ok = cfg_msg(s, t, p, len); break;
    case UBX_CFG_RATE: ok = cfg_rate(s, t, p, len); break;
    case UBX_CFG_CFG: ok = len == 12 || len == 13; break; /* save/load: no battery-backed RAM here */
    case UBX_CFG_NAV5: ok = len == 36; break;             /* accepted; the dynamic model is not modelled */
    default: ok = 0; break;
  }
  if (ok >= 0) acknowledge(s, t, ok);
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
    if (parse_uint(f[2], 10, &port) && port == UART1 && parse_uint(f[3], 16, &in) && parse_uint(f[4], 16, &outp) &&
        parse_uint(f[5], 10, &baud) && baud <= 0xFFFFFFFFul && baud_ok((uint32_t)baud)) {
      s->in_proto = (uint16_t)(in & 0xFFFF);
      s->out_proto = (uint16_t)(outp & 0xFFFF);
      s->tx.baud = (uint32_t)baud;
    }
  }
}

static void nmea_byte(struct ublox_neo6m *s, uint8_t c) {
  char text[UBLOX_MAX_LINE];
  if (gnss_line_byte(s->line, &s->line_len, UBLOX_MAX_LINE, (char)c, text) && (s->in_proto & PROTO_NMEA) &&
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
