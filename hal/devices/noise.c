/* Counter-based noise: splitmix64 indexed directly by counter, Box-Muller for the normal. */
#include "noise.h"

#include <math.h>

#define GOLDEN_GAMMA UINT64_C(0x9E3779B97F4A7C15)
/* Keeps noise_uniform's stream apart from noise_gaussian's for the same seed (any odd constant
 * that is not a small multiple of the golden gamma would do). */
#define UNIFORM_STREAM UINT64_C(0xD1B54A32D192ED03)
#define TWO_PI 6.283185307179586476925286766559

/* splitmix64's output function (Steele, Lea, Flood 2014): a bijection with full avalanche, so
 * consecutive counters give independent-looking words. */
static uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
  z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
  return z ^ (z >> 31);
}

uint64_t noise_hash64(uint64_t seed, uint64_t index) {
  /* splitmix64's state after n steps is start + n * gamma, so element `index` is reached
   * directly. The seed is mixed first: raw seeds s and s + gamma would otherwise share a stream
   * shifted by one. */
  const uint64_t start = mix64(seed);
  return mix64(start + (index + 1u) * GOLDEN_GAMMA);
}

/* Top 53 bits, because that is what a double holds exactly. */
static double to_unit(uint64_t word) { return (double)(word >> 11) * (1.0 / 9007199254740992.0); }

double noise_uniform(uint64_t seed, uint64_t index) { return to_unit(noise_hash64(seed ^ UNIFORM_STREAM, index)); }

/* Box-Muller's radius and angle of draw `index`: two stream elements per draw (2k and 2k+1), so
 * no draw shares a uniform with another. u1 in (0, 1] keeps log() finite. */
static void polar(uint64_t seed, uint64_t index, double *radius, double *angle) {
  const double u1 = 1.0 - to_unit(noise_hash64(seed, 2u * index));
  const double u2 = to_unit(noise_hash64(seed, 2u * index + 1u));
  *radius = sqrt(-2.0 * log(u1));
  *angle = TWO_PI * u2;
}

double noise_gaussian(uint64_t seed, uint64_t index) {
  /* Only the cosine branch, so every draw costs the same two words whatever was asked before. */
  double radius, angle;
  polar(seed, index, &radius, &angle);
  return radius * cos(angle);
}

void noise_gaussian_pair(uint64_t seed, uint64_t index, double out[2]) {
  double radius, angle;
  polar(seed, index, &radius, &angle);
  out[0] = radius * cos(angle);
  out[1] = radius * sin(angle);
}
