/* The UBX NAV messages of a u-blox 6 receiver (GPS.G6-SW-10018, "UBX Class NAV"), built from the
 * same solution as the epoch's NMEA sentences: layouts, units and flags as the protocol
 * specification gives them, little-endian. */
#ifndef SEAR_DEVICES_UBX_NAV_H
#define SEAR_DEVICES_UBX_NAV_H

#include <stdint.h>

#include "nmea.h"

#ifdef __cplusplus
extern "C" {
#endif

#define UBX_CLASS_NAV 0x01

/* GPS time runs ahead of UTC by the leap seconds since 1980: 18 s since 2017-01-01 (IERS Bulletin C:
 * none added since). The model's UTC has no leap seconds, so the offset is this constant. */
#define UBX_LEAP_SECONDS 18
#define UBX_GPS_EPOCH_UNIX_S INT64_C(315964800) /* 1980-01-06 00:00:00 UTC */

/* The NAV messages this receiver outputs, in the order one epoch prints them (by message id). */
enum ubx_nav_msg {
  UBX_NAV_POSECEF, UBX_NAV_POSLLH, UBX_NAV_STATUS, UBX_NAV_DOP, UBX_NAV_SOL, UBX_NAV_VELECEF,
  UBX_NAV_VELNED, UBX_NAV_TIMEGPS, UBX_NAV_TIMEUTC, UBX_NAV_SVINFO, UBX_NAV_SBAS, UBX_NAV_MSGS
};
#define UBX_NAV_MAX_PAYLOAD (8 + 12 * NMEA_MAX_SATELLITES) /* NAV-SVINFO with every channel */

/* Everything a NAV message says about one epoch. */
struct ubx_epoch {
  struct nmea_solution fix;
  uint32_t itow_ms;        /* GPS time of week of the epoch */
  int16_t week;            /* GPS week (not truncated to 10 bits) */
  uint32_t msss;           /* milliseconds since power-on */
  uint32_t ttff_ms;        /* power-on to the first fix; 0 before it */
  double h_acc_m, v_acc_m; /* accuracy estimates the receiver claims (1 sigma, see ubx_nav.c) */
  double s_acc_mps;        /* 3D speed accuracy (1 sigma) */
  int sbas_enabled;        /* CFG-SBAS mode bit 0 */
};

/* The message id of m within class NAV. */
uint8_t ubx_nav_id(enum ubx_nav_msg m);
/* The NAV message with this id, or -1 if a u-blox 6 has no such output (NAV-PVT, NAV-SAT, ...). */
int ubx_nav_index(uint8_t id);

/* GPS week and time of week of a UTC instant (ms since 1970). */
void ubx_gps_time(int64_t utc_ms, int16_t *week, uint32_t *itow_ms);

/* Writes m's payload for epoch e into out (room for UBX_NAV_MAX_PAYLOAD); returns its length. */
uint16_t ubx_nav_payload(enum ubx_nav_msg m, const struct ubx_epoch *e, uint8_t *out);

/* WGS-84 geodetic (degrees, ellipsoidal height) to earth-centred earth-fixed metres, and a local
 * east-north-up vector at that point into ECEF. */
void ubx_ecef(double latitude_deg, double longitude_deg, double height_m, double xyz[3]);
void ubx_enu_to_ecef(double latitude_deg, double longitude_deg, double e, double n, double u, double xyz[3]);

/* Geometric, time, north and east DOP besides the three gnss_dop() gives, from the same satellites:
 * the diagonal of (G^T G)^-1 by Cholesky. Returns 0 for a singular geometry. */
struct ubx_dop_set {
  double g, p, t, v, h, n, e;
};
int ubx_dops(const struct nmea_solution *f, struct ubx_dop_set *d);

#ifdef __cplusplus
}
#endif
#endif
