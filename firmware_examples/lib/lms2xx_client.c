/* The MCU side of a SICK LMS2xx: see lms2xx_client.h. The protocol is SICK's "Telegrams for
 * Configuring and Operating the LMS2xx Laser Measurement Systems" (the telegram listing): the
 * telegram frame and its CRC, commands 20h (operating mode and baud rate: 24h, 25h, 40h 38400, 41h
 * 19200, 42h 9600, 48h 500 kbaud), 3Bh (variant) and the B0h measured values; the codes agree
 * with sicktoolbox's. Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include "lms2xx_client.h"

#include <hal/hal.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI_F 3.14159265f

/* Telegram framing, from the telegram listing. */
#define STX 0x02
#define ACK 0x06
#define NAK 0x15
#define TO_LMS 0x00   /* address byte of a request */
#define FROM_LMS 0x80 /* a reply's address has bit 7 set */
#define REPLY 0x80    /* reply command = request command + 80h */

#define CMD_MODE 0x20
#define MODE_CONTINUOUS 0x24 /* monitoring: all measured values, continuously */
#define MODE_REQUEST 0x25    /* monitoring: values only on request, i.e. streaming stops */
#define MODE_38400 0x40
#define MODE_19200 0x41
#define MODE_9600 0x42
#define MODE_500K 0x48
#define CMD_VARIANT 0x3B
#define CMD_POWER_UP 0x90 /* sent once the scanner has finished its self test */

#define FAST_MODE MODE_500K /* 48h: LMS_FAST_BAUD */

/* Receiving. The UART interrupt only queues bytes in a ring; the main loop frames them here.
 * At 500 kbaud a byte comes every 20 us, too often to do more in the interrupt, and framing in
 * the main loop can afford to go back: when a candidate telegram fails (an STX that was really
 * data or line noise, a length that does not fit, a wrong CRC), the hunt resumes at the next STX
 * after the false one, among the bytes already taken, so that a false start cannot swallow the
 * real telegram behind it. The stream has no pauses long enough to rely on for that. */
/* 41 ms at 500 kbaud. The reference rover's main loop on the ATmega2560 (the AVR engine's
 * instruction-accurate run) takes 4 ms on average but up to 18 ms now and then, with a report to
 * format or a compass to read, and a scan comes as 732 bytes back to back in 14.6 ms: 512 bytes
 * overflowed every few scans, and a scan short of one byte is lost. A power of two, so that the
 * 16-bit indices wrap with it. */
#define RING 2048
static uint8_t ring[RING];
static volatile uint16_t ring_head; /* written by the interrupt only */
static uint16_t ring_tail;          /* read by the interrupt, written with interrupts held off */
static volatile uint16_t ring_overruns;

static void on_lms_byte(uint8_t byte) {
  const uint16_t head = ring_head;
  if ((uint16_t)(head - ring_tail) >= RING) {
    ring_overruns++;
    return;
  }
  ring[head % RING] = byte;
  ring_head = (uint16_t)(head + 1u);
}

static uint8_t port;
uint8_t lms_telegram[LMS_TELEGRAM_MAX]; /* the candidate, from its STX on */
static uint16_t have;                   /* bytes in it; 0 while hunting */
static uint8_t telegram_ready;          /* a whole, checked telegram waits in lms_telegram[] */
static uint8_t acks, naks;
uint16_t lms_crc_errors;
static uint16_t bad_headers;

/* SICK's CRC-16 (telegram listing, appendix "CRC calculation"): shift left, xor the generator
 * 8005h on a carry out, then xor in the current byte as the low and the previous byte as the high
 * half; the register and the "previous byte" start at 0, and it runs from STX to the last byte
 * before the CRC. Not the CRC-16/ARC of the same generator: the previous byte takes part. */
static uint16_t sick_crc_step(uint16_t crc, uint8_t previous, uint8_t byte) {
  crc = (uint16_t)((crc & 0x8000u) ? ((crc & 0x7FFFu) << 1) ^ 0x8005u : (unsigned)crc << 1);
  return (uint16_t)(crc ^ (uint16_t)(((uint16_t)previous << 8) | byte));
}

static uint16_t sick_crc(const uint8_t *data, uint16_t n) {
  uint16_t crc = 0;
  uint8_t previous = 0;
  for (uint16_t i = 0; i < n; ++i) {
    crc = sick_crc_step(crc, previous, data[i]);
    previous = data[i];
  }
  return crc;
}

enum { PARTIAL, COMPLETE, BAD_HEADER, BAD_CRC };

/* What the first n bytes of a candidate are. Past STX: the address has bit 7 set in a reply; the
 * length counts command, data and status (so at least 2) and fits the buffer; every reply's
 * command has bit 7 set; a scan's length fits its count of values; then the CRC. */
static uint8_t judge(const uint8_t *t, uint16_t n) {
  if (n >= 2 && !(t[1] & FROM_LMS)) return BAD_HEADER;
  if (n < 4) return PARTIAL;
  const uint16_t length = (uint16_t)(t[2] | ((uint16_t)t[3] << 8));
  if (length < 2 || length > LMS_TELEGRAM_MAX - 6u) return BAD_HEADER;
  if (n >= 5 && !(t[4] & REPLY)) return BAD_HEADER;
  if (n >= 7 && t[4] == LMS_CMD_SCAN && length != 1u + 2u + 2u * ((t[5] | (unsigned)t[6] << 8) & 0x3FFu) + 1u)
    return BAD_HEADER;
  if (n < length + 6u) return PARTIAL;
  const uint16_t sent = (uint16_t)(t[length + 4u] | ((uint16_t)t[length + 5u] << 8));
  return sent == sick_crc(t, (uint16_t)(length + 4u)) ? COMPLETE : BAD_CRC;
}

static void take_byte(uint8_t byte) {
  if (have == 0) {
    if (byte == STX) lms_telegram[have++] = byte;
    else if (byte == ACK) acks++;
    else if (byte == NAK) naks++;
    /* anything else between telegrams is line noise */
    return;
  }
  lms_telegram[have++] = byte;
  /* Past the header and short of the CRC there is nothing to judge: on the AVR this is most of
   * 27 000 bytes a second, so it is kept short. */
  if (have > 7 && have < (uint16_t)(lms_telegram[2] | ((uint16_t)lms_telegram[3] << 8)) + 6u) return;
  for (;;) {
    const uint8_t verdict = judge(lms_telegram, have);
    if (verdict == PARTIAL) return;
    if (verdict == COMPLETE) {
      telegram_ready = 1;
      have = 0;
      return;
    }
    if (verdict == BAD_CRC) lms_crc_errors++;
    else bad_headers++;
    /* Go back to the next STX after the false one; without one, hunt among new bytes. */
    uint16_t next = 1;
    while (next < have && lms_telegram[next] != STX) ++next;
    memmove(lms_telegram, lms_telegram + next, (size_t)(have - next));
    have = (uint16_t)(have - next);
    if (have == 0) return;
  }
}

uint8_t lms_poll(void) {
  if (telegram_ready) return 1;
  irq_disable(); /* a 16-bit index is two byte reads on the AVR */
  const uint16_t head = ring_head;
  irq_enable();
  uint16_t tail = ring_tail;
  while (tail != head && !telegram_ready) {
    take_byte(ring[tail % RING]);
    tail++;
  }
  irq_disable();
  ring_tail = tail;
  irq_enable();
  return telegram_ready;
}

void lms_release(void) { telegram_ready = 0; }

/* Forgets every byte and candidate so far, as after a change of baud rate. */
static void lms_flush(void) {
  irq_disable();
  ring_tail = ring_head;
  irq_enable();
  have = 0;
  telegram_ready = 0;
}

static void say(const char *text) { uart_print(0, text); }

/* Sends a request telegram: command and data in body, n bytes. */
static void lms_send(const uint8_t *body, uint8_t n) {
  uint8_t head[4];
  head[0] = STX;
  head[1] = TO_LMS;
  head[2] = n;
  head[3] = 0;
  uint16_t crc = 0;
  uint8_t previous = 0;
  for (uint8_t i = 0; i < 4; ++i) {
    uart_write(port, head[i]);
    crc = sick_crc_step(crc, previous, head[i]);
    previous = head[i];
  }
  for (uint8_t i = 0; i < n; ++i) {
    uart_write(port, body[i]);
    crc = sick_crc_step(crc, previous, body[i]);
    previous = body[i];
  }
  uart_write(port, (uint8_t)(crc & 0xFF));
  uart_write(port, (uint8_t)(crc >> 8));
}

/* Sends a request and waits for its ACK and then its reply telegram (other telegrams, such as
 * scans still streaming, are passed over). Returns 1 with the reply held in lms_telegram[] (the
 * caller releases it), or 0 after a NAK or timeout_ms without an answer. */
static uint8_t lms_request(const uint8_t *body, uint8_t n, uint16_t timeout_ms) {
  lms_release();
  acks = 0;
  naks = 0;
  lms_send(body, n);
  const uint32_t start = millis();
  while (millis() - start < timeout_ms) {
    if (naks) return 0;
    if (lms_poll()) {
      if (acks && lms_telegram[4] == (uint8_t)(body[0] | REPLY)) return 1;
      lms_release();
    }
    delay_ms(1);
  }
  return 0;
}

/* A mode change (20h); its reply A0h carries 00h for success, then the status byte. Probing for
 * the rate waits briefly (the ACK is due within 60 ms); configuring waits longer, as the scanner
 * may take a while over a change that it stores. */
#define PROBE_MS 300
#define CONFIG_MS 3000
static uint8_t lms_mode(uint8_t mode, uint16_t timeout_ms) {
  const uint8_t body[2] = {CMD_MODE, mode};
  for (uint8_t attempt = 0; attempt < 3; ++attempt) {
    if (lms_request(body, 2, timeout_ms)) {
      const uint8_t ok = lms_telegram[5] == 0x00;
      lms_release();
      if (ok) return 1;
    }
  }
  return 0;
}

/* The variant (3Bh): angle and resolution, LE16 each; the reply BBh starts with 01h when taken,
 * followed by the angle and resolution now in force. */
static uint8_t lms_variant(uint16_t angle, uint16_t res_cdeg) {
  const uint8_t body[5] = {CMD_VARIANT, (uint8_t)(angle & 0xFF), (uint8_t)(angle >> 8), (uint8_t)(res_cdeg & 0xFF),
                           (uint8_t)(res_cdeg >> 8)};
  for (uint8_t attempt = 0; attempt < 3; ++attempt) {
    if (lms_request(body, 5, CONFIG_MS)) {
      const uint8_t ok = lms_telegram[5] == 0x01 && lms_telegram[6] == body[1] && lms_telegram[7] == body[2] &&
                         lms_telegram[8] == body[3] && lms_telegram[9] == body[4];
      lms_release();
      if (ok) return 1;
    }
  }
  return 0;
}

static const uint32_t probe_bauds[] = {9600uL, LMS_FAST_BAUD, 38400uL, 19200uL};

/* Finds the scanner's rate (9600 after power-up, the fast rate after a reset of this board
 * alone), stops any streaming, moves it to the fast rate and configures the scan. */
static void lms_configure(void) {
  char line[72];
  uart_begin(port, 9600);
  /* The power-up telegram says the self test is over; after a reset of this board alone there
   * is none, so a few seconds without it is no failure. */
  const uint32_t start = millis();
  while (millis() - start < 3000u) {
    if (lms_poll()) {
      const uint8_t cmd = lms_telegram[4];
      lms_release();
      if (cmd == CMD_POWER_UP) {
        say("lms: power-up telegram\r\n");
        break;
      }
    }
    delay_ms(2);
  }
  uint32_t baud = 0;
  while (!baud) {
    for (uint8_t i = 0; i < sizeof probe_bauds / sizeof probe_bauds[0] && !baud; ++i) {
      uart_begin(port, probe_bauds[i]);
      lms_flush();
      if (lms_mode(MODE_REQUEST, PROBE_MS)) baud = probe_bauds[i];
    }
    if (!baud) say("lms: no answer at any rate, trying again\r\n");
  }
  snprintf(line, sizeof line, "lms: answering at %lu baud\r\n", (unsigned long)baud);
  say(line);
  if (baud != LMS_FAST_BAUD) {
    /* Answered at the old rate; both ends switch once the reply is in. */
    if (!lms_mode(FAST_MODE, CONFIG_MS)) say("lms: baud change refused\r\n");
    else {
      uart_begin(port, LMS_FAST_BAUD);
      lms_flush();
    }
    if (!lms_mode(MODE_REQUEST, CONFIG_MS)) say("lms: silent at the new rate\r\n");
  }
  if (!lms_variant(LMS_SCAN_ANGLE, LMS_SCAN_RES_CDEG)) say("lms: variant refused\r\n");
  if (!lms_mode(MODE_CONTINUOUS, CONFIG_MS)) say("lms: continuous mode refused\r\n");
  snprintf(line, sizeof line, "lms: %u deg at 0.%02u deg, streaming at %lu baud\r\n", LMS_SCAN_ANGLE, LMS_SCAN_RES_CDEG,
           (unsigned long)LMS_FAST_BAUD);
  say(line);
}

/* sin(k/2 degrees) for k = 0..180, scaled by 2^14, filled once at start-up. */
static int16_t sin_half_deg[181];

void lms_fill_sin_table(void) {
  for (uint16_t k = 0; k <= 180; ++k)
    sin_half_deg[k] = (int16_t)lroundf(16384.0f * sinf((float)k * PI_F / 360.0f));
}

int16_t lms_sin_k(uint16_t k) { return k <= 180 ? sin_half_deg[k] : sin_half_deg[360 - k]; }
int16_t lms_cos_k(uint16_t k) { return k <= 180 ? sin_half_deg[180 - k] : (int16_t)-sin_half_deg[k - 180]; }

/* Value i of a scan in millimetres. The count word's bits 14-15 give the unit (00 cm, 01 mm;
 * lms_scan_unit() passes over anything else); bits 0-12 of a value are the distance, the top ones
 * flags. Codes from 8183 up mean no measurement (dazzle, no reflection, out of range), and they
 * count as nothing seen. */
uint16_t lms_range_mm(uint16_t i, uint8_t unit) {
  const uint16_t raw =
      (uint16_t)((lms_telegram[7 + 2 * i] | (unsigned)lms_telegram[8 + 2 * i] << 8) & 0x1FFFu);
  if (raw >= 8183u || raw == 0) return LMS_NOTHING_MM;
  const uint32_t mm = unit == 0 ? raw * 10uL : raw;
  return mm > LMS_NOTHING_MM ? LMS_NOTHING_MM : (uint16_t)mm;
}


int8_t lms_scan_unit(void) {
  const uint16_t count = (uint16_t)(lms_telegram[5] | ((uint16_t)lms_telegram[6] << 8));
  if (lms_telegram[4] != LMS_CMD_SCAN || (count & 0x3FFu) != LMS_SCAN_VALUES || (count >> 14) > 1) return -1;
  return (int8_t)(count >> 14);
}

void lms_start(uint8_t uart_port) {
  port = uart_port;
  irq_attach_uart_rx(port, on_lms_byte);
  lms_configure();
}
