// The simulator's checks of the link at their boundaries: the last value a firmware can honestly
// write passes and the first one past it is refused, for every event field and reading kind with a
// range (the board's 70 pins, PWM duty, servo pulse, UART rate and port, each sensor's output).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "firmware_run.hpp"
#include "link_check.h"
#include "lockstep_link.h"

namespace sear::test {
namespace {

// One event alone in a turn from 0 to 1 ms, checked against a fresh watch.
int check_event(std::uint8_t kind, std::uint8_t index, std::uint32_t value, std::string* why_out = nullptr) {
  auto link = std::make_unique<sear_link>();
  sear_link_watch w;
  sear_link_watch_init(&w, 0);
  w.quantum_end_ns = 1'000'000;
  w.clock_ns = 1'000'000;
  link->events[0] = {500'000, value, kind, index, {0, 0}};
  sear_event e;
  char why[256] = "";
  const int got = sear_link_check_event(link.get(), 0, &w, &e, why, sizeof why);
  if (why_out) *why_out = why;
  return got;
}

TEST(LinkBoundaries, EventFieldsPassUpToTheirLastValueAndNoFurther) {
  // The ATmega2560 board has pins 0..69 (SEAR_LINK_PINS): 69 is the last, 70 the first refused.
  std::string why;
  EXPECT_EQ(check_event(SEAR_EVENT_PIN, SEAR_LINK_PINS - 1, 1), 0);
  EXPECT_EQ(check_event(SEAR_EVENT_PIN, SEAR_LINK_PINS, 1, &why), -1);
  EXPECT_NE(why.find("events[0].index (pin 70; the board has 0..69)"), std::string::npos) << why;
  EXPECT_EQ(check_event(SEAR_EVENT_PIN, 0, 2), -1);  // a level is 0 or 1
  EXPECT_EQ(check_event(SEAR_EVENT_PIN_MODE, 0, 2), 0);  // INPUT_PULLUP, the last mode
  EXPECT_EQ(check_event(SEAR_EVENT_PIN_MODE, 0, 3), -1);
  EXPECT_EQ(check_event(SEAR_EVENT_PWM, 0, 255), 0);  // 8-bit duty
  EXPECT_EQ(check_event(SEAR_EVENT_PWM, 0, 256), -1);
  EXPECT_EQ(check_event(SEAR_EVENT_SERVO, 0, 2600), 0);  // the longest servo pulse the HAL makes
  EXPECT_EQ(check_event(SEAR_EVENT_SERVO, 0, 2601), -1);
  // UARTs 0..3 at 300..2 000 000 baud (hal/uart.h).
  EXPECT_EQ(check_event(SEAR_EVENT_UART_BEGIN, SEAR_LINK_UARTS - 1, 300), 0);
  EXPECT_EQ(check_event(SEAR_EVENT_UART_BEGIN, SEAR_LINK_UARTS, 300), -1);
  EXPECT_EQ(check_event(SEAR_EVENT_UART_BEGIN, 0, 299), -1);
  EXPECT_EQ(check_event(SEAR_EVENT_UART_BEGIN, 0, 2'000'000), 0);
  EXPECT_EQ(check_event(SEAR_EVENT_UART_BEGIN, 0, 2'000'001), -1);
  EXPECT_EQ(check_event(SEAR_EVENT_CAN_BEGIN, 0, 10'000), 0);  // the MCP2515's bit rates
  EXPECT_EQ(check_event(SEAR_EVENT_CAN_BEGIN, 0, 9'999), -1);
  EXPECT_EQ(check_event(SEAR_EVENT_CAN_BEGIN, 0, 1'000'000), 0);
  EXPECT_EQ(check_event(SEAR_EVENT_CAN_BEGIN, 0, 1'000'001), -1);
}

// A reading of `kind` whose value k is v (the others 0), published at 600 ns of a 1000 ns clock.
int check_reading(std::uint32_t kind, std::uint32_t k, double v) {
  auto link = std::make_unique<sear_link>();
  sear_reading_watch watch{};
  sear_link_reading r{};
  link->readings[0] = {600, 1, 0, {0, 0, 0, 0, 0, 0}};
  link->readings[0].value[k] = v;
  char why[256] = "";
  return sear_link_check_reading(link.get(), 0, kind, 1000, &watch, &r, why, sizeof why);
}

double just_above(double v) { return std::nextafter(v, std::numeric_limits<double>::infinity()); }
double just_below(double v) { return std::nextafter(v, -std::numeric_limits<double>::infinity()); }

struct Bound {
  std::uint32_t kind;
  std::uint32_t value;
  double low, high;  // the widest honest reading, both ends inclusive
  const char* what;
};
void PrintTo(const Bound& b, std::ostream* os) { *os << b.what; }

class ReadingBounds : public ::testing::TestWithParam<Bound> {};

TEST_P(ReadingBounds, TheLastHonestValuePassesAndTheNextDoubleIsRefused) {
  const Bound b = GetParam();
  EXPECT_EQ(check_reading(b.kind, b.value, b.high), 1);
  EXPECT_EQ(check_reading(b.kind, b.value, just_above(b.high)), -1);
  EXPECT_EQ(check_reading(b.kind, b.value, b.low), 1);
  EXPECT_EQ(check_reading(b.kind, b.value, just_below(b.low)), -1);
}

constexpr double kG = 9.80665;
constexpr double kPi = 3.14159265358979;

// link_check.c's plausible(): outputs within the rails with room for an AVCC up to 10 V, an echo
// no longer than 40 ms (38 ms of no echo), 16 g and 2000 deg/s (the MPU's widest full scales) with
// a little room for rounding, 18 G (the HMC5883L's overflow code at its least sensitive gain).
INSTANTIATE_TEST_SUITE_P(
    EveryKind, ReadingBounds,
    ::testing::Values(Bound{SEAR_INPUT_GP2D12, 0, 0.0, 10.0, "GP2D12 volts"},
                      Bound{SEAR_INPUT_HCSR04, 0, 0.0, 0.04, "HC-SR04 echo width"},
                      Bound{SEAR_INPUT_HCSR04, 1, 0.0, 7.0, "HC-SR04 distance"},
                      Bound{SEAR_INPUT_MAXBOTIX, 0, 0.0, 10.0, "MaxBotix volts"},
                      Bound{SEAR_INPUT_MAXBOTIX, 1, 0.0, 1000.0, "MaxBotix inches"},
                      Bound{SEAR_INPUT_MPU6000, 0, -16.1 * kG, 16.1 * kG, "MPU-6000 accel"},
                      Bound{SEAR_INPUT_MPU6050, 5, -2001.0 * kPi / 180.0, 2001.0 * kPi / 180.0, "MPU-6050 gyro"},
                      Bound{SEAR_INPUT_HMC5883L, 2, -1.8e-3, 1.8e-3, "HMC5883L field"},
                      Bound{SEAR_INPUT_QMC5883L, 0, -1.8e-3, 1.8e-3, "QMC5883L field"}),
    case_name<Bound>);

TEST(LinkBoundaries, LevelsAreZeroOrOneAndCountsWhole) {
  EXPECT_EQ(check_reading(SEAR_INPUT_SWITCH, 0, 1.0), 1);
  EXPECT_EQ(check_reading(SEAR_INPUT_SWITCH, 0, just_below(1.0)), -1);
  EXPECT_EQ(check_reading(SEAR_INPUT_GP2D15, 0, just_above(0.0)), -1);
  EXPECT_EQ(check_reading(SEAR_INPUT_ENCODER, 0, -1e13), 1);
  EXPECT_EQ(check_reading(SEAR_INPUT_ENCODER, 0, 2.5), -1);  // a count is whole
  EXPECT_EQ(check_reading(SEAR_INPUT_ENCODER, 0, just_above(1e13)), -1);
}

}  // namespace
}  // namespace sear::test
