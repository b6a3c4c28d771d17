/* Counter-based noise for device models: the k-th draw is a pure function of (seed, k), so a
 * sample's noise never depends on how many other samples were drawn before it, or in what order. */
#ifndef SEAR_DEVICES_NOISE_H
#define SEAR_DEVICES_NOISE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Uniform 64-bit hash of (seed, index): element `index` of the splitmix64 stream started from a
 * scrambled `seed`. Distinct seeds give unrelated streams, not shifted copies of one stream. */
uint64_t noise_hash64(uint64_t seed, uint64_t index);

/* Uniform in [0, 1) with 53 random bits. Drawn from a stream separate from noise_gaussian's,
 * so a model may use both with one seed without the two being correlated. */
double noise_uniform(uint64_t seed, uint64_t index);

/* Standard normal N(0, 1) by Box-Muller from two uniforms; the same (seed, index) gives the
 * same value in the same build. */
double noise_gaussian(uint64_t seed, uint64_t index);

/* Two independent standard normals from draw `index`'s two uniforms, both of Box-Muller's
 * branches, for half the cost of two draws: out[0] is noise_gaussian(seed, index), out[1] the
 * sine branch that noise_gaussian leaves unused. */
void noise_gaussian_pair(uint64_t seed, uint64_t index, double out[2]);

#ifdef __cplusplus
}
#endif
#endif
