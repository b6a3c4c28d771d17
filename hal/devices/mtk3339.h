/* MediaTek MT3339 GPS module (GlobalTop PA6H, Adafruit Ultimate GPS) on its UART: the MTK NMEA
 * flavour (hhmmss.sss, ddmm.mmmm, RTC time before a fix) and the PMTK commands hobby firmware
 * sends (PMTK220 fix interval, PMTK314 sentence rates, PMTK251 baud, restarts) with their
 * PMTK001 acknowledgements. UBX bytes are ignored, as the module does. */
#ifndef SEAR_DEVICES_MTK3339_H
#define SEAR_DEVICES_MTK3339_H

#include <stddef.h>
#include <stdint.h>

#include "gnss_error.h"
#include "gnss_talker.h"
#include "nmea.h"
#include "serial_byte.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MTK_DEFAULT_BAUD 9600u          /* PA6H datasheet: 9600 8N1 default */
#define MTK_TX_BUFFER 1024u             /* as UBLOX_TX_BUFFER: an assumption, whole sentences dropped */
#define MTK_BOOT_NS INT64_C(100000000)  /* $PMTK011/$PMTK010 after power-on: assumption */
#define MTK_OUTPUT_DELAY_NS INT64_C(50000000)
#define MTK_REPLY_DELAY_NS INT64_C(5000000)
#define MTK_HOT_START_TTFF_S 1.0        /* PA6H datasheet, TTFF: hot start 1 s */
#define MTK_MAX_LINE 128
/* PMTK314 field order (MTK NMEA packet user manual, packet 314). */
enum mtk_nmea_id { MTK_GLL = 0, MTK_RMC, MTK_VTG, MTK_GGA, MTK_GSA, MTK_GSV, MTK_ZDA = 17, MTK_NMEA_IDS = 19 };

struct mtk3339_config {
  double rate_hz;          /* 1 ... 10 Hz (default 1) */
  uint32_t baud;           /* 4800 ... 115200 (default 9600) */
  int64_t utc_start_s;     /* UTC at power-on, seconds since 1970 */
  struct gnss_error_config error;
};

struct mtk3339 {
  struct gnss_truth_source src;
  struct gnss_error error;
  struct nmea_tx tx;
  struct gnss_talker talker;
  uint8_t rate[MTK_NMEA_IDS];
  char line[MTK_MAX_LINE];
  size_t line_len;
  uint32_t acks;
};

void mtk3339_defaults(struct mtk3339_config *c);
void mtk3339_init(struct mtk3339 *s, const struct mtk3339_config *c, struct gnss_truth_source src, int64_t power_on_ns);
void mtk3339_receive(struct mtk3339 *s, const struct serial_byte *b);
/* As ublox_neo6m_transmit. */
size_t mtk3339_transmit(struct mtk3339 *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out, size_t cap);
uint32_t mtk3339_baud(const struct mtk3339 *s);

#ifdef __cplusplus
}
#endif
#endif
