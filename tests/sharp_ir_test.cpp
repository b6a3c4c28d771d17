// Sharp GP2D12 / GP2D15 device models against their datasheet (Sharp "GP2D12/GP2D15 General
// Purpose Type Distance Measuring Sensors"), and the counter-based noise they draw from.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "devices/noise.h"
#include "devices/sharp_gp2d12.h"
#include "devices/sharp_gp2d15.h"

namespace {

double volts_at_cm(double cm) { return gp2d12_output_v(cm / 100.0); }

// What a 10-bit ADC against a 5 V reference reads, as hal/include/hal/adc.h defines it.
int adc10_code(double volts) { return static_cast<int>(std::floor(volts * 1024.0 / 5.0)); }

// The white-paper curve of the figure "Analog output voltage vs. distance to reflective object",
// read off at the marked distances; +-0.08 V is about one fifth of a 0.5 V grid division, what
// reading a printed curve by eye is good for.
TEST(Gp2d12Curve, MatchesDatasheetFigureAcrossTheRange) {
  const struct {
    double cm, volts;
  } figure[] = {{10, 2.40}, {20, 1.39}, {30, 0.98}, {40, 0.76}, {50, 0.62}, {60, 0.53}, {80, 0.40}};
  for (const auto& p : figure) EXPECT_NEAR(volts_at_cm(p.cm), p.volts, 0.08) << p.cm << " cm";
}

// Electro-optical characteristics table: Vo(80 cm) = 0.25 / 0.4 / 0.55 V (min/typ/max) and
// dVo(80 cm -> 10 cm) = 1.75 / 2.0 / 2.25 V. A typical curve must sit at the typical values.
TEST(Gp2d12Curve, MeetsTheElectroOpticalTable) {
  const double v80 = volts_at_cm(80.0);
  const double v10 = volts_at_cm(10.0);
  EXPECT_GE(v80, GP2D12_V80_MIN_V);
  EXPECT_LE(v80, GP2D12_V80_MAX_V);
  EXPECT_NEAR(v80, GP2D12_V80_TYP_V, 0.02);
  EXPECT_GE(v10 - v80, GP2D12_DELTA_V_MIN_V);
  EXPECT_LE(v10 - v80, GP2D12_DELTA_V_MAX_V);
  EXPECT_NEAR(v10 - v80, GP2D12_DELTA_V_TYP_V, 0.05);
}

// Between the table's points the curve should still follow the figure. An independent reading
// of it, the common 10-bit fit d = 6787 / (code - 3) - 4, i.e. V = 33.14 / (d + 4) + 0.015,
// checked every millimetre from 10 to 80 cm.
TEST(Gp2d12Curve, FollowsTheInverseDistanceLawBetweenTablePoints) {
  for (int mm = 100; mm <= 800; ++mm) {
    const double cm = mm / 10.0;
    const double fit = 6787.0 * 5.0 / 1024.0 / (cm + 4.0) + 3.0 * 5.0 / 1024.0;
    ASSERT_NEAR(volts_at_cm(cm), fit, 0.05) << cm << " cm";
  }
}

// Figure: one maximum (near 8 cm), then the output falls all the way out to 80 cm and beyond.
TEST(Gp2d12Curve, FallsMonotonicallyFromThePeak) {
  int peak_mm = 0;
  for (int mm = 0; mm <= 200; ++mm)
    if (volts_at_cm(mm / 10.0) > volts_at_cm(peak_mm / 10.0)) peak_mm = mm;
  EXPECT_GE(peak_mm, 60);
  EXPECT_LE(peak_mm, 90);
  EXPECT_GT(volts_at_cm(peak_mm / 10.0), volts_at_cm(10.0));
  EXPECT_LT(volts_at_cm(peak_mm / 10.0), 2.8);  // the figure's curve stays under 2.8 V
  for (int mm = peak_mm; mm < 800; ++mm)
    ASSERT_GT(volts_at_cm(mm / 10.0), volts_at_cm((mm + 1) / 10.0)) << mm << " mm";
  for (int mm = 800; mm < 1500; ++mm)
    ASSERT_GE(volts_at_cm(mm / 10.0), volts_at_cm((mm + 1) / 10.0)) << mm << " mm";
}

// Figure: closer than the peak the output falls again, so a target at 3 cm reads like one well
// inside the range (the ambiguity every GP2D12 firmware has to live with).
TEST(Gp2d12Curve, FallsAgainBelowThePeak) {
  EXPECT_LT(volts_at_cm(3.0), volts_at_cm(7.0));
  EXPECT_LT(volts_at_cm(1.0), volts_at_cm(3.0));
  EXPECT_DOUBLE_EQ(volts_at_cm(0.0), 0.0);
  const double v3 = volts_at_cm(3.0);
  EXPECT_LT(v3, volts_at_cm(10.0));
  EXPECT_GT(v3, volts_at_cm(30.0));
}

TEST(Gp2d12Curve, NothingInRangeGivesTheNoObjectOutput) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(gp2d12_output_v(inf), GP2D12_NO_OBJECT_V);
  EXPECT_DOUBLE_EQ(gp2d12_output_v(-1.0), GP2D12_NO_OBJECT_V);
  EXPECT_DOUBLE_EQ(gp2d12_output_v(nan), GP2D12_NO_OBJECT_V);
  EXPECT_DOUBLE_EQ(gp2d12_output_v(5.0), GP2D12_NO_OBJECT_V);
  // Continuous into it, and never below it: "far" and "nothing" look alike, as on the bench.
  EXPECT_NEAR(gp2d12_output_v(GP2D12_CURVE_END_M - 1e-9), GP2D12_NO_OBJECT_V, 1e-6);
  for (int cm = 10; cm <= 150; ++cm) EXPECT_GE(volts_at_cm(cm), GP2D12_NO_OBJECT_V) << cm << " cm";
  // The no-object level is one a real unit can show at the end of its range (Vo min at 80 cm).
  EXPECT_GE(GP2D12_NO_OBJECT_V, GP2D12_V80_MIN_V);
}

// A 10-bit, 5 V ADC (code = floor(V * 1024 / 5)) reading the figure's typical values:
// 2.4 V -> 491, 1.39 V -> 284, 0.76 V -> 155, 0.4 V -> 81; the tolerances are the +-0.08-0.1 V
// of reading the figure. At 80 cm the code must also lie inside the table's 0.25-0.55 V.
TEST(Gp2d12Curve, TenBitAdcCodesAtTheFigureDistances) {
  EXPECT_NEAR(adc10_code(volts_at_cm(10.0)), 491, 20);
  EXPECT_NEAR(adc10_code(volts_at_cm(20.0)), 284, 16);
  EXPECT_NEAR(adc10_code(volts_at_cm(40.0)), 155, 16);
  EXPECT_NEAR(adc10_code(volts_at_cm(80.0)), 81, 16);
  EXPECT_GE(adc10_code(volts_at_cm(80.0)), adc10_code(GP2D12_V80_MIN_V));
  EXPECT_LE(adc10_code(volts_at_cm(80.0)), adc10_code(GP2D12_V80_MAX_V));
}

TEST(Gp2d12Sample, NoiseDependsOnlyOnSeedAndIndex) {
  const double d = 0.30;
  const double sd = 0.02;
  std::vector<double> forward;
  for (uint64_t k = 0; k < 50; ++k) forward.push_back(gp2d12_sample_v(d, 42, k, sd));
  for (uint64_t k = 50; k-- > 0;) ASSERT_DOUBLE_EQ(gp2d12_sample_v(d, 42, k, sd), forward[k]);
  EXPECT_NE(forward[0], forward[1]);
  EXPECT_NE(gp2d12_sample_v(d, 43, 0, sd), forward[0]);
  EXPECT_NEAR(forward[7] - gp2d12_output_v(d), sd * noise_gaussian(42, 7), 1e-12);
}

TEST(Gp2d12Sample, NoNoiseIsTheCurveAndTheRailsHold) {
  EXPECT_DOUBLE_EQ(gp2d12_sample_v(0.25, 1, 9, 0.0), gp2d12_output_v(0.25));
  for (uint64_t k = 0; k < 2000; ++k) {
    const double v_near_contact = gp2d12_sample_v(0.0, 7, k, 1.0);
    const double v_peak = gp2d12_sample_v(0.08, 7, k, 3.0);
    ASSERT_GE(v_near_contact, 0.0);
    ASSERT_LE(v_peak, GP2D12_VCC_V);
  }
}

// Timing chart: a result every 38.3 ms, shown at most 5 ms after its measurement ends; the
// output is unstable before the first one.
TEST(Gp2d12Timing, OutputIndexFollowsTheMeasuringCycle) {
  EXPECT_EQ(GP2D12_PERIOD_NS, 38300000);
  EXPECT_EQ(gp2d12_output_index(0), -1);
  EXPECT_EQ(gp2d12_output_index(43299999), -1);
  EXPECT_EQ(gp2d12_output_index(43300000), 0);
  EXPECT_EQ(gp2d12_output_index(43300000 + 38299999), 0);
  EXPECT_EQ(gp2d12_output_index(43300000 + 38300000), 1);
  EXPECT_EQ(gp2d12_output_index(1000000000), (1000000000 - 43300000) / 38300000);
}

TEST(Noise, GaussianHasZeroMeanAndUnitDeviation) {
  for (uint64_t seed : {uint64_t{0}, uint64_t{1}, uint64_t{0xC0FFEE}}) {
    const int n = 100000;
    double sum = 0.0, sum_sq = 0.0;
    for (int k = 0; k < n; ++k) {
      const double z = noise_gaussian(seed, static_cast<uint64_t>(k));
      sum += z;
      sum_sq += z * z;
    }
    const double mean = sum / n;
    const double sd = std::sqrt(sum_sq / n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 0.01) << "seed " << seed;
    EXPECT_NEAR(sd, 1.0, 0.01) << "seed " << seed;
  }
}

TEST(Noise, GaussianTailsAreNormal) {
  // P(|z| > 2) = 4.55 % and P(|z| > 3) = 0.27 % for N(0, 1).
  const int n = 100000;
  int beyond2 = 0, beyond3 = 0;
  for (int k = 0; k < n; ++k) {
    const double z = std::fabs(noise_gaussian(5, static_cast<uint64_t>(k)));
    beyond2 += z > 2.0;
    beyond3 += z > 3.0;
  }
  EXPECT_NEAR(beyond2 / double(n), 0.0455, 0.003);
  EXPECT_NEAR(beyond3 / double(n), 0.0027, 0.0007);
}

TEST(Noise, APairIsTheDrawAndAnIndependentNormalBeside) {
  const int n = 100000;
  double sum = 0.0, sum_sq = 0.0, cross = 0.0;
  int beyond2 = 0;
  for (int k = 0; k < n; ++k) {
    double z[2];
    noise_gaussian_pair(7, static_cast<uint64_t>(k), z);
    ASSERT_EQ(z[0], noise_gaussian(7, static_cast<uint64_t>(k))) << k;
    sum += z[1];
    sum_sq += z[1] * z[1];
    cross += z[0] * z[1];
    beyond2 += std::fabs(z[1]) > 2.0;
  }
  // The sine branch is N(0, 1) too: the mean's sd is 1/sqrt(n) = 0.0032, the sample sd's
  // 1/sqrt(2n) = 0.0022, so 0.01 is over 3 of either; P(|z| > 2) = 4.55 % with sd 0.07 %.
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum_sq / n - mean * mean), 1.0, 0.01);
  EXPECT_NEAR(beyond2 / double(n), 0.0455, 0.003);
  // And uncorrelated with the cosine branch: the sum / n of independent products has sd 0.0032.
  EXPECT_NEAR(cross / n, 0.0, 0.015);
}

TEST(Noise, DrawsAreReproducibleAndUncorrelated) {
  EXPECT_EQ(noise_gaussian(9, 1234), noise_gaussian(9, 1234));
  EXPECT_NE(noise_gaussian(9, 1234), noise_gaussian(9, 1235));
  EXPECT_NE(noise_gaussian(9, 1234), noise_gaussian(10, 1234));
  const int n = 100000;
  double lag1 = 0.0, seeds = 0.0, with_uniform = 0.0;
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<uint64_t>(k);
    lag1 += noise_gaussian(3, i) * noise_gaussian(3, i + 1);
    seeds += noise_gaussian(3, i) * noise_gaussian(4, i);
    with_uniform += noise_gaussian(3, i) * (noise_uniform(3, i) - 0.5) * std::sqrt(12.0);
  }
  // For independent unit-variance draws each sum / n has sd 1/sqrt(n) = 0.0032.
  EXPECT_NEAR(lag1 / n, 0.0, 0.015);
  EXPECT_NEAR(seeds / n, 0.0, 0.015);
  EXPECT_NEAR(with_uniform / n, 0.0, 0.015);
}

TEST(Noise, UniformCoversTheUnitInterval) {
  const int n = 100000;
  int bins[10] = {};
  for (int k = 0; k < n; ++k) {
    const double u = noise_uniform(11, static_cast<uint64_t>(k));
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ++bins[static_cast<int>(u * 10.0)];
  }
  for (int b : bins) EXPECT_NEAR(b, n / 10, 400);  // 4.2 sd of a binomial(1e5, 0.1) count
}

// Datasheet note *4: the judgement distance is where the output goes from L to H, so H means
// "object within 24 cm"; switching back needs the target to recede past the hysteresis width.
TEST(Gp2d15, SwitchesOnAtTheThresholdWhenApproaching) {
  gp2d15 s;
  gp2d15_init_typical(&s);
  EXPECT_EQ(GP2D15_LEVEL_DETECTED, 1);
  EXPECT_EQ(gp2d15_level(&s), GP2D15_LEVEL_CLEAR);
  double switched_at = -1.0;
  for (int mm = 400; mm >= 0; --mm) {
    if (gp2d15_update(&s, mm / 1000.0) == GP2D15_LEVEL_DETECTED) {
      switched_at = mm / 1000.0;
      break;
    }
  }
  EXPECT_NEAR(switched_at, 0.239, 1e-9);  // the first millimetre step inside 24 cm
}

TEST(Gp2d15, StaysOnUntilThresholdPlusHysteresisWhenReceding) {
  gp2d15 s;
  ASSERT_EQ(gp2d15_init(&s, 0.24, 0.01), 0);
  ASSERT_EQ(gp2d15_update(&s, 0.10), GP2D15_LEVEL_DETECTED);
  for (int mm = 100; mm <= 249; ++mm) ASSERT_EQ(gp2d15_update(&s, mm / 1000.0), GP2D15_LEVEL_DETECTED) << mm;
  EXPECT_EQ(gp2d15_update(&s, 0.2499), GP2D15_LEVEL_DETECTED);
  EXPECT_EQ(gp2d15_update(&s, 0.2501), GP2D15_LEVEL_CLEAR);
  // A target jittering a few mm either side of 24 cm does not make the output chatter.
  ASSERT_EQ(gp2d15_update(&s, 0.235), GP2D15_LEVEL_DETECTED);
  for (int k = 0; k < 100; ++k)
    ASSERT_EQ(gp2d15_update(&s, 0.24 + ((k % 2) ? 0.004 : -0.004)), GP2D15_LEVEL_DETECTED);
}

TEST(Gp2d15, NothingHitMeansNothingDetected) {
  gp2d15 s;
  gp2d15_init_typical(&s);
  ASSERT_EQ(gp2d15_update(&s, 0.05), GP2D15_LEVEL_DETECTED);
  EXPECT_EQ(gp2d15_update(&s, std::numeric_limits<double>::infinity()), GP2D15_LEVEL_CLEAR);
  ASSERT_EQ(gp2d15_update(&s, 0.05), GP2D15_LEVEL_DETECTED);
  EXPECT_EQ(gp2d15_update(&s, -1.0), GP2D15_LEVEL_CLEAR);
  ASSERT_EQ(gp2d15_update(&s, 0.05), GP2D15_LEVEL_DETECTED);
  EXPECT_EQ(gp2d15_update(&s, std::numeric_limits<double>::quiet_NaN()), GP2D15_LEVEL_CLEAR);
}

// Table note *2: units ship adjusted to 24 cm +- 3 cm, so a model switching outside 21-27 cm is
// not a GP2D15.
TEST(Gp2d15, SwitchingDistanceMustLieInTheDatasheetSpread) {
  gp2d15 s;
  gp2d15_init_typical(&s);
  const gp2d15 before = s;
  EXPECT_EQ(gp2d15_init(&s, 0.20, 0.01), -1);
  EXPECT_EQ(gp2d15_init(&s, 0.28, 0.01), -1);
  EXPECT_EQ(gp2d15_init(&s, std::numeric_limits<double>::quiet_NaN(), 0.01), -1);
  EXPECT_EQ(gp2d15_init(&s, 0.24, -0.001), -1);
  EXPECT_EQ(gp2d15_init(&s, 0.24, std::numeric_limits<double>::infinity()), -1);
  EXPECT_EQ(s.switch_distance_m, before.switch_distance_m);
  EXPECT_EQ(s.hysteresis_m, before.hysteresis_m);
  EXPECT_EQ(gp2d15_init(&s, GP2D15_SWITCH_DISTANCE_MIN_M, 0.0), 0);
  EXPECT_EQ(gp2d15_init(&s, GP2D15_SWITCH_DISTANCE_MAX_M, 0.02), 0);
  EXPECT_EQ(gp2d15_update(&s, 0.26), GP2D15_LEVEL_DETECTED);
  EXPECT_EQ(gp2d15_update(&s, 0.285), GP2D15_LEVEL_DETECTED);
  EXPECT_EQ(gp2d15_update(&s, 0.291), GP2D15_LEVEL_CLEAR);
}

}  // namespace
