/* NMEA 0183 sentences as GPS modules print them (checksums, field layouts, the empty no-fix
 * forms), and the time-stamped transmit queue of a talker's UART; shared by the u-blox and
 * MediaTek talkers, which differ only in number formats and order. */
#ifndef SEAR_DEVICES_NMEA_H
#define SEAR_DEVICES_NMEA_H

#include <stddef.h>
#include <stdint.h>

#include "gnss_error.h"
#include "serial_byte.h"

#ifdef __cplusplus
extern "C" {
#endif

/* NMEA 0183 v4.10 section 5.3: a sentence is at most 82 characters, '$' through CR LF. */
#define NMEA_MAX_SENTENCE 82
#define NMEA_MAX_SATELLITES 12 /* channels a GSA sentence can list */

/* XOR of the n characters (those between '$' and '*'). */
uint8_t nmea_checksum(const char *s, size_t n);

/* Writes "$" body "*HH\r\n" into out (cap >= NMEA_MAX_SENTENCE + 1, NUL-terminated). Returns the
 * length without the NUL, or 0 if the sentence would exceed NMEA_MAX_SENTENCE. */
size_t nmea_finish(char *out, size_t cap, const char *body);

/* 1 if s[0..n) is "$...*HH" (optionally followed by CR LF) with a correct checksum; then
 * body and body_len name the text between '$' and '*'. */
int nmea_parse_frame(const char *s, size_t n, const char **body, size_t *body_len);

/* Civil UTC from milliseconds since 1970-01-01 (proleptic Gregorian, no leap seconds). */
struct nmea_utc {
  int year, month, day, hour, minute, second, millisecond;
};
void nmea_utc_from_unix_ms(int64_t unix_ms, struct nmea_utc *out);
/* Seconds since 1970 of a civil UTC date and time. */
int64_t nmea_unix_s(int year, int month, int day, int hour, int minute, int second);

/* How one vendor prints numbers. */
struct nmea_style {
  int time_decimals;     /* hhmmss.ss (u-blox) or hhmmss.sss (MediaTek) */
  int minute_decimals;   /* ddmm.mmmmm (u-blox) or ddmm.mmmm (MediaTek) */
  int speed_decimals;    /* knots and km/h */
  int pad_used_count;    /* GGA satellites used: "08" (u-blox) or "8" (MediaTek) */
  int time_before_fix;   /* MediaTek prints its RTC time and zero speeds before a fix */
};

/* A satellite as GSV lists it. elevation_deg < 0: position not yet known (empty fields);
 * snr_dbhz 0: not tracked (empty field). */
struct nmea_satellite {
  int prn, elevation_deg, azimuth_deg, snr_dbhz;
};

/* The solution an epoch reports: what the receiver believes, noise included. */
struct nmea_solution {
  int valid;                  /* a 3D fix */
  int time_valid;             /* utc_ms may be printed */
  int64_t utc_ms;             /* of the measurement epoch */
  double latitude_deg, longitude_deg, altitude_msl_m, geoid_separation_m;
  double speed_mps, course_deg; /* over ground; course clockwise from true north, [0, 360) */
  double east_mps, north_mps, up_mps; /* the velocity these come from, in the local frame */
  int used_count;             /* satellites in the solution (first used_count of used_prn) */
  int used_prn[NMEA_MAX_SATELLITES];
  double pdop, hdop, vdop;
  int in_view;                /* satellites listed by GSV */
  struct nmea_satellite sky[NMEA_MAX_SATELLITES];
};

/* The solution a receiver reports at the measurement epoch epoch_ns: truth (asked of src only if
 * there is a fix) plus the error model's error at that time; the sky as tracked since start_ns
 * (power-on or the last restart). time_valid is set from time_known. */
void nmea_solve(struct nmea_solution *f, struct gnss_error *e, struct gnss_truth_source src, int64_t epoch_ns,
                int64_t power_on_ns, int64_t start_ns, int64_t utc_ms, int time_known);

/* Sentence builders: each writes one complete sentence (or, for GSV, part `index` of
 * nmea_gsv_count()) and returns its length, 0 if it does not fit in 82 characters. */
size_t nmea_rmc(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f);
size_t nmea_vtg(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f);
size_t nmea_gga(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f);
size_t nmea_gsa(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f);
size_t nmea_gll(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f);
size_t nmea_zda(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f);
int nmea_gsv_count(const struct nmea_solution *f); /* sentences of 4 satellites, at least 1 */
size_t nmea_gsv(char *out, size_t cap, const struct nmea_solution *f, int index);

/* ---- Transmit side of a UART: bytes leave back to back at the baud rate. ---- */

#define NMEA_TX_RING 4096 /* bytes held for the caller; a power of two */

struct nmea_tx_byte {
  int64_t end_ns;
  uint32_t baud;
  uint8_t value;
};

struct nmea_tx {
  struct nmea_tx_byte ring[NMEA_TX_RING];
  uint32_t head, count;    /* oldest byte not yet handed out, and how many there are */
  int64_t line_free_ns;    /* when the last queued byte's stop bit ends */
  int64_t until_ns;       /* end of the caller's current window; INT64_MIN before the first */
  int64_t gap_from_ns, gap_to_ns; /* bytes overlapping this skipped span are lost */
  uint32_t baud;
  size_t buffer_bytes;     /* the module's output buffer: bytes queued but not yet started */
  uint64_t dropped_bytes;  /* refused because that buffer was full */
};

void nmea_tx_init(struct nmea_tx *q, uint32_t baud, size_t buffer_bytes);
/* Bytes queued whose start bit has not begun by t_ns: what fills the module's buffer. */
size_t nmea_tx_waiting(const struct nmea_tx *q, int64_t t_ns);
/* Queues n bytes ready at ready_ns if they all fit in the module's buffer at that time, as a
 * module drops whole messages when its buffer is full; returns 1 if queued. force ignores the
 * module's buffer (answers to commands); either way a message that does not fit in the ring
 * (bytes the caller has not taken yet) is dropped whole. */
int nmea_tx_queue(struct nmea_tx *q, int64_t ready_ns, const void *bytes, size_t n, int force);
/* Opens the caller's window [now_ns, until_ns): if now_ns is past the previous window's end, the
 * bytes that started in the gap the caller skipped are lost (nobody was listening). */
void nmea_tx_window(struct nmea_tx *q, int64_t now_ns, int64_t until_ns);
/* Hands out queued bytes whose stop bit ends before the window's end, at most cap; returns how
 * many went to out. What cap cuts off stays queued for the next window. */
size_t nmea_tx_take(struct nmea_tx *q, struct serial_byte *out, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
