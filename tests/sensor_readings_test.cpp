// What the in-process device models give the firmware reaches the simulator (RunTap::on_reading,
// from the link's readings[]) and agrees with the truth each model was fed, within the datasheet's
// errors; a firmware that scribbles nonsense there is stopped like any other link corruption.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "devices/sharp_gp2d12.h"
#include "firmware_run.hpp"
#include "link_check.h"
#include "runtime/lockstep.hpp"
#include "scene/project_loader.hpp"

namespace sear::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.80665;
constexpr double kDuration_s = 3;
constexpr double kTurnFrom_s = 1.2, kTurnTo_s = 2.6;  // the script turns the rover on the spot
constexpr double kIrNoise_v = 0.01;
constexpr int kEncoderCycles = 90;
constexpr double kQuarter_rad = 2 * kPi / (4 * kEncoderCycles);

// The bundled rover facing a wall 0.50 m beyond its IR ranger (the face at x = 0.65, the ranger at
// x = 0.15), standing for 1.2 s, then turning left on the spot until 2.6 s.
std::string readings_project() {
  const std::string mcu = std::string(R"(    <script>
      <motor t="1.2" name="left" duty="0.5" dir="reverse"/>
      <motor t="1.2" name="right" duty="0.5" dir="forward"/>
      <motor t="2.6" name="left" duty="0" dir="brake"/>
      <motor t="2.6" name="right" duty="0" dir="brake"/>
    </script>
    <mcu name="main">
      <firmware executable=")") + READINGS_PROBE + R"("/>
      <gp2d12 name="ir" adc="0" pos="0.15 0 0.02" noise_v="0.01"/>
      <mpu6000 name="imu" cs="53" pos="0 0 0.05" gyro_bias="0"/>
      <hmc5883l name="compass" pos="0 0 0.1"/>
      <quadrature_encoder name="encoder" a="2" b="3" wheel="left" cycles_per_rev="90"/>
    </mcu>
)";
  const std::string world = R"(    <gps_origin latitude="52.2053" longitude="0.1218" altitude="12"/>
    <magnetic declination_deg="0.9"/>
    <wall name="target" from="0.7 -2" to="0.7 2" height="0.5" thickness="0.1"/>
)";
  return rover_project(mcu, world, kDuration_s);
}

struct Record {
  double t;
  std::array<double, SEAR_LINK_SAMPLE_VALUES> v{};
  std::size_t n = 0;
};

// Every sample and every reading, per device name, unthinned.
class Recorder final : public RunTap {
 public:
  explicit Recorder(const McuDesc& mcu) : mcu_(mcu) {}
  void on_sample(std::size_t, std::size_t device, const sear_link_sample& s) override {
    Record r{static_cast<double>(s.time_ns) * 1e-9};
    std::copy(s.value, s.value + SEAR_LINK_SAMPLE_VALUES, r.v.begin());
    r.n = SEAR_LINK_SAMPLE_VALUES;
    samples[mcu_.devices.at(device).name].push_back(r);
  }
  void on_reading(std::size_t, std::size_t device, std::int64_t time_ns, const double* values,
                  std::size_t count) override {
    Record r{static_cast<double>(time_ns) * 1e-9};
    std::copy(values, values + std::min<std::size_t>(count, SEAR_LINK_SAMPLE_VALUES), r.v.begin());
    r.n = count;
    readings[mcu_.devices.at(device).name].push_back(r);
  }
  std::map<std::string, std::vector<Record>> samples, readings;

 private:
  const McuDesc& mcu_;
};

class NoListener final : public McuListener {
  void on_events(std::size_t, const sear_event*, std::size_t) override {}
  void on_stop(std::size_t, std::int64_t) override {}
};

// The truth the model held at time t: the last sample at or before it.
const Record& truth_at(const std::vector<Record>& samples, double t) {
  auto it = std::upper_bound(samples.begin(), samples.end(), t, [](double x, const Record& r) { return x < r.t; });
  return *std::prev(it == samples.begin() ? std::next(it) : it);
}

class SensorReadings : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    Diagnostics diagnostics;
    auto project = load_project_text(readings_project(), (dir_->path() / "project.xml").string(), diagnostics);
    ASSERT_TRUE(project) << diagnostics.joined();
    project_ = new ProjectDesc(std::move(*project));
    recorder_ = new Recorder(project_->robots.at(0).mcus.at(0));
    Simulation sim(*project_, project_->run.seed);
    LockstepOptions options;
    options.out_dir = dir_->path().string();
    options.mcu.tap = recorder_;
    NoListener listener;
    Lockstep lockstep(sim, *project_, options, listener);
    while (sim.time_ns() < std::llround(kDuration_s * 1e9)) ASSERT_TRUE(lockstep.step());
  }
  static void TearDownTestSuite() {
    delete recorder_;
    delete project_;
    delete dir_;
  }
  static const std::vector<Record>& samples(const char* d) { return recorder_->samples[d]; }
  static const std::vector<Record>& readings(const char* d) { return recorder_->readings[d]; }
  static TempDir* dir_;
  static ProjectDesc* project_;
  static Recorder* recorder_;
};
TempDir* SensorReadings::dir_ = nullptr;
ProjectDesc* SensorReadings::project_ = nullptr;
Recorder* SensorReadings::recorder_ = nullptr;

TEST_F(SensorReadings, EveryModelsReadingsArriveInTimeOrder) {
  // Per kind, the values of lockstep_link.h's struct sear_link_reading, and how many readings at
  // least: the IR's 38.3 ms cycle (78 in 3 s), the MPU's 100 samples/s once awake at 50 ms (the
  // tap is told at most once a quantum), the HMC's 15 Hz, and an encoder edge in most quanta of
  // the turn.
  const std::map<std::string, std::pair<std::size_t, std::size_t>> expected = {
      {"ir", {1, 70}}, {"imu", {6, 280}}, {"compass", {3, 40}}, {"encoder", {2, 300}}};
  for (const auto& [name, want] : expected) {
    SCOPED_TRACE(name);
    const auto& r = readings(name.c_str());
    EXPECT_GE(r.size(), want.second);
    for (std::size_t i = 0; i < r.size(); ++i) {
      EXPECT_EQ(r[i].n, want.first);
      if (i) {
        EXPECT_GE(r[i].t, r[i - 1].t);
      }
      EXPECT_LE(r[i].t, kDuration_s);
    }
  }
}

TEST_F(SensorReadings, IrVoltsFollowTheDatasheetCurveWithinItsNoise) {
  // The wall stands 0.50 m ahead until the turn.
  EXPECT_NEAR(truth_at(samples("ir"), 1.0).v[0], 0.50, 0.002);
  // Each reading is the sample of that instant through the typical curve plus N(0, noise_v): all
  // within 4 sd (3 sd would be crossed by one of ~80 draws one run in eight), and their spread
  // that sd within 30 % (the estimate's own sd is 1/sqrt(2n), 8 %).
  double sum_sq = 0;
  std::size_t n = 0;
  for (const Record& r : readings("ir")) {
    if (r.t == 0) continue;  // the output before the first sample: 0 V
    const Record& s = truth_at(samples("ir"), r.t);
    ASSERT_EQ(s.t, r.t);  // the output changes when a measurement is taken
    const double residual = r.v[0] - gp2d12_output_v(s.v[0]);
    EXPECT_LE(std::fabs(residual), 4 * kIrNoise_v) << "at " << r.t << " s, " << s.v[0] << " m";
    sum_sq += residual * residual;
    ++n;
  }
  ASSERT_GT(n, 70u);
  EXPECT_NEAR(std::sqrt(sum_sq / static_cast<double>(n)), kIrNoise_v, 0.3 * kIrNoise_v);
  // Standing 0.50 m from the wall: between the table's 0.40 V typical at 80 cm and 2.4 V at 10 cm.
  EXPECT_NEAR(readings("ir")[10].v[0], gp2d12_output_v(0.50), 4 * kIrNoise_v);
  EXPECT_GT(readings("ir")[10].v[0], GP2D12_V80_TYP_V + 0.1);
}

// The model draws each part's errors from the datasheet's tolerances taken as 3 sd (mpu6000.c); a
// bound at 4 sd of those draws holds for all but one part in ~16000 per figure. PS-MPU-6000A
// table 6.2 at +-4 g: zero-g offset +-50 mg (x, y), +-80 mg (z); calibration +-3 %; cross-axis
// +-2 %. Table 6.1 at +-500 deg/s with the zero-rate offset set to 0 (gyro_bias="0"): scale
// +-3 %, cross-axis +-2 %.
constexpr double kFourSd = 4.0 / 3.0;
double part_tolerance(const std::array<double, 3>& truth, int axis, double offset) {
  double cross = 0;
  for (int j = 0; j < 3; ++j)
    if (j != axis) cross += std::fabs(truth[static_cast<std::size_t>(j)]);
  return kFourSd * (offset + 0.03 * std::fabs(truth[static_cast<std::size_t>(axis)]) + 0.02 * cross);
}

// The truth's mean over [from, to]: what the reading's low-pass filter (44 Hz, a response ~23 ms
// long) makes of the chassis' 1 kHz vibration, and what a mean of readings is compared with.
std::array<double, 6> truth_mean(const std::vector<Record>& truth, double from, double to) {
  std::array<double, 6> sum{};
  std::size_t n = 0;
  for (const Record& s : truth)
    if (s.t >= from && s.t <= to) {
      for (std::size_t k = 0; k < 6; ++k) sum[k] += s.v[k];
      ++n;
    }
  for (double& x : sum) x /= static_cast<double>(std::max<std::size_t>(n, 1));
  return sum;
}

TEST_F(SensorReadings, ImuReadsOneGUpAtRestAndTheTruthRateTurning) {
  const auto& truth = samples("imu");
  std::array<double, 6> rest_sum{}, turn_sum{};
  std::size_t at_rest = 0, turning = 0;
  for (const Record& r : readings("imu")) {
    // Awake at 50 ms and its filters settled; 0.2 s clear of the script's start and stop.
    const bool rest = r.t > 0.2 && r.t < kTurnFrom_s;
    const bool turn = r.t > kTurnFrom_s + 0.2 && r.t < kTurnTo_s;
    if (!rest && !turn) continue;
    for (std::size_t k = 0; k < 6; ++k) (rest ? rest_sum : turn_sum)[k] += r.v[k];
    ++(rest ? at_rest : turning);
    // Each gyro reading against the rate over the filter's span: within the part's errors, its
    // noise (0.005 deg/s/sqrt(Hz) over 42 Hz, 0.032 deg/s rms, at 4 sd: 0.0023 rad/s) with half
    // a 1/65.5 deg/s step, and the chassis' rate jitter the filter leaves (0.005 rad/s over 20 ms).
    const std::array<double, 6> m = truth_mean(truth, r.t - 0.02, r.t);
    const std::array<double, 3> rate{m[3], m[4], m[5]};
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(r.v[static_cast<std::size_t>(a + 3)], rate[static_cast<std::size_t>(a)],
                  part_tolerance(rate, a, 0) + 0.0025 + 0.005)
          << "gyro axis " << a << " at " << r.t << " s";
  }
  ASSERT_GT(at_rest, 90u);
  ASSERT_GT(turning, 100u);
  // The accelerometer's mean against the truth's over each span (the filter keeps the mean): the
  // part's errors, with its noise averaged away. Standing, that is +1 g on z.
  const std::array<double, 6> rest_truth = truth_mean(truth, 0.2, kTurnFrom_s);
  const std::array<double, 6> turn_truth = truth_mean(truth, kTurnFrom_s + 0.2, kTurnTo_s);
  EXPECT_NEAR(rest_truth[2], kG, 0.01);
  const std::array<double, 3> rest_f{rest_truth[0], rest_truth[1], rest_truth[2]};
  const std::array<double, 3> turn_f{turn_truth[0], turn_truth[1], turn_truth[2]};
  for (int a = 0; a < 3; ++a) {
    const double offset = (a == 2 ? 0.080 : 0.050) * kG;
    const auto k = static_cast<std::size_t>(a);
    EXPECT_NEAR(rest_sum[k] / static_cast<double>(at_rest), rest_f[k], part_tolerance(rest_f, a, offset)) << a;
    EXPECT_NEAR(turn_sum[k] / static_cast<double>(turning), turn_f[k], part_tolerance(turn_f, a, offset)) << a;
  }
  // It did turn, faster than 2 rad/s, and its gyro saw it.
  EXPECT_GT(turn_truth[5], 2.0);
  EXPECT_NEAR(turn_sum[5] / static_cast<double>(turning), turn_truth[5], part_tolerance({0, 0, turn_truth[5]}, 2, 0));
}

TEST_F(SensorReadings, EncoderAngleIsWithinOneCountOfTheShaft) {
  // The shaft between samples turns at the sample's rate, as the model plays its edges out.
  const auto& truth = samples("encoder");
  double last = 0;
  for (const Record& r : readings("encoder")) {
    const Record& s = truth_at(truth, r.t);
    const double shaft = s.v[0] + s.v[1] * (r.t - s.t);
    EXPECT_EQ(r.v[0], std::round(r.v[0]));
    EXPECT_NEAR(r.v[1], r.v[0] * kQuarter_rad, 1e-9);
    EXPECT_LE(std::fabs(r.v[1] - shaft), kQuarter_rad + 1e-6) << "at " << r.t << " s";
    last = r.v[0];
  }
  EXPECT_GT(std::fabs(last), 4 * kEncoderCycles);  // at least a turn of the wheel
}

TEST_F(SensorReadings, CompassFieldIsTheTruthWithinNoiseAndQuantisation) {
  // Datasheet: 2 mG noise with one sample, 8 averaged (the driver's setting): 0.71 mG, at 4 sd;
  // plus half a step of 1/1090 G: 0.33 uT. A measurement ends on the truth held then, which at a
  // sample's own instant may still be the one before.
  const auto& truth = samples("compass");
  std::size_t checked = 0;
  for (const Record& r : readings("compass")) {
    if (r.t < 0.1) continue;  // before the driver set it up: registers at 0
    auto it = std::lower_bound(truth.begin(), truth.end(), r.t, [](const Record& s, double x) { return s.t < x; });
    double worst_best = INFINITY;
    for (auto c = it == truth.begin() ? it : std::prev(it); c != truth.end() && c <= it; ++c) {
      if (c->t > r.t) continue;
      double worst = 0;
      for (std::size_t a = 0; a < 3; ++a) worst = std::max(worst, std::fabs(r.v[a] - c->v[a]));
      worst_best = std::min(worst_best, worst);
    }
    EXPECT_LE(worst_best, 4 * 0.71e-7 + 0.5e-4 / 1090) << "at " << r.t << " s";
    ++checked;
  }
  EXPECT_GT(checked, 35u);
}

// The simulator's check of what it reads in readings[]: only a moved count is a new reading; its
// time within what the firmware's clock reached, never before the last; values as the kind makes.
TEST(SensorReadingsGuard, TheLinkCheckTakesOnlyPlausibleNewReadings) {
  auto link = std::make_unique<sear_link>();
  sear_reading_watch watch{};
  sear_link_reading r{};
  char why[256] = "";
  const auto check = [&](std::uint32_t kind, std::int64_t clock_ns) {
    return sear_link_check_reading(link.get(), 0, kind, clock_ns, &watch, &r, why, sizeof why);
  };
  EXPECT_EQ(check(SEAR_INPUT_SWITCH, 1000), 0);  // count 0: nothing published yet
  link->readings[0] = {500, 1, 0, {1, 0, 0, 0, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_SWITCH, 1000), 1);
  EXPECT_EQ(r.value[0], 1);
  EXPECT_EQ(check(SEAR_INPUT_SWITCH, 1000), 0);  // the same count again
  link->readings[0] = {400, 2, 0, {0, 0, 0, 0, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_SWITCH, 1000), -1) << "before the last";
  EXPECT_NE(std::string(why).find("readings[0].time_ns"), std::string::npos) << why;
  link->readings[0] = {2000, 2, 0, {0, 0, 0, 0, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_SWITCH, 1000), -1) << "after the firmware's clock";
  link->readings[0] = {600, 2, 0, {0.5, 0, 0, 0, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_SWITCH, 1000), -1) << "a switch half closed";
  link->readings[0] = {600, 2, 0, {17 * kG, 0, 0, 0, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_MPU6000, 1000), -1) << "beyond the widest full scale";
  link->readings[0] = {600, 2, 0, {15.9 * kG, 0, 0, -34.9, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_MPU6000, 1000), 1) << why;  // +16 g, -2000 deg/s are what it reads at most
  link->readings[0] = {700, 3, 0, {0, 0, 0, 0, 0, 0}};
  EXPECT_EQ(check(SEAR_INPUT_KIND_END, 1000), -1) << "a kind without readings";
}

// A NaN where the first input's reading goes: reported as the link's other corruptions are.
TEST(SensorReadingsGuard, ANanInAReadingStopsTheMcuAsCorrupted) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + READINGS_SCRIBBLE_PROBE +
                          "\"/>\n      <bump name=\"bump\" pin=\"4\" pos=\"0.2 0 0.02\"/>\n    </mcu>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, "", 0.5), "--quiet");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find("mcu rover.main overwrote the simulator link at readings[0].value[0]"), std::string::npos)
      << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  ASSERT_EQ(summary["mcu_stops"].size(), 1u);
  EXPECT_EQ(summary["mcu_stops"][0]["kind"], "corrupted");
  // It scribbled after its 50 + 50 ms of delays (and the bus set-up before): within that quantum.
  const double t = summary["mcu_stops"][0]["sim_time_s"].get<double>();
  EXPECT_GE(t, 0.100);
  EXPECT_LE(t, 0.110);
}

}  // namespace
}  // namespace sear::test
