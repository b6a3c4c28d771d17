/* SICK LMS200/LMS291 laser scanner as its RS-232 telegram protocol: takes the host's bytes, gives
 * time-stamped reply and scan telegrams, with the line's own throughput limiting the scan rate.
 * World-free: the ranges come from a caller-supplied scan source. Times in integer ns. */
#ifndef SEAR_DEVICES_SICK_LMS2XX_H
#define SEAR_DEVICES_SICK_LMS2XX_H

#include <stddef.h>
#include <stdint.h>

#include "serial_byte.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Telegram framing (SICK "Telegrams for Configuring and Operating the LMS2xx Laser
 * Measurement Systems", telegram listing 8007954, section 2 "Transfer and data format"). ---- */
#define LMS2XX_STX 0x02u
#define LMS2XX_ACK 0x06u
#define LMS2XX_NAK 0x15u
#define LMS2XX_HOST_ADDRESS 0x00u   /* requests are addressed to 0x00 ... */
#define LMS2XX_REPLY_ADDRESS 0x80u  /* ... replies come from 0x80 (address + 0x80) */
#define LMS2XX_STATUS_OK 0x10u      /* status byte closing every reply in normal operation */
#define LMS2XX_CRC_POLY 0x8005u     /* CRC-16 generator, over STX through the status byte */

/* Request codes the model answers, and their reply codes (request + 0x80). */
#define LMS2XX_CMD_RESET 0x10u          /* -> 0x91, then 0x90 once rebooted */
#define LMS2XX_CMD_MODE 0x20u           /* -> 0xA0 */
#define LMS2XX_CMD_VALUES 0x30u         /* -> 0xB0 */
#define LMS2XX_CMD_STATUS 0x31u         /* -> 0xB1 */
#define LMS2XX_CMD_ERRORS 0x32u         /* -> 0xB2 */
#define LMS2XX_CMD_TYPE 0x3Au           /* -> 0xBA */
#define LMS2XX_CMD_VARIANT 0x3Bu        /* -> 0xBB */
#define LMS2XX_CMD_READ_CONFIG 0x74u    /* -> 0xF4 */
#define LMS2XX_CMD_WRITE_CONFIG 0x77u   /* -> 0xF7 */
#define LMS2XX_REPLY_POWER_ON 0x90u
#define LMS2XX_REPLY_RESET 0x91u /* the exception to "request + 0x80": 0x90 is the power-on message */
#define LMS2XX_REPLY_NOT_RECOGNISED 0x92u

/* Operating modes (data byte of 0x20) and the baud codes that share the command. */
#define LMS2XX_MODE_INSTALLATION 0x00u   /* followed by the 8-byte password "SICK_LMS" */
#define LMS2XX_MODE_STREAM 0x24u         /* all measured values, continuously */
#define LMS2XX_MODE_REQUEST 0x25u        /* measured values on request (power-up default) */
#define LMS2XX_MODE_STREAM_PARTIAL 0x2Au /* each partial (interlaced) scan right after its sweep */
#define LMS2XX_BAUD_38400 0x40u
#define LMS2XX_BAUD_19200 0x41u
#define LMS2XX_BAUD_9600 0x42u
#define LMS2XX_BAUD_500000 0x48u

/* The 0xB1 status reply's baud word (data byte 116, low byte first, as sicktoolbox reads it):
 * 0x8019 at 38400 per the telegram listing, which is 0x8000 | (16 MHz / (16 x rate) - 1), the
 * reload value of a UART clocked at 16 MHz; the other rates follow from that. */
#define LMS2XX_STATUS_BAUD_9600 0x8067u
#define LMS2XX_STATUS_BAUD_19200 0x8033u
#define LMS2XX_STATUS_BAUD_38400 0x8019u
#define LMS2XX_STATUS_BAUD_500000 0x8001u

/* Measuring modes (configuration block D) and units (block E). */
#define LMS2XX_MEAS_8_80M_FA_FB_DAZZLE 0x00u /* 13-bit values: 8 m in mm, 80 m in cm */
#define LMS2XX_MEAS_8_80M_REFLECTOR 0x01u
#define LMS2XX_MEAS_8_80M_FA_FB_FC 0x02u
#define LMS2XX_MEAS_16M_REFLECTOR 0x03u      /* 14-bit values */
#define LMS2XX_MEAS_16M_FA_FB 0x04u
#define LMS2XX_MEAS_32M_REFLECTOR 0x05u      /* 15-bit values */
#define LMS2XX_MEAS_32M_FA 0x06u
#define LMS2XX_MEAS_32M_IMMEDIATE 0x0Fu      /* 15-bit values, no flags */
#define LMS2XX_UNITS_CM 0x00u
#define LMS2XX_UNITS_MM 0x01u

/* 0xB0 count word: bits 0-9 the number of values, 11-12 the partial scan's offset in
 * 0.25 degree steps, 13 set for a partial scan, 14-15 the unit (00 cm, 01 mm). */
#define LMS2XX_COUNT_MASK 0x03FFu
#define LMS2XX_PARTIAL_INDEX_SHIFT 11
#define LMS2XX_PARTIAL_FLAG 0x2000u
#define LMS2XX_UNIT_SHIFT 14

/* Error codes sit at the top of each measuring mode's value range (telegram listing p. 124, as
 * the ROS sicklms driver quotes it: 8191 not valid, 8190 dazzling, 8189 overflow, 8187 signal to
 * noise too small, 8186 channel 1 error, 8183 "measured value > maximum value"; 32767 ... 32759
 * in the 32 m modes). The model sends the last where nothing returns within range. */
#define LMS2XX_CODE_OVER_RANGE_BELOW_TOP 8u

/* Sizes. A 0.25 degree scan (401 values) is the longest telegram: 4 + 1 + 2 + 802 + 1 + 2. */
#define LMS2XX_MAX_VALUES 401
#define LMS2XX_MAX_TELEGRAM 812
#define LMS2XX_MAX_REQUEST_DATA 256 /* longer announced lengths are taken for garbage */
#define LMS2XX_CONFIG_BYTES 34      /* configuration blocks A..A4 of 0x74/0x77 */
#define LMS2XX_STATUS_BYTES 152     /* data bytes of the 0xB1 status reply */
#define LMS2XX_MAX_JOBS 4
#define LMS2XX_JOB_BYTES 192
#define LMS2XX_TYPE_CHARS 20

/* Timing. The mirror turns at 75 Hz (technical description: scan time 13.33 ms); a 0.5 degree
 * scan interlaces 2 sweeps, a 0.25 degree scan 4 (26.7 / 53.3 ms, as the ROS sicklms node
 * assumes). The delays are this model's choices within what drivers allow: Player waits 1 s for
 * an ACK or reply, sicktoolbox 1 s (3 s for mode changes, 15 s for a configuration write). */
#define LMS2XX_SWEEP_NS_NUM INT64_C(40000000) /* one sweep = 40e6 / 3 ns */
#define LMS2XX_SWEEP_NS_DEN INT64_C(3)
#define LMS2XX_ACK_DELAY_NS INT64_C(1000000)        /* last request byte -> ACK starts */
#define LMS2XX_REPLY_DELAY_NS INT64_C(2000000)      /* last request byte -> reply may start */
#define LMS2XX_CONFIG_WRITE_NS INT64_C(500000000)   /* EEPROM write before 0xF7 */
#define LMS2XX_DEFAULT_POWER_UP_NS INT64_C(5000000000)
#define LMS2XX_POWER_UP_BAUD 9600u

/* Where scans come from: the simulator casts rays; tests give geometry. Angles in radians in the
 * scanner's own convention (0 = its right, pi/2 = straight ahead, increasing counter-clockwise seen
 * from above), ranges in metres, INFINITY where nothing returns. Called only for a scan that will
 * be sent, once per mirror sweep that scan interlaces (time_ns = the sweep's start). */
struct lms2xx_scan_source {
  void (*measure)(void *context, int64_t time_ns, double first_rad, double step_rad, uint32_t count, double *out_m);
  void *context;
};

struct lms2xx_config {
  char type[LMS2XX_TYPE_CHARS + 1]; /* answer to 0x3A, e.g. "LMS200;30106" */
  uint64_t seed;                    /* noise stream */
  int64_t power_up_ns;              /* power-on (or reset) to the 0x90 message */
  double noise_sd_mm_mode_m;        /* range noise, 1 sigma, in mm mode ... */
  double noise_sd_cm_mode_m;        /* ... and in cm mode; 0 gives exact geometry */
  uint16_t scan_angle_deg;          /* variant at power-up: 180 or 100 */
  uint16_t resolution_cdeg;         /* 100, 50 or 25 (1/100 degree) */
  uint8_t units;                    /* LMS2XX_UNITS_* at power-up */
  uint8_t measuring_mode;           /* LMS2XX_MEAS_* at power-up */
};

/* The LMS200 factory state (Quick Manual for LMS communication setup, "LMS default settings":
 * 9600 baud, 180 degrees at 0.5 degree, cm, 8/80 m) and datasheet noise (technical description
 * LMS200: statistical error 1 sigma 5 mm in mm mode; 1 cm taken for cm mode). */
void lms2xx_default_config(struct lms2xx_config *c);

/* A reply or scan waiting for the line. */
struct lms2xx_job {
  int64_t due_ns;
  uint8_t kind;
  uint8_t after;      /* what happens once its last byte is out: baud switch, reset */
  uint16_t len;
  uint32_t after_arg;
  uint8_t bytes[LMS2XX_JOB_BYTES];
};

/* The whole device state; caller-owned, fixed size, no allocation. Read-only to callers. */
struct lms2xx {
  struct lms2xx_config config;
  struct lms2xx_scan_source source;
  int64_t power_on_ns;
  int64_t booting_until_ns; /* receiver deaf and mirror data not served until then */
  int64_t latest_ns;        /* latest time the model has been told about */

  /* settings */
  uint32_t baud;           /* both directions */
  int64_t baud_since_ns;   /* when `baud` took effect */
  uint32_t pending_baud;   /* 0 or the rate taking over at pending_baud_ns */
  int64_t pending_baud_ns;
  uint8_t mode;
  uint16_t scan_angle_deg;
  uint16_t resolution_cdeg;
  uint8_t cfg[LMS2XX_CONFIG_BYTES];

  /* receiver */
  uint8_t rx[4 + LMS2XX_MAX_REQUEST_DATA + 2];
  size_t rx_len;

  /* transmitter: the telegram on the line, and what waits for it */
  uint8_t tx[LMS2XX_MAX_TELEGRAM];
  size_t tx_len, tx_pos;
  int64_t tx_next_ns; /* start of the next byte, or when the line fell idle */
  uint32_t tx_baud;
  uint8_t tx_after; /* what happens once the telegram on the line has ended */
  struct lms2xx_job jobs[LMS2XX_MAX_JOBS];
  size_t job_count;

  /* scans: sweeps are numbered from power-on; a scan is named by its last sweep */
  int64_t last_sent_sweep;
  uint64_t scans_sent;      /* 0xB0 telegrams built, each after casting its scan */
  double scratch_m[LMS2XX_MAX_VALUES];
};

void lms2xx_init(struct lms2xx *s, const struct lms2xx_config *c, struct lms2xx_scan_source source, int64_t power_on_ns);

/* A byte from the host, as the device's receiver decoded it (its end time and value). A byte
 * sent at another rate than the receiver's is a framing error and breaks the telegram it is in. */
void lms2xx_receive(struct lms2xx *s, const struct serial_byte *b);

/* Appends to out (at most cap) every byte whose stop bit ends before until_ns, in order, each
 * stamped and with the baud it was sent at. Every new transmission (ACK, reply, scan) starts at
 * or after now_ns; bytes of a telegram already under way follow back to back, so a byte that
 * straddled the last until_ns comes now with its start before now_ns. Called with non-decreasing
 * now_ns/until_ns. Returns the count; bytes not returned because of cap stay queued. */
size_t lms2xx_transmit(struct lms2xx *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out, size_t cap);

/* The rate its receiver listens at now (at the latest time it has been told about). */
uint32_t lms2xx_baud(const struct lms2xx *s);
/* When that rate took effect: a host reading the line needs the instant, not the call it learnt it in. */
int64_t lms2xx_baud_since_ns(const struct lms2xx *s);

/* The status reply's baud word for a rate (LMS2XX_STATUS_BAUD_*), 0 for a rate it does not have. */
uint16_t lms2xx_status_baud_code(uint32_t baud);

/* SICK's CRC-16 (generator 0x8005, each step folds in the current and the previous byte). */
uint16_t lms2xx_crc(const uint8_t *data, size_t len);

/* A request telegram to the scanner: STX, 0x00, length, command and data, CRC low byte first.
 * payload = command byte and its data. Returns the telegram's length, 0 if cap is too small. */
size_t lms2xx_encode_request(const uint8_t *payload, size_t payload_len, uint8_t *out, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
