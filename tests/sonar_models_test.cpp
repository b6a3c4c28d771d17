// HC-SR04, LV-MaxSonar-EZ1 and quadrature encoder device models against their datasheets:
// ElecFreaks "Ultrasonic Ranging Module HC-SR04", MaxBotix "LV-MaxSonar-EZ1 Data Sheet", and
// the quadrature (Gray code) sequence of incremental encoders.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "devices/hcsr04.h"
#include "devices/maxbotix_lv_ez.h"
#include "devices/noise.h"
#include "devices/quadrature_encoder.h"

namespace {

// ---------------------------------------------------------------- HC-SR04

// What a firmware with micros() (1 us ticks) measures on ECHO for one measurement triggered at
// t_ns: the pulse width in us, or -1 when ECHO never rose. Also returns the rise time.
struct EchoSeen {
  int64_t rise_ns = -1, fall_ns = -1;
  int64_t width_us() const { return fall_ns / 1000 - rise_ns / 1000; }
};

EchoSeen trigger_and_listen(hcsr04& s, int64_t t_ns, int64_t high_ns = 10000) {
  hcsr04_trigger(&s, 1, t_ns);
  hcsr04_trigger(&s, 0, t_ns + high_ns);
  EchoSeen seen;
  while (hcsr04_next_edge_ns(&s) != INT64_MAX) {
    const int64_t t = hcsr04_next_edge_ns(&s);
    (hcsr04_take_edge(&s) ? seen.rise_ns : seen.fall_ns) = t;
  }
  return seen;
}

// Datasheet: "uS / 58 = centimeters", 2 cm to 4 m, "ranging accuracy can reach to 3mm". A
// firmware timing ECHO with micros() and dividing by 58 gets every distance within 3 mm (the
// model's noise is clipped there) + 1 us of micros() quantisation (1/58 cm = 0.17 mm). ECHO rises
// the measured 468 us after TRIG falls, whatever the range.
TEST(Hcsr04, FirmwareTimingEchoWithMicrosGetsTheDistanceWithinThreeMillimetres) {
  hcsr04 s;
  hcsr04_init(&s, 42);
  const double tolerance_m = 0.003 + 0.01 / 58.0;
  int64_t t = 1000000;
  for (double d = 0.02; d <= 4.0 + 1e-9; d += 0.0137) {
    hcsr04_set_distance(&s, d, t - 500000);
    const EchoSeen e = trigger_and_listen(s, t);
    ASSERT_EQ(e.rise_ns, t + 10000 + 468000) << d;
    const double measured_m = static_cast<double>(e.width_us()) / 58.0 / 100.0;
    ASSERT_NEAR(measured_m, d, tolerance_m) << d;
    t += 60000000;  // the datasheet's suggested cycle
  }
}

// The noise is per measurement, deterministic in (seed, measurement number), Gaussian with the
// documented 1 mm standard deviation: over 2000 measurements of 1 m the spread is 1 mm within
// 10 % (the sample sd's own relative error is 1/sqrt(2N) = 1.6 %, clipping at 3 sd takes 1.4 %
// off), and the mean within 3 sd / sqrt(N) = 0.07 mm.
TEST(Hcsr04, NoiseIsSmallDeterministicAndPerMeasurement) {
  hcsr04 a, b;
  hcsr04_init(&a, 7);
  hcsr04_init(&b, 7);
  const int n = 2000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const int64_t t = 1000000 + k * INT64_C(60000000);
    hcsr04_set_distance(&a, 1.0, t);
    hcsr04_set_distance(&b, 1.0, t);
    const EchoSeen ea = trigger_and_listen(a, t);
    const EchoSeen eb = trigger_and_listen(b, t);
    ASSERT_EQ(ea.fall_ns, eb.fall_ns);
    const int64_t width = ea.fall_ns - ea.rise_ns;
    ASSERT_EQ(width, hcsr04_echo_width_ns(1.0, 7, static_cast<uint64_t>(k)));
    const double err_m = static_cast<double>(width) / 58000.0 / 100.0 - 1.0;
    sum += err_m;
    sum2 += err_m * err_m;
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 3.0 * HCSR04_NOISE_SD_M / std::sqrt(n));
  EXPECT_NEAR(sd, HCSR04_NOISE_SD_M, 0.1 * HCSR04_NOISE_SD_M);
  // Another seed gives other noise.
  EXPECT_NE(hcsr04_echo_width_ns(1.0, 7, 0), hcsr04_echo_width_ns(1.0, 8, 0));
}

// Outside 2 cm - 4 m (and with nothing there) no echo is heard: ECHO stays high for the ~38 ms
// time-out. Triggers shorter than 10 us, or sooner than 60 ms after the last measurement, are
// ignored; the distance used is the one in force when the burst leaves.
TEST(Hcsr04, OutOfRangeTimesOutAndBadTriggersAreIgnored) {
  hcsr04 s;
  hcsr04_init(&s, 1);
  int64_t t = 1000000;
  for (double d : {double{INFINITY}, 4.01, 6.0, 0.019, 0.0, -1.0, double{NAN}}) {
    hcsr04_set_distance(&s, d, t);
    const EchoSeen e = trigger_and_listen(s, t);
    EXPECT_EQ(e.fall_ns - e.rise_ns, HCSR04_NO_ECHO_NS) << d;
    t += 60000000;
  }
  hcsr04_set_distance(&s, 1.0, t);
  EXPECT_EQ(trigger_and_listen(s, t, 9999).rise_ns, -1);        // 9.999 us: too short
  const EchoSeen ok = trigger_and_listen(s, t + 1000000);        // 10 us: accepted
  EXPECT_GT(ok.rise_ns, 0);
  const int64_t accepted_fall = t + 1000000 + 10000;
  EXPECT_EQ(trigger_and_listen(s, accepted_fall + 59000000 - 10000).rise_ns, -1);  // 59 ms later
  EXPECT_GT(trigger_and_listen(s, accepted_fall + 60000000 - 10000).rise_ns, 0);   // 60 ms later

  // A distance stamped before the burst counts even when given after the trigger (the truth
  // grid and the firmware's trigger are independent); one stamped after the burst does not.
  for (const int64_t stamp : {INT64_C(1100000), INT64_C(1278000), INT64_C(1278001), INT64_C(2000000)}) {
    hcsr04 m;
    hcsr04_init(&m, 3);
    hcsr04_set_distance(&m, 1.0, 0);
    hcsr04_trigger(&m, 1, 1000000);
    hcsr04_trigger(&m, 0, 1010000);        // the burst leaves at 1.010 + 0.468 - 0.200 ms
    hcsr04_set_distance(&m, 2.0, stamp);
    ASSERT_EQ(hcsr04_next_edge_ns(&m), 1010000 + 468000);
    ASSERT_EQ(hcsr04_take_edge(&m), 1);
    const double used = stamp <= 1278000 ? 2.0 : 1.0;
    EXPECT_EQ(hcsr04_next_edge_ns(&m) - 1478000, hcsr04_echo_width_ns(used, 3, 0)) << stamp;
    EXPECT_EQ(hcsr04_take_edge(&m), 0);
    EXPECT_EQ(hcsr04_next_edge_ns(&m), INT64_MAX);
  }
}

// 58 us per cm is the round trip at the stated speed of sound: 2 cm / 58 us = 344.8 m/s, which
// 331.3 m/s * sqrt(1 + T / 273.15 K) gives at 22.8 C (room temperature).
TEST(Hcsr04, FiftyEightMicrosecondsPerCentimetreIsTheRoundTripAtTheStatedSoundSpeed) {
  EXPECT_NEAR(2.0 * 0.01 / HCSR04_SOUND_SPEED_MPS, 58e-6, 1e-12);
  const double t_c = (std::pow(HCSR04_SOUND_SPEED_MPS / 331.3, 2.0) - 1.0) * 273.15;
  EXPECT_NEAR(t_c, 22.8, 0.1);
  // The echo delay holds the 8-cycle 40 kHz burst (200 us).
  EXPECT_EQ(HCSR04_BURST_NS, 8 * 1000000000LL / 40000);
  EXPECT_GT(HCSR04_ECHO_DELAY_NS, HCSR04_BURST_NS);
}

// ---------------------------------------------------------------- LV-MaxSonar-EZ1

// The firmware's side as hal/runtime would drive it: at each cycle start, the reading for that
// cycle from the common function, then the PW edges; AN read when asked.
struct PinsRun {
  maxbotix_lv_ez s;
  uint64_t seed;
  double noise_sd_m;
  std::vector<int64_t> rises, falls;
  std::vector<int64_t> cycle_starts;
  std::vector<int> readings;
};

// Runs the firmware-side model to t_end_ns with distance_of(t) as the truth.
template <typename Distance>
void run_pins(PinsRun& r, int64_t t_end_ns, Distance distance_of) {
  for (;;) {
    uint64_t k = 0;
    const int64_t cycle = maxbotix_lv_ez_next_cycle_ns(&r.s, &k);
    const int64_t edge = maxbotix_lv_ez_next_edge_ns(&r.s);
    if (edge < cycle && edge < t_end_ns) {
      (maxbotix_lv_ez_take_edge(&r.s) ? r.rises : r.falls).push_back(edge);
      continue;
    }
    if (cycle >= t_end_ns) break;
    const int inches = maxbotix_reading_inches(distance_of(cycle), r.seed, k, r.noise_sd_m);
    maxbotix_lv_ez_take_reading(&r.s, inches, cycle);
    r.cycle_starts.push_back(cycle);
    r.readings.push_back(inches);
  }
}

std::string text_of(const std::vector<serial_byte>& bytes, size_t from, size_t n) {
  std::string s;
  for (size_t i = from; i < from + n && i < bytes.size(); ++i) s.push_back(static_cast<char>(bytes[i].value));
  return s;
}

// Pin Out and Timing Description: a target at 1.000 m is 39.37 in, read as 39 (1-inch
// resolution). AN = 39 x Vcc/512 = 0.380859 V at 5 V; PW high 39 x 147 us = 5.733 ms, rising
// after the 13 waves at 42 kHz (309.5 us) of each 49 ms cycle; TX "R039\r" at 9600 8N1 in the
// cycle's last 4.7 ms. The first reading's cycle starts 250 ms + one 49 ms calibration cycle
// after power-up, so nothing is shown before 299 ms, and the outputs agree cycle by cycle.
TEST(MaxbotixLvEz1, ThreeOutputsAgreeWithTheDistanceAndTheDatasheetTiming) {
  EXPECT_EQ(maxbotix_reading_inches(1.000, 0, 0, 0.0), 39);
  PinsRun r{{}, 5, 0.0, {}, {}, {}, {}};
  maxbotix_lv_ez_init(&r.s);
  EXPECT_EQ(maxbotix_lv_ez_analog_v(&r.s, 200000000, 5.0), 0.0);
  run_pins(r, 1000000000, [](int64_t) { return 1.000; });

  maxbotix_lv_ez_serial tx;
  maxbotix_lv_ez_serial_init(&tx, 5, 0.0);
  maxbotix_lv_ez_serial_set_distance(&tx, 1.000, 0);
  std::vector<serial_byte> bytes(200);
  bytes.resize(maxbotix_lv_ez_serial_transmit(&tx, 0, 1000000000, bytes.data(), bytes.size()));

  // 299 ms + 49 ms * k up to 1 s: k = 0..14.
  ASSERT_EQ(r.cycle_starts.size(), 15u);
  ASSERT_EQ(r.rises.size(), 15u);
  ASSERT_EQ(r.falls.size(), 15u);
  ASSERT_EQ(bytes.size(), 70u);  // cycle 14's serial (at 985.3 ms on) ends after 1 s
  const double frame_ns = 1e10 / 9600.0;  // 10 bits of 8N1 at 9600 baud
  for (size_t k = 0; k < 14; ++k) {
    const int64_t start = 299000000 + static_cast<int64_t>(k) * 49000000;
    EXPECT_EQ(r.cycle_starts[k], start);
    EXPECT_EQ(r.cycle_starts[k], maxbotix_cycle_start_ns(k));
    EXPECT_EQ(r.rises[k], start + 309524);
    EXPECT_EQ(r.falls[k] - r.rises[k], 39 * 147000);
    EXPECT_EQ(text_of(bytes, 5 * k, 5), "R039\r");
    EXPECT_NEAR(static_cast<double>(bytes[5 * k].end_ns - start), 44.3e6 + frame_ns, 1.0);  // ns rounding
    for (size_t i = 0; i < 5; ++i) EXPECT_EQ(bytes[5 * k + i].baud, 9600u);
  }
  // AN of the last reading at 5 V and 3.3 V: 39 x Vcc / 512 (0.3809 V and 0.2514 V).
  EXPECT_DOUBLE_EQ(maxbotix_lv_ez_analog_v(&r.s, 999000000, 5.0), 39.0 * 5.0 / 512.0);
  EXPECT_DOUBLE_EQ(maxbotix_lv_ez_analog_v(&r.s, 999000000, 3.3), 39.0 * 3.3 / 512.0);
}

// The same (seed, k) gives the same reading in the firmware's process and in the simulator's, so
// a moving target reads alike on PW, AN and TX cycle by cycle, noise included.
TEST(MaxbotixLvEz1, FirmwareSideAndSerialSideReadTheSameNoisyCycles) {
  // A target that jumps 7.4 cm (~3 in) from one 1 ms quantum to the next, sweeping 0.3-2.8 m, so
  // a cycle measured with the wrong quantum's truth would read differently.
  auto distance_of = [](int64_t t) { return 0.3 + std::fmod(static_cast<double>(t / 1000000) * 0.0737, 2.5); };
  PinsRun r{{}, 99, MAXBOTIX_NOISE_SD_M, {}, {}, {}, {}};
  maxbotix_lv_ez_init(&r.s);
  int held = 0, ramping = 0, settled = 0;
  maxbotix_lv_ez_serial tx;
  maxbotix_lv_ez_serial_init(&tx, 99, MAXBOTIX_NOISE_SD_M);
  std::vector<serial_byte> bytes;
  // 1 ms quanta, as the lockstep runs them: the truth at each quantum's start to both sides,
  // given to the serial half before its transmit call in even quanta and after it in odd ones
  // (the cycle it covers is then re-measured with it).
  for (int64_t q = 0; q < 5000000000; q += 1000000) {
    const bool truth_first = (q / 1000000) % 2 == 0;
    if (truth_first) maxbotix_lv_ez_serial_set_distance(&tx, distance_of(q), q);
    serial_byte out[8];
    const size_t n = maxbotix_lv_ez_serial_transmit(&tx, q, q + 1000000, out, 8);
    if (!truth_first) maxbotix_lv_ez_serial_set_distance(&tx, distance_of(q), q);
    bytes.insert(bytes.end(), out, out + n);
    run_pins(r, q + 1000000, [&](int64_t) { return distance_of(q); });
    // AN through the cycle: the previous reading until listening ends (PW's latest fall,
    // 0.31 + 37.5 ms), the new one from the start of the serial data (49 - 4.7 ms), in between
    // on its way.
    if (r.readings.empty()) continue;
    const int64_t t = q + 999999;
    const int64_t since = t - r.cycle_starts.back();
    const double now_v = r.readings.back() * 5.0 / 512.0;
    const double before_v = r.readings.size() > 1 ? r.readings[r.readings.size() - 2] * 5.0 / 512.0 : 0.0;
    const double an = maxbotix_lv_ez_analog_v(&r.s, t, 5.0);
    if (since < 309524 + 37500000) {
      ASSERT_DOUBLE_EQ(an, before_v) << t;
      ++held;
    } else if (since >= 44300000) {
      ASSERT_DOUBLE_EQ(an, now_v) << t;
      ++settled;
    } else {
      ASSERT_GE(an, std::min(before_v, now_v) - 1e-12) << t;
      ASSERT_LE(an, std::max(before_v, now_v) + 1e-12) << t;
      ++ramping;
    }
  }
  EXPECT_GT(held, 0);
  EXPECT_GT(ramping, 0);
  EXPECT_GT(settled, 0);
  ASSERT_GE(r.readings.size(), 95u);
  ASSERT_GE(bytes.size(), 5 * (r.readings.size() - 1));
  int changed = 0;
  for (size_t k = 0; k + 1 < r.readings.size(); ++k) {
    const std::string frame = text_of(bytes, 5 * k, 5);
    ASSERT_EQ(frame.size(), 5u);
    EXPECT_EQ(frame[0], 'R');
    EXPECT_EQ(frame[4], '\r');
    EXPECT_EQ(std::stoi(frame.substr(1, 3)), r.readings[k]) << k;
    EXPECT_EQ((r.falls[k] - r.rises[k]) / 147000, r.readings[k]) << k;
    EXPECT_EQ((r.falls[k] - r.rises[k]) % 147000, 0) << k;
    // The truth at the cycle's start, truncated, within +-5 sd of the Gaussian noise (a bound
    // a draw leaves once in 1.7 million).
    const double true_in = distance_of(r.cycle_starts[k]) / 0.0254;
    EXPECT_GE(r.readings[k], std::floor(true_in - 5 * MAXBOTIX_NOISE_SD_M / 0.0254)) << k;
    EXPECT_LE(r.readings[k], std::floor(true_in + 5 * MAXBOTIX_NOISE_SD_M / 0.0254)) << k;
    if (k > 0 && r.readings[k] != r.readings[k - 1]) ++changed;
  }
  EXPECT_GT(changed, 50);  // the reading follows the target
  // AN shows the last reading once its ramp is done.
  const size_t last = r.readings.size() - 1;
  EXPECT_NEAR(maxbotix_lv_ez_analog_v(&r.s, r.cycle_starts[last] + 44300000, 5.0), r.readings[last] * 5.0 / 512.0,
              1e-12);
}

// Objects from 0 to 6 in range as 6 in; nothing in range: PW stays high its full 37.5 ms
// (255 x 147 us = 37.485 ms) and TX says the maximum 255.
TEST(MaxbotixLvEz1, CloserThanSixInchesReadsSixAndNothingReadsTheMaximum) {
  EXPECT_EQ(maxbotix_reading_inches(0.0, 0, 0, 0.0), 6);
  EXPECT_EQ(maxbotix_reading_inches(0.10, 0, 0, 0.0), 6);   // 3.9 in
  EXPECT_EQ(maxbotix_reading_inches(0.1524, 0, 0, 0.0), 6); // 6.0 in
  EXPECT_EQ(maxbotix_reading_inches(0.1780, 0, 0, 0.0), 7); // 7.008 in
  EXPECT_EQ(maxbotix_reading_inches(6.4516, 0, 0, 0.0), 254);
  EXPECT_EQ(maxbotix_reading_inches(6.48, 0, 0, 0.0), 255);
  EXPECT_EQ(maxbotix_reading_inches(INFINITY, 0, 0, 0.0), 255);
  EXPECT_EQ(maxbotix_reading_inches(NAN, 0, 0, 0.0), 255);
  EXPECT_LE(255 * MAXBOTIX_PW_NS_PER_INCH, MAXBOTIX_LISTEN_NS);
  uint8_t f[5];
  maxbotix_serial_frame(255, f);
  EXPECT_EQ(std::string(f, f + 5), "R255\r");
  maxbotix_serial_frame(6, f);
  EXPECT_EQ(std::string(f, f + 5), "R006\r");
}

// RX held low stops ranging at the end of the running cycle; brought high (>= 20 us) it starts a
// new cycle; both halves, given the same RX edges, stop and restart together.
TEST(MaxbotixLvEz1, RxHeldLowStopsBothHalvesAndRaisingItRestarts) {
  PinsRun r{{}, 1, 0.0, {}, {}, {}, {}};
  maxbotix_lv_ez_init(&r.s);
  maxbotix_lv_ez_serial tx;
  maxbotix_lv_ez_serial_init(&tx, 1, 0.0);
  maxbotix_lv_ez_serial_set_distance(&tx, 0.5, 0);  // 19.69 in -> 19
  std::vector<serial_byte> bytes(100);
  auto half = [](int64_t) { return 0.5; };

  // Cycles at 299, 348, 397 ms; RX low at 420 ms: cycle 397 runs to 446 ms, then the part stops.
  run_pins(r, 420000000, half);
  size_t n = maxbotix_lv_ez_serial_transmit(&tx, 0, 420000000, bytes.data(), 100);
  maxbotix_lv_ez_set_rx_level(&r.s, 0, 420000000);
  maxbotix_lv_ez_serial_set_rx_level(&tx, 0, 420000000);
  run_pins(r, 700000000, half);
  n += maxbotix_lv_ez_serial_transmit(&tx, 420000000, 700000000, bytes.data() + n, 100 - n);
  EXPECT_EQ(r.cycle_starts.size(), 3u);
  EXPECT_EQ(n, 15u);
  EXPECT_EQ(maxbotix_lv_ez_next_cycle_ns(&r.s, nullptr), INT64_MAX);
  EXPECT_EQ(r.falls.size(), 3u);

  // RX high at 700 ms: the command is seen 20 us later.
  maxbotix_lv_ez_set_rx_level(&r.s, 1, 700000000);
  maxbotix_lv_ez_serial_set_rx_level(&tx, 1, 700000000);
  run_pins(r, 800000000, half);
  n += maxbotix_lv_ez_serial_transmit(&tx, 700000000, 800000000, bytes.data() + n, 100 - n);
  ASSERT_EQ(r.cycle_starts.size(), 6u);
  EXPECT_EQ(r.cycle_starts[3], 700020000);
  EXPECT_EQ(r.cycle_starts[4], 749020000);
  EXPECT_EQ(r.cycle_starts[5], 798020000);
  ASSERT_EQ(n, 25u);
  EXPECT_EQ(text_of(bytes, 15, 5), "R019\r");
  EXPECT_NEAR(static_cast<double>(bytes[15].end_ns), 700020000 + 44.3e6 + 1041667, 1.0);
  EXPECT_EQ(r.falls[3] - r.rises[3], 19 * 147000);
}

// ---------------------------------------------------------------- quadrature encoder

// A decoder as firmware writes it: the Gray sequence 00 -> 10 -> 11 -> 01 -> 00 (A, B) counts
// +1 per step, the reverse -1; both channels changing at once is an error.
struct Decoder {
  int a = 0, b = 0;
  int64_t count = 0;
  int errors = 0;
  void edge(int channel, int level) {
    const int old_state = state(a, b);
    (channel == 0 ? a : b) = level;
    const int d = (state(a, b) - old_state + 4) % 4;
    if (d == 1) ++count;
    else if (d == 3) --count;
    else ++errors;
  }
  static int state(int a, int b) { return a && !b ? 1 : (a && b ? 2 : (!a && b ? 3 : 0)); }
};

// Constant rate: every edge is at the exact crossing time of its quarter-cycle boundary
// (rounded to the ns), whether the motion is given once or renewed every 1 ms quantum; forward,
// A rises a quarter cycle before B.
TEST(QuadratureEncoder, EdgesAreAtTheExactCrossingTimesOfAConstantRate) {
  const uint32_t cpr = 100;
  const double quarter = 2.0 * M_PI / 400.0;
  const double rate = 2.0 * M_PI * 0.37;  // 148 edges per second
  const double theta0 = 0.3 * quarter;
  quadrature_encoder once, renewed;
  encoder_init(&once, cpr, theta0);
  encoder_init(&renewed, cpr, theta0);
  encoder_set_motion(&once, theta0, rate, 0);
  Decoder dec;
  std::vector<int> channels;
  int m = 1;
  for (int64_t q = 0; q < 2000000000; q += 1000000) {
    encoder_set_motion(&renewed, theta0 + rate * static_cast<double>(q) * 1e-9, rate, q);
    while (encoder_next_edge_ns(&renewed) < q + 1000000) {
      const int64_t t_once = encoder_next_edge_ns(&once);
      const int64_t t = encoder_next_edge_ns(&renewed);
      // Boundary m crossed at (m - 0.3) quarters / rate; doubles and ns rounding: +-1 ns.
      const double exact_ns = (m - 0.3) * quarter / rate * 1e9;
      ASSERT_NEAR(static_cast<double>(t), exact_ns, 1.0) << m;
      ASSERT_NEAR(static_cast<double>(t_once), exact_ns, 1.0) << m;
      int ch, level, ch1, level1;
      encoder_take_edge(&renewed, &ch, &level);
      encoder_take_edge(&once, &ch1, &level1);
      ASSERT_EQ(ch, ch1);
      ASSERT_EQ(level, level1);
      dec.edge(ch, level);
      if (channels.size() < 8) channels.push_back(ch * 2 + level);
      ++m;
    }
  }
  EXPECT_EQ(m - 1, 296);  // 2 s at 148 edges/s (first at 0.3 quarter in: 296 edges before 2 s)
  EXPECT_EQ(dec.count, 296);
  EXPECT_EQ(dec.errors, 0);
  // A up, B up, A down, B down, ... (channel * 2 + level).
  const std::vector<int> expected = {1, 3, 0, 2, 1, 3, 0, 2};
  EXPECT_EQ(channels, expected);
}

// Many revolutions forward, then back past the start, with the motion renewed every 1 ms from a
// smooth profile (so the given angle is not exactly the previous linear extrapolation and
// catch-up edges occur): the decoder's count equals floor(angle / quarter) at every quantum,
// except within 1 ns of travel of a boundary (edge times are rounded to the ns), and exactly at
// the end.
TEST(QuadratureEncoder, CountsFollowTheWheelAngleOverManyRevolutionsForwardThenBack) {
  const uint32_t cpr = 360;
  const double quarter = 2.0 * M_PI / (4.0 * cpr);
  // 0 -> 40 rev forward and back to -7 rev over 8 s: angle(t) = A (1 - cos(w t)) - B t^2 style
  // smooth profile with its exact derivative as the rate.
  const double peak = 40.0 * 2.0 * M_PI, end_angle = -7.0 * 2.0 * M_PI;
  auto angle = [&](double t) {
    const double s = t / 8.0;
    return peak * std::sin(M_PI * s) + end_angle * s * s + 0.123;
  };
  auto rate = [&](double t) {
    const double s = t / 8.0;
    return peak * M_PI / 8.0 * std::cos(M_PI * s) + end_angle * 2.0 * s / 8.0;
  };
  quadrature_encoder e;
  encoder_init(&e, cpr, angle(0.0));
  Decoder dec;
  const int64_t start_quarter = static_cast<int64_t>(std::floor(angle(0.0) / quarter));
  int64_t max_count = 0;
  int checked = 0;
  for (int64_t q = 0; q <= 8000000000; q += 1000000) {
    const double t = static_cast<double>(q) * 1e-9;
    encoder_set_motion(&e, angle(t), rate(t), q);
    while (encoder_next_edge_ns(&e) <= q) {
      int ch, level;
      encoder_take_edge(&e, &ch, &level);
      dec.edge(ch, level);
    }
    const double a = angle(t);
    const double to_boundary = std::fabs(a / quarter - std::round(a / quarter)) * quarter;
    if (to_boundary > std::fabs(rate(t)) * 1e-9) {
      ASSERT_EQ(dec.count, static_cast<int64_t>(std::floor(a / quarter)) - start_quarter) << q;
      ++checked;
    }
    max_count = std::max(max_count, dec.count);
    while (encoder_next_edge_ns(&e) < q + 1000000) {
      int ch, level;
      encoder_take_edge(&e, &ch, &level);
      dec.edge(ch, level);
    }
  }
  EXPECT_GT(checked, 7900);
  EXPECT_EQ(dec.errors, 0);
  EXPECT_GT(max_count, 37 * 1440);  // went ~40 revolutions out (x4 counts: 1440 per rev)
  // Final: stopped at angle(8 s) = -7 rev + 0.123 rad.
  encoder_set_motion(&e, angle(8.0), 0.0, 8001000000);
  while (encoder_next_edge_ns(&e) != INT64_MAX) {
    int ch, level;
    encoder_take_edge(&e, &ch, &level);
    dec.edge(ch, level);
  }
  EXPECT_EQ(dec.count, static_cast<int64_t>(std::floor(angle(8.0) / quarter)) - start_quarter);
  EXPECT_NEAR(static_cast<double>(dec.count), -7.0 * 1440.0, 1.0);
  EXPECT_EQ(encoder_levels(&e), (dec.a ? 1 : 0) | (dec.b ? 2 : 0));
}

}  // namespace
