/* LMS2xx telegram protocol: a byte-wise request parser that resynchronises on STX, a FIFO of
 * replies, and a transmitter that fills an idle line with the newest complete scan. */
#include "sick_lms2xx.h"

#include <math.h>
#include <string.h>

#include "noise.h"

#define PI 3.14159265358979323846

enum { JOB_RAW = 0, JOB_SCAN = 1 };
enum { AFTER_NONE = 0, AFTER_BAUD = 1, AFTER_RESET = 2 };

/* 0xA0 answer codes (telegram listing, 0x20 reply): 0 done, 1 wrong password, 2 not possible. */
#define MODE_OK 0x00u
#define MODE_BAD_PASSWORD 0x01u
#define MODE_NOT_POSSIBLE 0x02u

/* The LMS's factory password for installation mode, as every driver sends it. */
static const uint8_t install_password[8] = {'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'};

/* Configuration blocks (0x74 reply / 0x77 request, blocks A..A4), by byte offset. */
#define CFG_MEASURING_MODE 5
#define CFG_UNITS 6

/* Status reply (0xB1) byte offsets counted from the reply code, as sicktoolbox reads them. */
#define ST_VERSION 1
#define ST_MODE 8
#define ST_STATUS 9
#define ST_MEASURING_MODE 102
#define ST_ANGLE 107
#define ST_RESOLUTION 109
#define ST_BAUD 116           /* word: the current rate's code, below */
#define ST_PERMANENT_BAUD 119 /* 0: back to 9600 at power-on */
#define ST_UNITS 122
#define ST_LASER_ON 123

void lms2xx_default_config(struct lms2xx_config *c) {
  memset(c, 0, sizeof *c);
  memcpy(c->type, "LMS200;30106", 13);
  c->seed = 0;
  c->power_up_ns = LMS2XX_DEFAULT_POWER_UP_NS;
  c->noise_sd_mm_mode_m = 0.005;
  c->noise_sd_cm_mode_m = 0.01;
  c->scan_angle_deg = 180;
  c->resolution_cdeg = 50;
  c->units = LMS2XX_UNITS_CM;
  c->measuring_mode = LMS2XX_MEAS_8_80M_FA_FB_DAZZLE;
}

/* ---- CRC and framing ---- */

uint16_t lms2xx_crc(const uint8_t *data, size_t len) {
  /* Telegram listing, "Formation of the CRC16 checksum": shift, fold in the generator when the
   * top bit falls out, then xor the word (current byte low, previous byte high). */
  uint16_t crc = 0;
  uint8_t previous = 0;
  for (size_t i = 0; i < len; ++i) {
    const uint8_t current = data[i];
    if (crc & 0x8000u) {
      crc = (uint16_t)(((crc & 0x7FFFu) << 1) ^ LMS2XX_CRC_POLY);
    } else {
      crc = (uint16_t)(crc << 1);
    }
    crc ^= (uint16_t)(current | (previous << 8));
    previous = current;
  }
  return crc;
}

static void put16(uint8_t *p, uint32_t v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)((v >> 8) & 0xFFu);
}

size_t lms2xx_encode_request(const uint8_t *payload, size_t payload_len, uint8_t *out, size_t cap) {
  const size_t total = 4 + payload_len + 2;
  if (payload_len == 0 || payload_len > 0xFFFFu || total > cap) return 0;
  out[0] = LMS2XX_STX;
  out[1] = LMS2XX_HOST_ADDRESS;
  put16(out + 2, (uint32_t)payload_len);
  memcpy(out + 4, payload, payload_len);
  put16(out + 4 + payload_len, lms2xx_crc(out, 4 + payload_len));
  return total;
}

/* A reply: STX, 0x80, length (code + data + status), code, data, status, CRC. */
static size_t build_reply(uint8_t *out, uint8_t code, const uint8_t *data, size_t len) {
  out[0] = LMS2XX_STX;
  out[1] = LMS2XX_REPLY_ADDRESS;
  put16(out + 2, (uint32_t)(len + 2));
  out[4] = code;
  if (len) memcpy(out + 5, data, len);
  out[5 + len] = LMS2XX_STATUS_OK;
  put16(out + 6 + len, lms2xx_crc(out, 6 + len));
  return len + 8;
}

/* ---- baud rate over time ---- */

static uint32_t rate_at(const struct lms2xx *s, int64_t t) {
  if (s->pending_baud && t >= s->pending_baud_ns) return s->pending_baud;
  return s->baud;
}

static void apply_pending_baud(struct lms2xx *s, int64_t t) {
  if (s->pending_baud && t >= s->pending_baud_ns) {
    s->baud = s->pending_baud;
    s->baud_since_ns = s->pending_baud_ns;
    s->pending_baud = 0;
  }
}

uint32_t lms2xx_baud(const struct lms2xx *s) { return rate_at(s, s->latest_ns); }

int64_t lms2xx_baud_since_ns(const struct lms2xx *s) {
  if (s->pending_baud && s->latest_ns >= s->pending_baud_ns) return s->pending_baud_ns;
  return s->baud_since_ns;
}

static void note_time(struct lms2xx *s, int64_t t) {
  if (t > s->latest_ns) s->latest_ns = t;
}

/* ---- mirror sweeps and scans ---- */

static int64_t sweep_start(const struct lms2xx *s, int64_t r) {
  return s->power_on_ns + (r * LMS2XX_SWEEP_NS_NUM) / LMS2XX_SWEEP_NS_DEN;
}

/* Index of the last sweep finished by t (sweep r ends where r + 1 starts); -1 if none. */
static int64_t last_finished_sweep(const struct lms2xx *s, int64_t t) {
  if (t < s->power_on_ns) return -1;
  int64_t n = ((t - s->power_on_ns) * LMS2XX_SWEEP_NS_DEN) / LMS2XX_SWEEP_NS_NUM;
  while (sweep_start(s, n + 1) <= t) ++n;
  while (n > 0 && sweep_start(s, n) > t) --n;
  return n - 1;
}

/* Sweeps one scan interlaces: 1 at 1 degree, 2 at 0.5, 4 at 0.25 (each sweep samples 1 degree
 * steps, offset by a multiple of the resolution). */
static int64_t partials(const struct lms2xx *s) { return 100 / s->resolution_cdeg; }

static int streaming(const struct lms2xx *s) {
  return s->mode == LMS2XX_MODE_STREAM || s->mode == LMS2XX_MODE_STREAM_PARTIAL;
}

/* Sweeps that close a scan: every sweep when partial scans are sent, else every P-th. */
static int64_t sweeps_per_scan(const struct lms2xx *s) {
  return s->mode == LMS2XX_MODE_STREAM_PARTIAL ? 1 : partials(s);
}

static int64_t newest_scan_end(const struct lms2xx *s, int64_t t) {
  const int64_t k = sweeps_per_scan(s);
  const int64_t r = last_finished_sweep(s, t);
  if (r < 0) return -1;
  return ((r + 1) / k) * k - 1;
}

static int64_t next_scan_end(const struct lms2xx *s, int64_t after) {
  const int64_t k = sweeps_per_scan(s);
  if (after < -1) after = -1;
  return ((after + 1) / k + 1) * k - 1;
}

/* The scan a 0x30 request gets at t: the newest complete one (a single sweep when partial scans
 * are streamed). */
static int64_t newest_polled_scan(const struct lms2xx *s, int64_t t) {
  return s->mode == LMS2XX_MODE_STREAM_PARTIAL ? last_finished_sweep(s, t) : newest_scan_end(s, t);
}

static unsigned value_bits(uint8_t measuring_mode) {
  switch (measuring_mode) {
    case LMS2XX_MEAS_16M_REFLECTOR:
    case LMS2XX_MEAS_16M_FA_FB: return 14;
    case LMS2XX_MEAS_32M_REFLECTOR:
    case LMS2XX_MEAS_32M_FA:
    case LMS2XX_MEAS_32M_IMMEDIATE: return 15;
    default: return 13;
  }
}

/* LMS200 technical description: maximum range 80 m (cm mode); the mm-mode ranges end where
 * the mode's value field does, below its error codes. */
#define DEVICE_MAX_RANGE_M 80.0

/* The noise of a sweep's beams, drawn a Box-Muller pair at a time: beams 2i and 2i + 1 take the
 * two values of draw (sweep, 2i), which halves the logarithms and square roots a telegram costs.
 * A pair is drawn only when one of its beams is in range. */
struct beam_noise {
  uint64_t seed, sweep_key;
  int64_t pair; /* the pair held in z, -1 for none */
  double z[2];
};

static double beam_noise_of(struct beam_noise *n, uint32_t beam) {
  const int64_t pair = (int64_t)(beam >> 1);
  if (n->pair != pair) {
    noise_gaussian_pair(n->seed, n->sweep_key | (beam & ~1u), n->z);
    n->pair = pair;
  }
  return n->z[beam & 1u];
}

static uint16_t encode_range(const struct lms2xx *s, double r_m, struct beam_noise *noise, uint32_t beam) {
  const uint8_t units = s->cfg[CFG_UNITS];
  const uint32_t top = (1u << value_bits(s->cfg[CFG_MEASURING_MODE])) - 1u;
  const uint32_t over = top - LMS2XX_CODE_OVER_RANGE_BELOW_TOP;
  const double unit_m = units == LMS2XX_UNITS_MM ? 0.001 : 0.01;
  const double sd = units == LMS2XX_UNITS_MM ? s->config.noise_sd_mm_mode_m : s->config.noise_sd_cm_mode_m;
  if (!(r_m >= 0.0) || !isfinite(r_m) || r_m > DEVICE_MAX_RANGE_M) return (uint16_t)over;
  double noisy = r_m;
  if (sd > 0.0) noisy += sd * beam_noise_of(noise, beam);
  double code = floor(noisy / unit_m + 0.5);
  if (code < 0.0) code = 0.0;
  if (code >= (double)over) return (uint16_t)over;
  return (uint16_t)code;
}

/* Builds the 0xB0 telegram of the scan ending with sweep `last`: either the P sweeps it
 * interlaces, or (partial) that one sweep alone with its offset in the count word. */
static size_t build_scan(struct lms2xx *s, uint8_t *out, int64_t last, int partial) {
  const int64_t p = partials(s);
  const uint32_t res = s->resolution_cdeg;
  const uint32_t n_full = (uint32_t)s->scan_angle_deg * 100u / res + 1u;
  const double start_deg = s->scan_angle_deg == 180 ? 0.0 : 40.0;
  const double deg = PI / 180.0;
  const int64_t first_j = partial ? last % p : 0;
  const int64_t last_j = partial ? first_j : p - 1;
  uint8_t *values = out + 7;
  uint32_t count = 0;
  for (int64_t j = first_j; j <= last_j; ++j) {
    const int64_t sweep = partial ? last : last - (p - 1) + j;
    const uint32_t n = (n_full - 1u - (uint32_t)j) / (uint32_t)p + 1u;
    s->source.measure(s->source.context, sweep_start(s, sweep), (start_deg + (double)j * res / 100.0) * deg,
                      (double)p * res / 100.0 * deg, n, s->scratch_m);
    /* Draws are keyed by (sweep, beam), so a beam's noise never depends on what was sent. */
    struct beam_noise noise = {s->config.seed, (uint64_t)sweep << 10, -1, {0.0, 0.0}};
    for (uint32_t m = 0; m < n; ++m) {
      const uint16_t v = encode_range(s, s->scratch_m[m], &noise, m);
      const uint32_t at = partial ? m : (uint32_t)j + (uint32_t)p * m;
      put16(values + 2u * at, v);
    }
    count += n;
  }
  uint32_t word = count | ((uint32_t)s->cfg[CFG_UNITS] << LMS2XX_UNIT_SHIFT);
  if (partial && p > 1) word |= LMS2XX_PARTIAL_FLAG | ((uint32_t)(first_j * (4 / p)) << LMS2XX_PARTIAL_INDEX_SHIFT);
  const size_t len = 2 + 2u * count;
  out[0] = LMS2XX_STX;
  out[1] = LMS2XX_REPLY_ADDRESS;
  put16(out + 2, (uint32_t)(len + 2));
  out[4] = LMS2XX_CMD_VALUES | 0x80u;
  put16(out + 5, word);
  out[5 + len] = LMS2XX_STATUS_OK;
  put16(out + 6 + len, lms2xx_crc(out, 6 + len));
  s->scans_sent++;
  return len + 8;
}

/* ---- reply queue ---- */

static struct lms2xx_job *push_job(struct lms2xx *s, int64_t due, uint8_t kind) {
  if (s->job_count >= LMS2XX_MAX_JOBS) return NULL;
  struct lms2xx_job *j = &s->jobs[s->job_count++];
  memset(j, 0, sizeof *j);
  j->due_ns = due;
  j->kind = kind;
  return j;
}

static void push_byte(struct lms2xx *s, int64_t due, uint8_t byte) {
  struct lms2xx_job *j = push_job(s, due, JOB_RAW);
  if (!j) return;
  j->bytes[0] = byte;
  j->len = 1;
}

static struct lms2xx_job *push_reply(struct lms2xx *s, int64_t due, uint8_t code, const uint8_t *data, size_t len) {
  struct lms2xx_job *j = push_job(s, due, JOB_RAW);
  if (j) j->len = (uint16_t)build_reply(j->bytes, code, data, len);
  return j;
}

static void push_power_on(struct lms2xx *s, int64_t due) {
  /* The power-on message carries the type string (as 0xBA does). */
  push_reply(s, due, LMS2XX_REPLY_POWER_ON, (const uint8_t *)s->config.type, strlen(s->config.type));
}

/* ---- requests ---- */

static int valid_variant(uint32_t angle, uint32_t res) {
  if (angle == 180) return res == 100 || res == 50;
  if (angle == 100) return res == 100 || res == 50 || res == 25;
  return 0;
}

static int valid_config(const uint8_t *cfg) {
  const uint8_t m = cfg[CFG_MEASURING_MODE];
  const int mode_ok = m <= LMS2XX_MEAS_32M_FA || m == LMS2XX_MEAS_32M_IMMEDIATE;
  return mode_ok && (cfg[CFG_UNITS] == LMS2XX_UNITS_CM || cfg[CFG_UNITS] == LMS2XX_UNITS_MM);
}

static void mode_change(struct lms2xx *s, const uint8_t *d, size_t n, int64_t due) {
  uint8_t answer = MODE_OK;
  uint32_t baud = 0;
  switch (d[0]) {
    case LMS2XX_MODE_INSTALLATION:
      if (n >= 9 && memcmp(d + 1, install_password, sizeof install_password) == 0) s->mode = d[0];
      else answer = MODE_BAD_PASSWORD;
      break;
    case LMS2XX_MODE_STREAM:
    case LMS2XX_MODE_REQUEST:
    case LMS2XX_MODE_STREAM_PARTIAL: s->mode = d[0]; break;
    case LMS2XX_BAUD_9600: baud = 9600; break;
    case LMS2XX_BAUD_19200: baud = 19200; break;
    case LMS2XX_BAUD_38400: baud = 38400; break;
    case LMS2XX_BAUD_500000: baud = 500000; break;
    default: answer = MODE_NOT_POSSIBLE; break;
  }
  struct lms2xx_job *j = push_reply(s, due, LMS2XX_CMD_MODE | 0x80u, &answer, 1);
  if (j && baud) {
    j->after = AFTER_BAUD;
    j->after_arg = baud;
  }
}

uint16_t lms2xx_status_baud_code(uint32_t baud) {
  switch (baud) {
    case 9600: return LMS2XX_STATUS_BAUD_9600;
    case 19200: return LMS2XX_STATUS_BAUD_19200;
    case 38400: return LMS2XX_STATUS_BAUD_38400;
    case 500000: return LMS2XX_STATUS_BAUD_500000;
    default: return 0;
  }
}

static void status_reply(struct lms2xx *s, int64_t due) {
  uint8_t st[LMS2XX_STATUS_BYTES + 1];
  memset(st, 0, sizeof st);
  /* Firmware versions from the listing's version table: V02.30 (LMS200/220), X01.27 (211/221/291). */
  const int lms20x = strncmp(s->config.type, "LMS20", 5) == 0 || strncmp(s->config.type, "LMS22", 5) == 0;
  memcpy(st + ST_VERSION, lms20x ? "V02.30 " : "X01.27 ", 7);
  st[ST_MODE] = s->mode;
  st[ST_STATUS] = 0;
  st[ST_MEASURING_MODE] = s->cfg[CFG_MEASURING_MODE];
  put16(st + ST_ANGLE, s->scan_angle_deg);
  put16(st + ST_RESOLUTION, s->resolution_cdeg);
  put16(st + ST_BAUD, lms2xx_status_baud_code(s->baud));
  st[ST_PERMANENT_BAUD] = 0; /* a 0x20 baud change holds until power-off or reset */
  st[ST_UNITS] = s->cfg[CFG_UNITS];
  st[ST_LASER_ON] = 1;
  push_reply(s, due, LMS2XX_CMD_STATUS | 0x80u, st + 1, LMS2XX_STATUS_BYTES);
}

static void handle_request(struct lms2xx *s, const uint8_t *p, size_t n, int64_t end) {
  /* An ACK and a reply each need a slot; a device with both still queued ignores the request. */
  if (s->job_count + 2 > LMS2XX_MAX_JOBS) return;
  push_byte(s, end + LMS2XX_ACK_DELAY_NS, LMS2XX_ACK);
  const int64_t due = end + LMS2XX_REPLY_DELAY_NS;
  const uint8_t cmd = p[0];
  const uint8_t *d = p + 1;
  const size_t dn = n - 1;
  uint8_t buf[LMS2XX_CONFIG_BYTES + 5];
  switch (cmd) {
    case LMS2XX_CMD_RESET: {
      struct lms2xx_job *j = push_reply(s, due, LMS2XX_REPLY_RESET, NULL, 0);
      if (j) j->after = AFTER_RESET;
      return;
    }
    case LMS2XX_CMD_MODE:
      if (dn >= 1) {
        mode_change(s, d, dn, due);
        return;
      }
      break;
    case LMS2XX_CMD_VALUES:
      if (dn >= 1 && d[0] == 0x01) {
        push_job(s, due, JOB_SCAN);
        return;
      }
      break;
    case LMS2XX_CMD_STATUS: status_reply(s, due); return;
    case LMS2XX_CMD_ERRORS: push_reply(s, due, LMS2XX_CMD_ERRORS | 0x80u, NULL, 0); return;
    case LMS2XX_CMD_TYPE:
      push_reply(s, due, LMS2XX_CMD_TYPE | 0x80u, (const uint8_t *)s->config.type, strlen(s->config.type));
      return;
    case LMS2XX_CMD_VARIANT:
      if (dn >= 4) {
        const uint32_t angle = (uint32_t)d[0] | ((uint32_t)d[1] << 8);
        const uint32_t res = (uint32_t)d[2] | ((uint32_t)d[3] << 8);
        buf[0] = 0;
        if (valid_variant(angle, res)) {
          s->scan_angle_deg = (uint16_t)angle;
          s->resolution_cdeg = (uint16_t)res;
          buf[0] = 1;
        }
        put16(buf + 1, s->scan_angle_deg);
        put16(buf + 3, s->resolution_cdeg);
        push_reply(s, due, LMS2XX_CMD_VARIANT | 0x80u, buf, 5);
        return;
      }
      break;
    case LMS2XX_CMD_READ_CONFIG: push_reply(s, due, LMS2XX_CMD_READ_CONFIG | 0x80u, s->cfg, LMS2XX_CONFIG_BYTES); return;
    case LMS2XX_CMD_WRITE_CONFIG:
      if (dn >= LMS2XX_CONFIG_BYTES) {
        /* Accepted only in installation mode, as the listing requires for writing the EEPROM. */
        buf[0] = 0;
        if (s->mode == LMS2XX_MODE_INSTALLATION && valid_config(d)) {
          memcpy(s->cfg, d, LMS2XX_CONFIG_BYTES);
          buf[0] = 1;
        }
        memcpy(buf + 1, s->cfg, LMS2XX_CONFIG_BYTES);
        push_reply(s, end + LMS2XX_CONFIG_WRITE_NS, LMS2XX_CMD_WRITE_CONFIG | 0x80u, buf, LMS2XX_CONFIG_BYTES + 1);
        return;
      }
      break;
    default: break;
  }
  push_reply(s, due, LMS2XX_REPLY_NOT_RECOGNISED, NULL, 0);
}

/* Appends one byte to the telegram being received. Returns 1 when the buffered bytes cannot be
 * a request (bad header or CRC): the caller then looks for the next STX after the first. */
static int receive_step(struct lms2xx *s, uint8_t c, int64_t t) {
  if (s->rx_len == 0) {
    if (c == LMS2XX_STX) s->rx[s->rx_len++] = c;
    return 0; /* garbage between telegrams is ignored */
  }
  s->rx[s->rx_len++] = c;
  if (s->rx_len == 2) return c != LMS2XX_HOST_ADDRESS;
  if (s->rx_len < 4) return 0;
  const size_t len = (size_t)s->rx[2] | ((size_t)s->rx[3] << 8);
  if (len == 0 || len > LMS2XX_MAX_REQUEST_DATA) return 1;
  if (s->rx_len < 4 + len + 2) return 0;
  const uint16_t crc = (uint16_t)(s->rx[4 + len] | (s->rx[5 + len] << 8));
  if (crc != lms2xx_crc(s->rx, 4 + len)) {
    if (s->job_count < LMS2XX_MAX_JOBS) push_byte(s, t + LMS2XX_ACK_DELAY_NS, LMS2XX_NAK);
    return 1;
  }
  s->rx_len = 0;
  handle_request(s, s->rx + 4, len, t);
  return 0;
}

static void receive_byte(struct lms2xx *s, uint8_t c, int64_t t, int framing_error) {
  uint8_t todo[sizeof s->rx + 1];
  size_t n = 0, k = 0;
  if (framing_error) {
    if (s->rx_len == 0) return;
  } else {
    todo[n++] = c;
  }
  int reject = framing_error;
  for (;;) {
    if (reject) {
      /* Re-read everything after the rejected STX, ahead of what is still to come. */
      uint8_t rest[sizeof todo];
      size_t m = 0;
      for (size_t i = 1; i < s->rx_len; ++i) rest[m++] = s->rx[i];
      for (size_t i = k; i < n; ++i) rest[m++] = todo[i];
      memcpy(todo, rest, m);
      n = m;
      k = 0;
      s->rx_len = 0;
    }
    if (k >= n) break;
    reject = receive_step(s, todo[k++], t);
  }
}

void lms2xx_receive(struct lms2xx *s, const struct serial_byte *b) {
  note_time(s, b->end_ns);
  apply_pending_baud(s, b->end_ns);
  if (b->end_ns < s->booting_until_ns) {
    s->rx_len = 0; /* booting: the receiver is not yet listening */
    return;
  }
  receive_byte(s, b->value, b->end_ns, b->baud != s->baud);
}

/* ---- transmitter ---- */

static void finish_telegram(struct lms2xx *s, int64_t end) {
  if (s->tx_after == AFTER_BAUD) {
    apply_pending_baud(s, end);
  } else if (s->tx_after == AFTER_RESET) {
    /* Rebooting: queued replies are lost, the rate returns to the power-up rate and the
     * operating mode to its default; the configuration lives in EEPROM and stays. */
    s->job_count = 0;
    s->rx_len = 0;
    s->mode = LMS2XX_MODE_REQUEST;
    s->pending_baud = 0;
    s->baud = LMS2XX_POWER_UP_BAUD;
    s->baud_since_ns = end;
    s->booting_until_ns = end + s->config.power_up_ns;
    push_power_on(s, s->booting_until_ns);
  }
  s->tx_after = AFTER_NONE;
}

static void pop_job(struct lms2xx *s) {
  for (size_t i = 1; i < s->job_count; ++i) s->jobs[i - 1] = s->jobs[i];
  s->job_count--;
}

static int64_t max64(int64_t a, int64_t b) { return a > b ? a : b; }

size_t lms2xx_transmit(struct lms2xx *s, int64_t now_ns, int64_t until_ns, struct serial_byte *out, size_t cap) {
  size_t n = 0;
  note_time(s, now_ns);
  for (;;) {
    if (s->tx_pos < s->tx_len) {
      const int64_t end = s->tx_next_ns + serial_frame_ns(s->tx_baud);
      if (end >= until_ns || n >= cap) break;
      out[n].end_ns = end;
      out[n].baud = s->tx_baud;
      out[n].value = s->tx[s->tx_pos++];
      memset(out[n].reserved, 0, sizeof out[n].reserved);
      ++n;
      s->tx_next_ns = end;
      if (s->tx_pos == s->tx_len) finish_telegram(s, end);
      continue;
    }
    /* The line is idle: the first reply in the queue, or the newest complete scan. */
    const int64_t free_at = max64(s->tx_next_ns, now_ns);
    int64_t job_start = INT64_MAX, scan_start = INT64_MAX, scan_last = -1;
    if (s->job_count) job_start = max64(s->jobs[0].due_ns, free_at);
    /* A polled scan is one not sent before: if the newest complete one went out already, the
     * answer waits for the next to complete (at 100 deg / 0.25 deg: 4 sweeps, 18.75 a second). */
    if (s->job_count && s->jobs[0].kind == JOB_SCAN && newest_polled_scan(s, job_start) <= s->last_sent_sweep)
      job_start = max64(job_start, sweep_start(s, next_scan_end(s, s->last_sent_sweep) + 1));
    /* While a request is being answered no new scan goes out between its ACK and its reply. */
    if (streaming(s) && s->job_count == 0) {
      const int64_t from = max64(free_at, s->booting_until_ns);
      const int64_t newest = newest_scan_end(s, from);
      if (newest > s->last_sent_sweep) {
        scan_start = from;
        scan_last = newest;
      } else {
        scan_last = next_scan_end(s, s->last_sent_sweep);
        scan_start = max64(from, sweep_start(s, scan_last + 1));
      }
    }
    const int64_t start = job_start <= scan_start ? job_start : scan_start;
    if (start == INT64_MAX || start >= until_ns) break;
    apply_pending_baud(s, start);
    s->tx_baud = s->baud;
    s->tx_next_ns = start;
    s->tx_pos = 0;
    s->tx_after = AFTER_NONE;
    if (job_start <= scan_start) {
      const struct lms2xx_job *j = &s->jobs[0];
      if (j->kind == JOB_SCAN) {
        int64_t last = newest_polled_scan(s, start);
        if (last < 0) last = next_scan_end(s, -1); /* no scan yet: this one is early, a corner case */
        s->tx_len = build_scan(s, s->tx, last, s->mode == LMS2XX_MODE_STREAM_PARTIAL);
        if (last > s->last_sent_sweep) s->last_sent_sweep = last;
      } else {
        memcpy(s->tx, j->bytes, j->len);
        s->tx_len = j->len;
      }
      s->tx_after = j->after;
      if (j->after == AFTER_BAUD) {
        /* The reply goes at the old rate; the new one holds from its last stop bit on. */
        s->pending_baud = j->after_arg;
        s->pending_baud_ns = start + (int64_t)s->tx_len * serial_frame_ns(s->tx_baud);
      }
      pop_job(s);
    } else {
      s->tx_len = build_scan(s, s->tx, scan_last, s->mode == LMS2XX_MODE_STREAM_PARTIAL);
      s->last_sent_sweep = scan_last;
    }
  }
  note_time(s, until_ns);
  return n;
}

void lms2xx_init(struct lms2xx *s, const struct lms2xx_config *c, struct lms2xx_scan_source source, int64_t power_on_ns) {
  memset(s, 0, sizeof *s);
  s->config = *c;
  s->config.type[LMS2XX_TYPE_CHARS] = '\0';
  if (!valid_variant(s->config.scan_angle_deg, s->config.resolution_cdeg)) {
    s->config.scan_angle_deg = 180;
    s->config.resolution_cdeg = 50;
  }
  s->source = source;
  s->power_on_ns = power_on_ns;
  s->latest_ns = power_on_ns;
  s->booting_until_ns = power_on_ns + s->config.power_up_ns;
  s->baud = LMS2XX_POWER_UP_BAUD;
  s->baud_since_ns = power_on_ns;
  s->mode = LMS2XX_MODE_REQUEST;
  s->scan_angle_deg = s->config.scan_angle_deg;
  s->resolution_cdeg = s->config.resolution_cdeg;
  s->cfg[CFG_MEASURING_MODE] = s->config.measuring_mode;
  s->cfg[CFG_UNITS] = s->config.units;
  if (!valid_config(s->cfg)) {
    s->cfg[CFG_MEASURING_MODE] = LMS2XX_MEAS_8_80M_FA_FB_DAZZLE;
    s->cfg[CFG_UNITS] = LMS2XX_UNITS_CM;
  }
  s->tx_next_ns = power_on_ns;
  s->last_sent_sweep = -1;
  push_power_on(s, s->booting_until_ns);
}
