/* Wall follower for the rover with a SICK LMS200 laser scanner on UART1: configures the scanner
 * (baud rate, 180 degree / 0.5 degree variant, continuous output), parses its telegrams and checks
 * their CRCs here, and keeps a wall about 0.5 m off the right side, slowing down and turning left
 * for whatever is ahead. The protocol is SICK's "Telegrams for Configuring and Operating the
 * LMS2xx Laser Measurement Systems" (the telegram listing): the telegram frame and its CRC,
 * commands 20h (operating mode and baud rate: 24h, 25h, 40h 38400, 41h 19200, 42h 9600, 48h
 * 500 kbaud), 3Bh (variant) and the B0h measured values; the codes agree with sicktoolbox's.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI_F 3.14159265f
#define CONSOLE 0
#define LMS 1 /* UART1: TX1 pin 18 to the scanner's RxD, RX1 pin 19 from its TxD */

/* Motor Shield R3: channel A drives the left motor, channel B the right one. */
#define LEFT_PWM 3
#define LEFT_DIR 12
#define LEFT_BRAKE 9
#define RIGHT_PWM 11
#define RIGHT_DIR 13
#define RIGHT_BRAKE 8

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
#define CMD_SCAN 0xB0     /* continuous scan data (a reply without a request) */
#define CMD_POWER_UP 0x90 /* sent once the scanner has finished its self test */

/* 180 degrees at 0.5 degree (interlaced: two mirror turns per scan) gives 361 values, so the
 * longest telegram is STX, address, length (2), command, count (2), 361 * 2, status, CRC (2). */
#define SCAN_ANGLE 180
#define SCAN_RES_CDEG 50
#define SCAN_VALUES 361
#define TELEGRAM_MAX (4 + 1 + 2 + 2 * SCAN_VALUES + 1 + 2)

#define FAST_BAUD 500000uL /* RS-422 rate; 38400 is the fastest over RS-232 */
#define FAST_MODE MODE_500K

/* Geometry and control, in millimetres (int) or metres and radians (float). */
#define HALF_WIDTH_MM 250 /* the rover is 0.25 m wide over its tyres, plus a margin each side */
#define BESIDE_MM 400     /* points right of the rover and at most this far ahead are beside it */
#define ON_LINE_MM 60     /* a wall's points lie this close to one line: the scan's noise and more */
#define WALL_M 0.5f       /* wanted distance from the wall on the right */
#define WALL_SEEN_MM 2500 /* beyond this the right side counts as open */
#define SLOW_MM 1000      /* start slowing down and turning left for things ahead */
#define STOP_MM 380       /* turn on the spot below this */
#define CRUISE 140        /* PWM duty of 255 */
#define CREEP 80
#define SPIN 120
#define K_DIST 2.0f  /* steer per metre of distance error */
#define K_ANGLE 1.2f /* steer per radian of heading towards the wall */
#define STEER_MAX 0.8f

/* Receiving. The UART1 interrupt only queues bytes in a ring; the main loop frames them here.
 * At 500 kbaud a byte comes every 20 us, too often to do more in the interrupt, and framing in
 * the main loop can afford to go back: when a candidate telegram fails (an STX that was really
 * data or line noise, a length that does not fit, a wrong CRC), the hunt resumes at the next STX
 * after the false one, among the bytes already taken, so that a false start cannot swallow the
 * real telegram behind it. The stream has no pauses long enough to rely on for that. */
#define RING 512 /* 10 ms at 500 kbaud: the main loop comes back sooner than that */
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

static uint8_t telegram[TELEGRAM_MAX]; /* the candidate, from its STX on */
static uint16_t have;                  /* bytes in it; 0 while hunting */
static uint8_t telegram_ready;         /* a whole, checked telegram waits in telegram[] */
static uint8_t acks, naks;
static uint16_t crc_errors, bad_headers;

/* SICK's CRC-16 (telegram listing, appendix "CRC calculation"): shift left, xor the generator
 * 8005h on a carry out, then xor in the current byte as the low and the previous byte as the high
 * half; the register and the "previous byte" start at 0, and it runs from STX to the last byte
 * before the CRC. Not the CRC-16/ARC of the same generator: the previous byte takes part. */
static uint16_t sick_crc_step(uint16_t crc, uint8_t previous, uint8_t byte) {
  crc = (crc & 0x8000u) ? (uint16_t)(((crc & 0x7FFFu) << 1) ^ 0x8005u) : (uint16_t)(crc << 1);
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
  if (length < 2 || length > TELEGRAM_MAX - 6u) return BAD_HEADER;
  if (n >= 5 && !(t[4] & REPLY)) return BAD_HEADER;
  if (n >= 7 && t[4] == CMD_SCAN && length != 1u + 2u + 2u * ((t[5] | ((uint16_t)t[6] << 8)) & 0x3FFu) + 1u)
    return BAD_HEADER;
  if (n < length + 6u) return PARTIAL;
  const uint16_t sent = (uint16_t)(t[length + 4u] | ((uint16_t)t[length + 5u] << 8));
  return sent == sick_crc(t, (uint16_t)(length + 4u)) ? COMPLETE : BAD_CRC;
}

static void take_byte(uint8_t byte) {
  if (have == 0) {
    if (byte == STX) telegram[have++] = byte;
    else if (byte == ACK) acks++;
    else if (byte == NAK) naks++;
    /* anything else between telegrams is line noise */
    return;
  }
  telegram[have++] = byte;
  /* Past the header and short of the CRC there is nothing to judge: on the AVR this is most of
   * 27 000 bytes a second, so it is kept short. */
  if (have > 7 && have < (uint16_t)(telegram[2] | ((uint16_t)telegram[3] << 8)) + 6u) return;
  for (;;) {
    const uint8_t verdict = judge(telegram, have);
    if (verdict == PARTIAL) return;
    if (verdict == COMPLETE) {
      telegram_ready = 1;
      have = 0;
      return;
    }
    if (verdict == BAD_CRC) crc_errors++;
    else bad_headers++;
    /* Go back to the next STX after the false one; without one, hunt among new bytes. */
    uint16_t next = 1;
    while (next < have && telegram[next] != STX) ++next;
    memmove(telegram, telegram + next, (size_t)(have - next));
    have = (uint16_t)(have - next);
    if (have == 0) return;
  }
}

/* Frames the bytes queued so far, stopping at a complete telegram. Returns telegram_ready. */
static uint8_t lms_poll(void) {
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

static void release_telegram(void) { telegram_ready = 0; }

/* Forgets every byte and candidate so far, as after a change of baud rate. */
static void lms_flush(void) {
  irq_disable();
  ring_tail = ring_head;
  irq_enable();
  have = 0;
  telegram_ready = 0;
}

static void say(const char *text) { uart_print(CONSOLE, text); }

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
    uart_write(LMS, head[i]);
    crc = sick_crc_step(crc, previous, head[i]);
    previous = head[i];
  }
  for (uint8_t i = 0; i < n; ++i) {
    uart_write(LMS, body[i]);
    crc = sick_crc_step(crc, previous, body[i]);
    previous = body[i];
  }
  uart_write(LMS, (uint8_t)(crc & 0xFF));
  uart_write(LMS, (uint8_t)(crc >> 8));
}

/* Sends a request and waits for its ACK and then its reply telegram (other telegrams, such as
 * scans still streaming, are passed over). Returns 1 with the reply held in telegram[] (the
 * caller releases it), or 0 after a NAK or timeout_ms without an answer. */
static uint8_t lms_request(const uint8_t *body, uint8_t n, uint16_t timeout_ms) {
  release_telegram();
  acks = 0;
  naks = 0;
  lms_send(body, n);
  const uint32_t start = millis();
  while (millis() - start < timeout_ms) {
    if (naks) return 0;
    if (lms_poll()) {
      if (acks && telegram[4] == (uint8_t)(body[0] | REPLY)) return 1;
      release_telegram();
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
      const uint8_t ok = telegram[5] == 0x00;
      release_telegram();
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
      const uint8_t ok = telegram[5] == 0x01 && telegram[6] == body[1] && telegram[7] == body[2] &&
                         telegram[8] == body[3] && telegram[9] == body[4];
      release_telegram();
      if (ok) return 1;
    }
  }
  return 0;
}

static const uint32_t probe_bauds[] = {9600uL, FAST_BAUD, 38400uL, 19200uL};

/* Finds the scanner's rate (9600 after power-up, the fast rate after a reset of this board
 * alone), stops any streaming, moves it to the fast rate and configures the scan. */
static void lms_configure(void) {
  char line[72];
  uart_begin(LMS, 9600);
  /* The power-up telegram says the self test is over; after a reset of this board alone there is
   * none, so a few seconds without it is no failure. */
  const uint32_t start = millis();
  while (millis() - start < 3000u) {
    if (lms_poll()) {
      const uint8_t cmd = telegram[4];
      release_telegram();
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
      uart_begin(LMS, probe_bauds[i]);
      lms_flush();
      if (lms_mode(MODE_REQUEST, PROBE_MS)) baud = probe_bauds[i];
    }
    if (!baud) say("lms: no answer at any rate, trying again\r\n");
  }
  snprintf(line, sizeof line, "lms: answering at %lu baud\r\n", (unsigned long)baud);
  say(line);
  if (baud != FAST_BAUD) {
    /* Answered at the old rate; both ends switch once the reply is in. */
    if (!lms_mode(FAST_MODE, CONFIG_MS)) say("lms: baud change refused\r\n");
    else {
      uart_begin(LMS, FAST_BAUD);
      lms_flush();
    }
    if (!lms_mode(MODE_REQUEST, CONFIG_MS)) say("lms: silent at the new rate\r\n");
  }
  if (!lms_variant(SCAN_ANGLE, SCAN_RES_CDEG)) say("lms: variant refused\r\n");
  if (!lms_mode(MODE_CONTINUOUS, CONFIG_MS)) say("lms: continuous mode refused\r\n");
  snprintf(line, sizeof line, "lms: %u deg at 0.%02u deg, streaming at %lu baud\r\n", SCAN_ANGLE, SCAN_RES_CDEG,
           (unsigned long)FAST_BAUD);
  say(line);
}

/* sin(k/2 degrees) for k = 0..180, scaled by 2^14, filled once at start-up. */
static int16_t sin_half_deg[181];

static void fill_sin_table(void) {
  for (uint16_t k = 0; k <= 180; ++k)
    sin_half_deg[k] = (int16_t)lroundf(16384.0f * sinf((float)k * PI_F / 360.0f));
}

static int16_t sin_k(uint16_t k) { return k <= 180 ? sin_half_deg[k] : sin_half_deg[360 - k]; }
static int16_t cos_k(uint16_t k) { return k <= 180 ? sin_half_deg[180 - k] : (int16_t)-sin_half_deg[k - 180]; }

/* Value i of a scan in millimetres. The count word's bits 14-15 give the unit (00 cm, 01 mm;
 * the main loop passes over anything else); bits 0-12 of a value are the distance, the top ones
 * flags. Codes from 8183 up mean no measurement (dazzle, no reflection, out of range), and they
 * count as nothing seen. */
#define NOTHING_MM 8000u
static uint16_t range_mm(uint16_t i, uint8_t unit) {
  const uint16_t raw =
      (uint16_t)((telegram[7 + 2 * i] | ((uint16_t)telegram[8 + 2 * i] << 8)) & 0x1FFFu);
  if (raw >= 8183u || raw == 0) return NOTHING_MM;
  const uint32_t mm = unit == 0 ? raw * 10uL : raw;
  return mm > NOTHING_MM ? NOTHING_MM : (uint16_t)mm;
}

/* The nearest return among values from..to, as a point in the scanner's frame (x ahead, y left). */
struct point {
  int32_t x, y;
  uint16_t r;
};
static struct point nearest(uint16_t from, uint16_t to, uint8_t unit) {
  struct point p = {0, 0, NOTHING_MM};
  uint16_t best = from;
  for (uint16_t i = from; i <= to; ++i) {
    const uint16_t r = range_mm(i, unit);
    if (r < p.r) {
      p.r = r;
      best = i;
    }
  }
  /* value i looks i/2 degrees left of the scanner's right, i.e. at (i/2 - 90) degrees */
  p.x = ((int32_t)p.r * sin_k(best)) >> 14;
  p.y = -(((int32_t)p.r * cos_k(best)) >> 14);
  return p;
}

struct view {
  uint16_t ahead_mm; /* nearest thing in the rover's path */
  uint8_t wall;      /* a wall on the right */
  float wall_m;      /* its distance from the scanner's axis, or of anything closer beside it */
  float wall_rad;    /* its direction: positive when the rover heads towards it */
};

static struct view look(uint8_t unit) {
  struct view v;
  v.ahead_mm = NOTHING_MM;
  uint16_t beside_mm = NOTHING_MM;
  for (uint16_t i = 0; i < SCAN_VALUES; ++i) {
    const uint16_t r = range_mm(i, unit);
    if (r >= NOTHING_MM) continue;
    const int32_t x = ((int32_t)r * sin_k(i)) >> 14;
    const int32_t y = -(((int32_t)r * cos_k(i)) >> 14);
    if (x > 0 && x < v.ahead_mm && y > -HALF_WIDTH_MM && y < HALF_WIDTH_MM) v.ahead_mm = (uint16_t)x;
    if (y < 0 && x < BESIDE_MM && -y < beside_mm) beside_mm = (uint16_t)-y;
  }
  /* Two points on the right wall, one abeam (-90..-88 degrees) and one ahead of it (-52..-48):
   * the line through them gives the wall's distance and direction, if a third point between them
   * (-72..-68) lies on it too. Otherwise they are on different things (a box abeam, the wall
   * behind it ahead), the line means nothing, and whatever is nearest beside the rover is the
   * distance to keep. */
  const struct point abeam = nearest(0, 4, unit);
  const struct point fore = nearest(76, 84, unit);
  const struct point middle = nearest(36, 44, unit);
  v.wall = abeam.r < WALL_SEEN_MM || fore.r < WALL_SEEN_MM || beside_mm < WALL_SEEN_MM;
  v.wall_m = (float)beside_mm / 1000.0f;
  v.wall_rad = 0;
  if (abeam.r < WALL_SEEN_MM && fore.r < WALL_SEEN_MM && middle.r < WALL_SEEN_MM) {
    const float dx = (float)(fore.x - abeam.x), dy = (float)(fore.y - abeam.y);
    const float length = sqrtf(dx * dx + dy * dy);
    const float off_line =
        fabsf((float)(middle.x - abeam.x) * dy - (float)(middle.y - abeam.y) * dx) / (length + 1.0f);
    if (length > 1.0f && off_line < (float)ON_LINE_MM) {
      v.wall_rad = atan2f(dy, dx);
      v.wall_m = fabsf((float)abeam.x * dy - (float)abeam.y * dx) / length / 1000.0f;
    }
  }
  return v;
}

/* One motor: speed -255..255, negative backwards. */
static void motor(uint8_t pwm_pin, uint8_t dir_pin, uint8_t brake_pin, int16_t speed) {
  digital_write(brake_pin, LOW);
  digital_write(dir_pin, speed >= 0 ? HIGH : LOW);
  pwm_write(pwm_pin, (uint8_t)(speed >= 0 ? speed : -speed));
}

static int16_t clamp_duty(float duty) {
  if (duty > 255.0f) return 255;
  if (duty < -255.0f) return -255;
  return (int16_t)duty;
}

/* steer -1..1, positive to the left */
static void drive(int16_t base, float steer) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, clamp_duty((float)base * (1.0f - steer)));
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, clamp_duty((float)base * (1.0f + steer)));
}

static void spin_left(void) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, -SPIN);
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, SPIN);
}

/* The wall follower's rule: a speed and a steer (-1..1, positive left) for what the scan shows;
 * returns 1 to turn left on the spot instead. */
static uint8_t decide(const struct view *v, int16_t *base, float *steer) {
  if (v->ahead_mm < STOP_MM) {
    *base = 0;
    *steer = 1;
    return 1;
  }
  float s = v->wall ? K_ANGLE * v->wall_rad - K_DIST * (v->wall_m - WALL_M)
                    : -0.25f; /* open on the right: arc right until a wall turns up */
  *base = CRUISE;
  if (v->ahead_mm < SLOW_MM) {
    /* closer: slower and further left, so that a corner ahead becomes the next wall */
    const float near = (float)(SLOW_MM - v->ahead_mm) / (float)(SLOW_MM - STOP_MM);
    *base = (int16_t)(CREEP + (float)(CRUISE - CREEP) * (1.0f - near));
    s += near;
  }
  if (s > STEER_MAX) s = STEER_MAX;
  if (s < -STEER_MAX) s = -STEER_MAX;
  *steer = s;
  return 0;
}

/* "1.23" for a distance in millimetres */
static void metres(char *out, uint8_t size, uint16_t mm) {
  snprintf(out, size, "%u.%02u", mm / 1000u, (mm % 1000u) / 10u);
}

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  pin_mode(LEFT_DIR, OUTPUT);
  pin_mode(LEFT_BRAKE, OUTPUT);
  pin_mode(RIGHT_DIR, OUTPUT);
  pin_mode(RIGHT_BRAKE, OUTPUT);
  drive(0, 0);
  fill_sin_table();
  say("wall_follower: ready\r\n");
  irq_attach_uart_rx(LMS, on_lms_byte);
  lms_configure();

  uint32_t scans = 0, last_scan_ms = millis(), next_report_ms = millis();
  uint16_t odd_scans = 0;
  float steer = 0;
  struct view v = {NOTHING_MM, 0, 0, 0};
  char line[96], right[8], ahead[8];
  for (;;) {
    if (lms_poll()) {
      const uint8_t cmd = telegram[4];
      const uint16_t count = (uint16_t)(telegram[5] | ((uint16_t)telegram[6] << 8));
      if (cmd == CMD_SCAN && (count & 0x3FFu) == SCAN_VALUES && (count >> 14) <= 1) {
        v = look((uint8_t)(count >> 14));
        scans++;
        last_scan_ms = millis();
      } else if (cmd == CMD_SCAN) {
        odd_scans++;
      }
      release_telegram();

      int16_t base;
      if (decide(&v, &base, &steer)) spin_left();
      else drive(base, steer);
    } else if (millis() - last_scan_ms > 500u) {
      steer = 0;
      drive(0, 0); /* blind: stand still until scans come back */
    }

    if ((int32_t)(millis() - next_report_ms) >= 0) {
      next_report_ms += 500u;
      metres(right, sizeof right, v.wall ? (uint16_t)(v.wall_m * 1000.0f) : NOTHING_MM);
      metres(ahead, sizeof ahead, v.ahead_mm);
      const int16_t s = (int16_t)lroundf(steer * 100.0f);
      const uint16_t s_abs = (uint16_t)(s < 0 ? -s : s);
      snprintf(line, sizeof line, "scan %lu: right %s m, ahead %s m, steer %c%u.%02u, crc errors %u\r\n",
               (unsigned long)scans, v.wall ? right : "--", ahead, s < 0 ? '-' : '+', s_abs / 100u, s_abs % 100u,
               crc_errors);
      say(line);
      if (odd_scans) {
        snprintf(line, sizeof line, "  %u scans of an unexpected size or unit\r\n", odd_scans);
        say(line);
        odd_scans = 0;
      }
    }
    delay_ms(1);
  }
}
