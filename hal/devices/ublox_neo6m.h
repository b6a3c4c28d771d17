/* u-blox NEO-6M GPS module on its UART: power-up $GPTXT banner, then RMC VTG GGA GSA GSV GLL
 * every measurement epoch at the baud rate, the UBX NAV messages CFG-MSG turns on (from the same
 * solution), MON-VER and NAV polls, and the UBX CFG and PUBX configuration drivers send (gpsd,
 * flight controllers, hobby firmware). MediaTek PMTK commands are ignored, as the module does. */
#ifndef SEAR_DEVICES_UBLOX_NEO6M_H
#define SEAR_DEVICES_UBLOX_NEO6M_H

#include <stddef.h>
#include <stdint.h>

#include "gnss_error.h"
#include "gnss_talker.h"
#include "nmea.h"
#include "serial_byte.h"
#include "ubx_nav.h"

#ifdef __cplusplus
extern "C" {
#endif

#define UBLOX_DEFAULT_BAUD 9600u /* NEO-6 datasheet, "UART": 9600 8N1 default */
/* u-blox 6 Receiver Description (GPS.G6-SW-10018), "Output buffer": a message that does not fit
 * in the port's buffer is dropped. The size is not documented; 1 kB is our assumption. */
#define UBLOX_TX_BUFFER 1024u
#define UBLOX_BOOT_NS INT64_C(100000000)   /* banner after power-on: assumption */
#define UBLOX_OUTPUT_DELAY_NS INT64_C(50000000) /* measurement epoch to its output: assumption */
#define UBLOX_REPLY_DELAY_NS INT64_C(5000000)   /* end of a command to its answer: assumption */
#define UBLOX_MAX_PAYLOAD 64  /* longer UBX messages it is sent are consumed (a CFG one NAKed) */
#define UBLOX_MAX_OUT_PAYLOAD UBX_NAV_MAX_PAYLOAD /* the longest it sends: NAV-SVINFO, 12 channels */
#define UBLOX_NAV5_LEN 36
#define UBLOX_SBAS_LEN 8
#define UBLOX_MAX_LINE 100

/* NMEA message ids of UBX class 0xF0 (u-blox 6 protocol spec, "NMEA Messages Overview"). */
enum ublox_nmea_id { UBLOX_GGA = 0, UBLOX_GLL, UBLOX_GSA, UBLOX_GSV, UBLOX_RMC, UBLOX_VTG, UBLOX_GRS, UBLOX_GST,
                     UBLOX_ZDA, UBLOX_NMEA_IDS };

struct ublox_neo6m_config {
  double rate_hz;          /* measurement rate, 1 ... 10 Hz (default 1) */
  uint32_t baud;           /* 4800 ... 115200 (default 9600) */
  int64_t utc_start_s;     /* UTC at power-on, seconds since 1970 (whole seconds) */
  struct gnss_error_config error;
};

struct ublox_neo6m {
  struct gnss_truth_source src;
  struct gnss_error error;
  struct nmea_tx tx;
  struct gnss_talker talker;         /* epoch schedule; its period_ms is CFG-RATE measRate */
  uint16_t time_ref;                 /* CFG-RATE timeRef: 0 UTC, 1 GPS (kept for polls) */
  uint8_t rate[UBLOX_NMEA_IDS];      /* an id is output every rate-th epoch; 0: off */
  uint8_t nav_rate[UBX_NAV_MSGS];    /* the same for the UBX NAV messages (all off by default) */
  struct ubx_epoch pending;          /* the latest measurement, until its output event */
  uint64_t pending_count;            /* its number, for the message rates */
  struct ubx_epoch last;             /* the latest epoch output, for polls */
  int has_output;                    /* last holds an epoch */
  uint32_t ttff_ms;                  /* power-on to the first fix, once there was one */
  uint8_t nav5[UBLOX_NAV5_LEN];      /* CFG-NAV5 as set (accepted; the error model ignores it) */
  uint8_t sbas[UBLOX_SBAS_LEN];      /* CFG-SBAS as set */
  uint16_t in_proto, out_proto;      /* CFG-PRT masks: bit 0 UBX, bit 1 NMEA */
  uint32_t port_mode;
  /* UBX receiver */
  int ubx_state;
  uint8_t ubx_class, ubx_id, ck_a, ck_b;
  uint16_t ubx_len, ubx_got;
  uint8_t payload[UBLOX_MAX_PAYLOAD];
  /* NMEA (PUBX) receiver */
  char line[UBLOX_MAX_LINE];
  size_t line_len;
  uint32_t acks, naks;
};

void ublox_neo6m_defaults(struct ublox_neo6m_config *c);
void ublox_neo6m_init(struct ublox_neo6m *s, const struct ublox_neo6m_config *c, struct gnss_truth_source src,
                      int64_t power_on_ns);
/* A byte from the host. A byte at another baud rate is a framing error: it resets the parsers. */
void ublox_neo6m_receive(struct ublox_neo6m *s, const struct serial_byte *b);
/* Every byte whose stop bit ends before until_ns, none starting before now_ns (bytes that would
 * have started in a span the caller skipped are lost); calls must not go back in time; what cap
 * cuts off stays queued for the next call. Returns the number written to out. */
size_t ublox_neo6m_transmit(struct ublox_neo6m *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out,
                            size_t cap);
uint32_t ublox_neo6m_baud(const struct ublox_neo6m *s);

/* UBX framing: sync B5 62, class, id, little-endian length, payload, 8-bit Fletcher checksum over
 * class..payload (u-blox 6 protocol spec, "UBX Checksum"). Returns the frame length (len + 8). */
size_t ubx_frame(uint8_t cls, uint8_t id, const uint8_t *payload, uint16_t len, uint8_t *out);

#ifdef __cplusplus
}
#endif
#endif
