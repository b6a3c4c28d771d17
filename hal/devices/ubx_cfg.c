/* UBX CFG of a u-blox 6 as the NEO-6M answers it: CFG-PRT, CFG-MSG (NMEA and NAV messages),
 * CFG-RATE, CFG-CFG, CFG-NAV5, CFG-SBAS; sets, polls and refusals. */
#include "ubx_cfg.h"

#include <string.h>

#define CFG_PRT 0x00
#define CFG_MSG 0x01
#define CFG_RATE 0x08
#define CFG_CFG 0x09
#define CFG_SBAS 0x16
#define CFG_NAV5 0x24

/* The fastest measurement rate this model offers (10 Hz, as the talker's schedule). The spec
 * gives no lower bound for measRate; the NEO-6 datasheet's "max navigation update rate" is 5 Hz,
 * so 100 ms already goes past the part. */
#define MIN_MEAS_RATE_MS 100u

static const uint32_t bauds[] = {4800, 9600, 19200, 38400, 57600, 115200};

int ubx_cfg_baud_ok(uint32_t baud) { return gnss_baud_listed(bauds, sizeof bauds / sizeof bauds[0], baud); }

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

void ubx_cfg_defaults(struct ublox_neo6m *s) {
  /* CFG-NAV5 factory values of the u-blox 6 spec: all parameters applied (mask 0xFFFF), dynModel 0
   * portable, fixMode 3 auto 2D/3D, fixedAlt 0, fixedAltVar 1 m^2, minElev 5 deg, drLimit 0 s,
   * pDop 25.0, tDop 25.0, pAcc 100 m, tAcc 300 m, staticHoldThresh 0, dgpsTimeOut 0. */
  uint8_t *n = s->nav5;
  memset(n, 0, UBLOX_NAV5_LEN);
  put16(n, 0xFFFF);
  n[2] = 0;
  n[3] = 3;
  put32(n + 8, 10000);
  n[12] = 5;
  put16(n + 14, 250);
  put16(n + 16, 250);
  put16(n + 18, 100);
  put16(n + 20, 300);
  /* CFG-SBAS: enabled (mode bit 0), ranging and corrections used (usage 0x03), up to 3 SBAS
   * channels, automatic PRN scan (scanmode 0). */
  static const uint8_t sbas[UBLOX_SBAS_LEN] = {0x01, 0x03, 3, 0, 0, 0, 0, 0};
  memcpy(s->sbas, sbas, sizeof sbas);
}

static void port_payload(const struct ublox_neo6m *s, uint8_t *p) {
  memset(p, 0, 20);
  p[0] = UBX_UART1;
  put32(p + 4, s->port_mode);
  put32(p + 8, s->tx.baud);
  put16(p + 12, s->in_proto);
  put16(p + 14, s->out_proto);
}

/* Applies a port setting the way the module does: what is queued leaves at the old rate, the
 * acknowledgement too, and the new rate starts after it (our reading of the u-blox 6 spec; some
 * drivers do not wait for this ACK at all). */
static int cfg_prt(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len == 0 || (len == 1 && p[0] == UBX_UART1)) {
    uint8_t reply[20];
    port_payload(s, reply);
    ublox_neo6m_reply(s, t, UBX_CLASS_CFG, CFG_PRT, reply, 20);
    return 1;
  }
  if (len != 20) return 0;
  if (p[0] != UBX_UART1) return p[0] <= 4; /* DDC, UART2, USB, SPI exist on the chip; not modelled */
  const uint32_t mode = u32_at(p + 4), baud = u32_at(p + 8);
  /* Only 8N1 is modelled, as serial_byte carries only 8N1 frames. */
  if ((mode & 0x3FC0u) != (UBX_MODE_8N1 & 0x3FC0u) && (mode & 0x3FC0u) != 0x0AC0u) return 0;
  if (!ubx_cfg_baud_ok(baud)) return 0;
  ublox_neo6m_acknowledge(s, t, 1);
  s->in_proto = u16_at(p + 12);
  s->out_proto = u16_at(p + 14);
  s->port_mode = mode;
  s->tx.baud = baud;
  return -1; /* already acknowledged */
}

/* The rate slot of a message: an NMEA id this model prints, a NAV message it outputs, or none. */
static uint8_t *rate_slot(struct ublox_neo6m *s, uint8_t cls, uint8_t id) {
  if (cls == UBX_NMEA_CLASS)
    return id < UBLOX_NMEA_IDS && id != UBLOX_GRS && id != UBLOX_GST ? &s->rate[id] : NULL;
  if (cls == UBX_CLASS_NAV) {
    const int k = ubx_nav_index(id);
    return k >= 0 ? &s->nav_rate[k] : NULL;
  }
  return NULL;
}

/* NMEA sentences of the u-blox 6 spec ("NMEA Messages Overview") the model never prints: GRS,
 * GST, GBS, DTM, TXT (the power-up banner is not rate-controlled). */
static int unprinted_nmea(uint8_t id) { return id == 0x06 || id == 0x07 || id == 0x09 || id == 0x0A || id == 0x41; }

/* CFG-MSG: poll (2 bytes), the rate on the port the command came in on (3 bytes), or the rates
 * of all six ports I2C, UART1, UART2, USB, SPI, reserved (8 bytes; UART1's applies). A message the
 * receiver does not have (NAV-PVT and NAV-SAT came with u-blox 7 and 8) is refused. */
static int cfg_msg(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len < 2) return 0;
  uint8_t *slot = rate_slot(s, p[0], p[1]);
  uint8_t off = 0;
  if (!slot && p[0] == UBX_NMEA_CLASS && unprinted_nmea(p[1])) {
    /* A sentence a u-blox 6 has but this model does not print: it is off, and may be set off. */
    if (len == 3 && p[2] != 0) return 0;
    if (len == 8 && p[2 + UBX_UART1] != 0) return 0;
    slot = &off;
  }
  if (!slot) return 0;
  if (len == 2) {
    const uint8_t reply[8] = {p[0], p[1], 0, *slot, 0, 0, 0, 0};
    ublox_neo6m_reply(s, t, UBX_CLASS_CFG, CFG_MSG, reply, 8);
    return 1;
  }
  if (len == 3) *slot = p[2];
  else if (len == 8) *slot = p[2 + UBX_UART1];
  else return 0;
  return 1;
}

/* CFG-RATE: measRate (ms), navRate (cycles), timeRef (0 UTC, 1 GPS). The u-blox 6 spec: "navRate
 * ... cannot be changed, and is always equals 1" on u-blox 5 and 6, so any other value is refused;
 * so is a timeRef other than UTC or GPS and a measRate faster than MIN_MEAS_RATE_MS. */
static int cfg_rate(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len == 0) {
    uint8_t reply[6];
    put16(reply, (uint32_t)s->talker.period_ms);
    put16(reply + 2, 1);
    put16(reply + 4, s->time_ref);
    ublox_neo6m_reply(s, t, UBX_CLASS_CFG, CFG_RATE, reply, 6);
    return 1;
  }
  if (len != 6) return 0;
  const uint16_t meas = u16_at(p), nav = u16_at(p + 2), ref = u16_at(p + 4);
  if (meas < MIN_MEAS_RATE_MS || nav != 1 || ref > 1) return 0;
  gnss_talker_set_period(&s->talker, meas, t);
  s->time_ref = ref;
  return 1;
}

/* CFG-NAV5: the parameters whose mask bit is set are applied (bit 0 dynModel, bit 2 fixMode, the
 * rest stored as sent). A u-blox 6 knows dynModel 0 and 2 ... 8 (1 is reserved) and fixMode 1 ... 3. */
static int cfg_nav5(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len == 0) {
    ublox_neo6m_reply(s, t, UBX_CLASS_CFG, CFG_NAV5, s->nav5, UBLOX_NAV5_LEN);
    return 1;
  }
  if (len != UBLOX_NAV5_LEN) return 0;
  const uint16_t mask = u16_at(p);
  if ((mask & 0x01) && (p[2] == 1 || p[2] > 8)) return 0;
  if ((mask & 0x04) && (p[3] < 1 || p[3] > 3)) return 0;
  /* Mask bits and the bytes they apply (u-blox 6 spec, CFG-NAV5 "mask"). */
  static const struct { uint16_t bit; uint8_t from, to; } groups[] = {
      {0x01, 2, 3},   /* dyn: dynModel */
      {0x02, 12, 13}, /* minEl */
      {0x04, 3, 12},  /* fixMode, fixedAlt, fixedAltVar */
      {0x08, 13, 14}, /* drLim */
      {0x10, 14, 20}, /* posMask: pDop, tDop, pAcc */
      {0x20, 20, 22}, /* timeMask: tAcc */
      {0x40, 22, 23}, /* staticHoldMask */
      {0x80, 23, 24}, /* dgpsMask */
  };
  for (size_t i = 0; i < sizeof groups / sizeof groups[0]; ++i)
    if (mask & groups[i].bit) memcpy(s->nav5 + groups[i].from, p + groups[i].from, groups[i].to - groups[i].from);
  return 1;
}

/* CFG-SBAS: stored as sent (the model's sky has no SBAS satellite, so it changes no fix). */
static int cfg_sbas(struct ublox_neo6m *s, int64_t t, const uint8_t *p, uint16_t len) {
  if (len == 0) {
    ublox_neo6m_reply(s, t, UBX_CLASS_CFG, CFG_SBAS, s->sbas, UBLOX_SBAS_LEN);
    return 1;
  }
  if (len != UBLOX_SBAS_LEN) return 0;
  memcpy(s->sbas, p, UBLOX_SBAS_LEN);
  return 1;
}

int ubx_cfg(struct ublox_neo6m *s, int64_t t) {
  const uint8_t *p = s->payload;
  const uint16_t len = s->ubx_len;
  if (len > UBLOX_MAX_PAYLOAD) return 0;
  switch (s->ubx_id) {
    case CFG_PRT: return cfg_prt(s, t, p, len);
    case CFG_MSG: return cfg_msg(s, t, p, len);
    case CFG_RATE: return cfg_rate(s, t, p, len);
    case CFG_CFG: return len == 12 || len == 13; /* save/load: no battery-backed RAM here */
    case CFG_NAV5: return cfg_nav5(s, t, p, len);
    case CFG_SBAS: return cfg_sbas(s, t, p, len);
    default: return 0;
  }
}
