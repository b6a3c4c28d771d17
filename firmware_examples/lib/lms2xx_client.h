/* The MCU side of a SICK LMS200/LMS291 on a UART: configuration (baud rate, 180 degree / 0.5
 * degree variant, continuous output) and the framing, CRC check and decoding of its telegrams.
 * Shared by the wall follower and the rover. */
#ifndef FIRMWARE_LMS2XX_CLIENT_H
#define FIRMWARE_LMS2XX_CLIENT_H
#include <stdint.h>

#define LMS_CMD_SCAN 0xB0 /* continuous scan data (a reply without a request) */

/* 180 degrees at 0.5 degree (interlaced: two mirror turns per scan) gives 361 values, so the
 * longest telegram is STX, address, length (2), command, count (2), 361 * 2, status, CRC (2). */
#define LMS_SCAN_ANGLE 180
#define LMS_SCAN_RES_CDEG 50
#define LMS_SCAN_VALUES 361
#define LMS_TELEGRAM_MAX (4 + 1 + 2 + 2 * LMS_SCAN_VALUES + 1 + 2)
#define LMS_FAST_BAUD 500000uL /* RS-422 rate; 38400 is the fastest over RS-232 */

/* A distance no return was had for, or beyond what the examples care about. */
#define LMS_NOTHING_MM 8000u

/* The last complete telegram (valid while lms_poll() returns 1, until lms_release()): [4] is its
 * command, [5..6] a scan's count word. */
extern uint8_t lms_telegram[LMS_TELEGRAM_MAX];
extern uint16_t lms_crc_errors;

/* Takes the scanner's bytes on `port` in its RX interrupt, then finds its rate, moves it to
 * LMS_FAST_BAUD and configures the scan, saying how it went on the console (port 0). Blocks
 * until the scanner has answered at some rate. */
void lms_start(uint8_t port);

/* Frames the bytes queued so far, stopping at a complete telegram. Returns 1 while one waits. */
uint8_t lms_poll(void);
void lms_release(void);

/* For a telegram that is a scan of the configured variant, its unit (0 cm, 1 mm); else -1. */
int8_t lms_scan_unit(void);

/* Value i (0..360, i/2 degrees left of the scanner's right) of the scan held, in millimetres,
 * LMS_NOTHING_MM for no measurement. */
uint16_t lms_range_mm(uint16_t i, uint8_t unit);

/* sin and cos of value i's direction from the scanner's right (i/2 degrees), scaled by 2^14:
 * a point is x = r * sin (ahead), y = -r * cos (left). lms_fill_sin_table() first. */
void lms_fill_sin_table(void);
int16_t lms_sin_k(uint16_t k);
int16_t lms_cos_k(uint16_t k);

#endif
