/* Computes for tens of milliseconds of host time between HAL calls while a 1 kHz timer handler is
 * attached: loops whose state lives only in floating-point registers, only in memory, or only in
 * general registers must never be taken for a loop waiting for an interrupt, so the times printed
 * are the HAL's own. */
#include <hal/hal.h>
#include <stdio.h>

#define ROUNDS 3

static volatile uint32_t ticks;
static void tick(void) { ticks++; }

/* Every general register stays the same from one pass to the next; only xmm0 moves. */
static double grow(double limit) {
  double x = 1.0;
  while (x < limit) x = x * 1.0000001 + 1e-12;
  return x;
}

/* The count lives in memory only: at the loop's test every general register and flag is the same
 * on each pass (the last load is `done`, 0 until the end). */
static volatile uint32_t count;
static volatile uint32_t done;
static uint32_t count_to(uint32_t target) {
  count = 0;
  done = 0;
  do {
    count = count + 1;
    done = count >= target;
  } while (!done);
  return count;
}

/* Only general registers move: no memory is written and no floating point is used on any pass
 * (xorshift64, whose state and counter the compiler keeps in two registers). */
static uint32_t mix(uint32_t passes) {
  uint64_t x = 88172645463325252ull;
  for (uint32_t i = 0; i < passes; ++i) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
  }
  return (uint32_t)(x >> 32);
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  irq_timer_start(1000, tick);
  uint32_t t[ROUNDS][4], seen[ROUNDS], counted[ROUNDS], mixed[ROUNDS];
  double grown[ROUNDS];
  for (int r = 0; r < ROUNDS; ++r) {
    t[r][0] = micros();
    grown[r] = grow(3.0 + r);
    t[r][1] = micros();
    counted[r] = count_to(40000000u + 1000u * (uint32_t)r);
    t[r][2] = micros();
    mixed[r] = mix(20000000u + 1000u * (uint32_t)r);
    t[r][3] = micros();
    seen[r] = ticks;
    delay_ms(2);
  }
  for (int r = 0; r < ROUNDS; ++r) {
    char line[200];
    snprintf(line, sizeof line, "round %d: %lu %lu %lu %lu us, grown %.17g, counted %lu, mixed %lu, ticks %lu\n", r,
             (unsigned long)t[r][0], (unsigned long)t[r][1], (unsigned long)t[r][2], (unsigned long)t[r][3],
             grown[r], (unsigned long)counted[r], (unsigned long)mixed[r], (unsigned long)seen[r]);
    uart_print(0, line);
  }
  for (;;) delay_ms(100);
}
