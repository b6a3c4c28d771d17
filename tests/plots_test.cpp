// Plots of a run (tools/plots/plot_run.py through write_plots): a short run on hills, among every
// kind of obstacle, with a GPS-guided rover and a scripted one that hits a crate, then the plots:
// each one a PNG of 1200 x 900 px (read from its header) that shows its data (decoded with stb,
// the pixels of the colour the plotter draws that data in counted). The world.json and the
// sensors CSV the plots are drawn from are checked against the project. With no interpreter the
// plotting is one warning, and `sear run` still exits 0. `sear run` draws in the background,
// holding a lock on its output folder, which the next run into the folder waits for.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>

#include "exporters/mcu_capture.hpp"
#include "exporters/plot_runner.hpp"
#include "exporters/run_summary.hpp"
#include "exporters/sensor_csv.hpp"
#include "exporters/trace_csv.hpp"
#include "exporters/world_json.hpp"
#include "firmware_run.hpp"
#include "runtime/lockstep.hpp"
#include "scene/project_loader.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr int kPlotWidth = 1200, kPlotHeight = 900;  // tools/plots/plot_run.py: 12 x 9 in at 100 dpi
constexpr double kTraceRate_hz = 50;
constexpr double kDuration_s = 3;
// The hills heightmap is 129 x 129 samples: under the cap, so it is written whole.
constexpr int kHillsSamples = 129;

// Two rovers on the hills: "gps" runs the GPS waypoint follower with a NEO-6M (fix after 0.5 s,
// 5 a second) and an HMC5883L; "bumper" is scripted at full speed into the crate 1 m ahead of it.
std::string plots_project() {
  const std::string assets = SEAR_ASSET_DIR;
  return R"(<project name="plots">
  <run duration=")" + std::to_string(kDuration_s) + R"(" seed="1" trace_rate=")" + std::to_string(kTraceRate_hz) + R"("/>
  <world step="0.001">
    <gps_origin latitude="52.2053" longitude="0.1218" altitude="12"/>
    <magnetic declination_deg="1.5"/>
    <terrain type="heightmap" image=")" + assets + R"(/heightmaps/hills.png" size="40 40" min_height="0" max_height="1.2"/>
    <box name="crate" pos="1.3 4" size="0.4 1.0 0.4"/>
    <tree name="oak" pos="-3 -3" trunk_radius="0.15" trunk_height="2.5" crown_radius="1.2"/>
    <wall name="north_wall" from="-6 7" to="6 7" height="0.6" thickness="0.15"/>
    <mesh name="rock" file=")" + assets + R"(/meshes/rock.obj" pos="2 -2" yaw_deg="35"/>
  </world>
  <robot name="gps" file=")" + assets + R"(/robots/rover.xml">
    <pose x="0" y="0"/>
    <mcu name="main">
      <firmware executable=")" + GPS_WAYPOINTS + R"("/>
      <ublox_neo6m name="gps" uart="3" rate_hz="5" ttff="0.5" cep="0.001"/>
      <hmc5883l name="compass" pos="0 0 0.1"/>
      <motor name="left" pwm="3" dir="12" brake="9"/>
      <motor name="right" pwm="11" dir="13" brake="8"/>
    </mcu>
  </robot>
  <robot name="bumper" file=")" + assets + R"(/robots/rover.xml">
    <pose x="0" y="4"/>
    <script>
      <motor t="0" name="left" duty="1"/>
      <motor t="0" name="right" duty="1"/>
    </script>
  </robot>
</project>
)";
}

// The run as `sear run` makes it, with the sensor CSV tapped and world.json written, in-process:
// the plots are tested before `sear run` writes their inputs itself.
void run_for_plots(const TempDir& dir, const fs::path& out) {
  const std::string file = dir.write("project.xml", plots_project());
  Diagnostics diagnostics;
  auto project = load_project(file, diagnostics);
  ASSERT_TRUE(project) << diagnostics.joined();
  fs::create_directories(out);
  write_world_json((out / "world.json").string(), *project);
  Simulation sim(*project, project->run.seed);
  TraceCsv trace(out.string(), sim, UINT64_MAX);
  McuCapture capture(out.string(), {{"gps.main", 0}}, false, UINT64_MAX);
  SensorCsv sensors(out.string(), *project, 1.0 / kTraceRate_hz, UINT64_MAX);
  LockstepOptions options;
  options.out_dir = out.string();
  options.mcu.tap = &sensors;
  Lockstep lockstep(sim, *project, options, capture);
  const std::int64_t end_ns = std::llround(kDuration_s * 1e9);
  const std::int64_t trace_every = std::llround(1e9 / kTraceRate_hz / static_cast<double>(sim.step_ns()));
  trace.write_row(sim);
  for (std::int64_t steps = 1; sim.time_ns() < end_ns; ++steps) {
    ASSERT_TRUE(lockstep.step());
    capture.advance_to(sim.time_ns());
    if (steps % trace_every == 0) trace.write_row(sim);
  }
  trace.flush();
  capture.finish(sim.time_ns());
  sensors.finish();
  RunOutcome outcome;
  outcome.project_name = project->name;
  std::ofstream(out / "summary.json") << summary_json(sim, outcome);
}

struct Png {
  int width = 0, height = 0;       // from the IHDR chunk
  std::vector<std::uint32_t> rgb;  // decoded, 0xRRGGBB per pixel
};

Png read_png(const fs::path& path) {
  const std::string bytes = read_file(path);
  Png png;
  EXPECT_GE(bytes.size(), 24u) << path;
  if (bytes.size() < 24) return png;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
  EXPECT_EQ(bytes.substr(12, 4), "IHDR") << path;
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = v << 8 | static_cast<unsigned char>(bytes[at + i]);
    return static_cast<int>(v);
  };
  png.width = be32(16);
  png.height = be32(20);
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                                static_cast<int>(bytes.size()), &w, &h, &channels, 3);
  EXPECT_NE(pixels, nullptr) << path << ": " << stbi_failure_reason();
  if (!pixels) return png;
  EXPECT_EQ(w, png.width);
  EXPECT_EQ(h, png.height);
  for (int i = 0; i < w * h; ++i)
    png.rgb.push_back(static_cast<std::uint32_t>(pixels[3 * i]) << 16 | pixels[3 * i + 1] << 8 | pixels[3 * i + 2]);
  stbi_image_free(pixels);
  return png;
}

std::size_t pixels_of(const Png& png, std::uint32_t colour) {
  return static_cast<std::size_t>(std::count(png.rgb.begin(), png.rgb.end(), colour));
}

std::size_t colours_in(const Png& png) { return std::set<std::uint32_t>(png.rgb.begin(), png.rgb.end()).size(); }

// tools/plots/plot_run.py's colours for the path, collision marks, truth, reading and no echo.
constexpr std::uint32_t kPath = 0xe6007e, kCollision = 0xff0000, kTruth = 0x1f77b4, kReading = 0xff7f0e,
                        kNoEcho = 0x7f7f7f;

// Pixels of `colour` in image rows [top, bottom).
std::size_t pixels_in_rows(const Png& png, std::uint32_t colour, int top, int bottom) {
  std::size_t n = 0;
  for (int y = std::max(top, 0); y < std::min(bottom, png.height); ++y)
    for (int x = 0; x < png.width; ++x) n += png.rgb[static_cast<std::size_t>(y) * png.width + x] == colour;
  return n;
}

// Waits for a background plotter of `out` to finish: it holds an flock on the folder until then.
void wait_for_plotter(const fs::path& out) {
  const int fd = open(out.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ASSERT_GE(fd, 0) << out;
  EXPECT_EQ(flock(fd, LOCK_EX), 0);
  close(fd);
}

std::vector<std::string> plots_in(const fs::path& out) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string().rfind("plot_", 0) == 0) found.push_back(e.path().filename().string());
  return found;
}

class Plots : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    out_ = dir_->path() / "out";
    run_for_plots(*dir_, out_);
    ::testing::internal::CaptureStderr();
    plotted_ = write_plots(out_.string());
    plot_err_ = ::testing::internal::GetCapturedStderr();
  }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
  static fs::path out_;
  static bool plotted_;
  static std::string plot_err_;
};
TempDir* Plots::dir_ = nullptr;
fs::path Plots::out_;
bool Plots::plotted_ = false;
std::string Plots::plot_err_;

TEST(WorldJson, HoldsTheTerrainGridAndEveryObstacle) {
  TempDir dir;
  Diagnostics diagnostics;
  const auto project = load_project(dir.write("project.xml", plots_project()), diagnostics);
  ASSERT_TRUE(project) << diagnostics.joined();
  const Json w = Json::parse(world_json(*project));
  EXPECT_EQ(w["terrain"]["kind"], "heightmap");
  EXPECT_EQ(w["terrain"]["size_m"], Json::array({40.0, 40.0}));
  const auto& grid = w["terrain"]["heights_m"];
  ASSERT_EQ(grid.size(), static_cast<std::size_t>(kHillsSamples));
  ASSERT_EQ(grid[0].size(), static_cast<std::size_t>(kHillsSamples));
  // Under the cap: every sample as loaded, row 0 the north edge as in the description.
  for (std::size_t r = 0; r < grid.size(); ++r)
    for (std::size_t c = 0; c < grid[r].size(); ++c)
      ASSERT_EQ(grid[r][c].get<double>(), project->world.terrain.heights_m[r * kHillsSamples + c]) << r << "," << c;
  EXPECT_EQ(w["obstacles"]["boxes"][0]["center_m"], Json::array({1.3, 4.0}));
  EXPECT_EQ(w["obstacles"]["trees"][0]["crown_radius_m"], 1.2);
  EXPECT_EQ(w["obstacles"]["walls"][0]["to_m"], Json::array({6.0, 7.0}));
  // The rock's outline surrounds its position and no point of it is farther than the mesh is big.
  const auto& rock = w["obstacles"]["meshes"][0]["footprint_m"];
  ASSERT_GE(rock.size(), 3u);
  double area = 0;  // shoelace: positive for a counter-clockwise outline
  for (std::size_t i = 0; i < rock.size(); ++i) {
    const auto& a = rock[i];
    const auto& b = rock[(i + 1) % rock.size()];
    area += a[0].get<double>() * b[1].get<double>() - b[0].get<double>() * a[1].get<double>();
  }
  EXPECT_GT(area / 2, 0.01);
  for (const auto& p : rock) EXPECT_LT(std::hypot(p[0].get<double>() - 2, p[1].get<double>() + 2), 3.0);
  EXPECT_EQ(w["robots"][0]["mcus"][0]["devices"][0]["wires"]["uart"], 3);
  EXPECT_EQ(w["gps_origin"]["latitude_deg"], 52.2053);
}

TEST(WorldJson, SamplesALargeHeightmapDownToTheCap) {
  ProjectDesc p;
  p.world.terrain.kind = TerrainKind::Heightmap;
  p.world.terrain.columns = 1000;  // every 4th sample: 250 columns
  p.world.terrain.rows = 600;      // 150 rows
  p.world.terrain.size_m = {100, 60};
  for (int r = 0; r < p.world.terrain.rows; ++r)
    for (int c = 0; c < p.world.terrain.columns; ++c) p.world.terrain.heights_m.push_back(r * 1000 + c);
  const Json w = Json::parse(world_json(p));
  const auto& grid = w["terrain"]["heights_m"];
  ASSERT_EQ(grid.size(), 150u);
  ASSERT_EQ(grid[0].size(), 250u);
  EXPECT_EQ(grid[1][1], 4 * 1000 + 4);
  EXPECT_EQ(grid[149][249], 596 * 1000 + 996);
}

TEST_F(Plots, SensorCsvHoldsTheCompassFieldAtTheTraceRate) {
  const auto lines = lines_of(read_file(out_ / "sensors_gps.csv"));
  ASSERT_GT(lines.size(), 1u);
  EXPECT_EQ(lines[0], "time_s,mcu,device,quantity,unit,value,source");
  std::vector<double> times, reading_times;
  double field_sq = 0, reading_sq = 0;
  int fields = 0, readings = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::istringstream row(lines[i]);
    std::string t, mcu, device, quantity, unit, value, source;
    std::getline(row, t, ',');
    std::getline(row, mcu, ',');
    std::getline(row, device, ',');
    std::getline(row, quantity, ',');
    std::getline(row, unit, ',');
    std::getline(row, value, ',');
    std::getline(row, source, ',');
    ASSERT_EQ(device, "compass") << lines[i];  // the GPS's model runs in the simulator: no samples
    EXPECT_EQ(unit, "T");
    ASSERT_TRUE(source == "truth" || source == "reading") << lines[i];
    const double v = std::stod(value);
    if (source == "truth") {
      if (quantity == "field_x") times.push_back(std::stod(t));
      field_sq += v * v;
      ++fields;
    } else {
      if (quantity == "field_x") reading_times.push_back(std::stod(t));
      reading_sq += v * v;
      ++readings;
    }
  }
  // One sample per trace period over the run, the first at t = 0.
  EXPECT_NEAR(static_cast<double>(times.size()), kDuration_s * kTraceRate_hz, 1.0);
  for (std::size_t i = 1; i < times.size(); ++i) EXPECT_NEAR(times[i] - times[i - 1], 1 / kTraceRate_hz, 1e-9);
  // The Earth's field at Cambridge (WMM): about 49 µT in total.
  EXPECT_NEAR(std::sqrt(field_sq / (fields / 3)), 49e-6, 3e-6);
  // The firmware runs the HMC5883L at 15 Hz, slower than the 50 Hz trace period thins to: a
  // reading for each result once it is set up, plus the registers' zeros at t = 0, in time order.
  ASSERT_GT(reading_times.size(), 20u);
  EXPECT_LE(static_cast<double>(reading_times.size()), kDuration_s * 15 + 2);
  for (std::size_t i = 1; i < reading_times.size(); ++i) EXPECT_GT(reading_times[i], reading_times[i - 1]);
  // Decoded at the firmware's gain, the same field, once the firmware set the part up (the first
  // reading, before it, is the registers' zeros).
  EXPECT_NEAR(std::sqrt(reading_sq / (readings / 3 - 1)), 49e-6, 3e-6);
}

TEST_F(Plots, EveryPlotIsA1200x900PngShowingItsData) {
  ASSERT_TRUE(plotted_) << plot_err_ << read_file(out_ / "plots.log");
  EXPECT_EQ(plot_err_, "");
  EXPECT_FALSE(fs::exists(out_ / "plots.log"));  // nothing to say
  const std::vector<std::string> names = {"plot_trajectory_gps.png", "plot_trajectory_bumper.png",
                                          "plot_motors_gps.png",     "plot_motors_bumper.png",
                                          "plot_sensor_gps.main.compass.png", "plot_sensor_gps.main.gps.png"};
  std::set<std::string> written;
  for (const auto& e : fs::directory_iterator(out_))
    if (e.path().extension() == ".png") written.insert(e.path().filename().string());
  EXPECT_EQ(written, std::set<std::string>(names.begin(), names.end()));
  for (const auto& name : names) {
    SCOPED_TRACE(name);
    const Png png = read_png(out_ / name);
    EXPECT_EQ(png.width, kPlotWidth);
    EXPECT_EQ(png.height, kPlotHeight);
    EXPECT_GT(colours_in(png), 50u);  // not a blank canvas
  }
  // The paths are drawn; the crate's collision is marked on the bumper's only.
  const Png bumper = read_png(out_ / "plot_trajectory_bumper.png");
  const Png gps = read_png(out_ / "plot_trajectory_gps.png");
  EXPECT_GT(pixels_of(bumper, kPath), 500u);
  EXPECT_GT(pixels_of(gps, kPath), 100u);  // at least its start and end marks
  EXPECT_GT(pixels_of(bumper, kCollision), 50u);
  EXPECT_EQ(pixels_of(gps, kCollision), 0u);
  // The terrain is drawn as an image with a colour bar: far more colours than a flat world's.
  EXPECT_GT(colours_in(bumper), 1000u);
  // The compass's truth and the reading its model gave the firmware; the GPS's fixes against the
  // trace's truth.
  const Png compass = read_png(out_ / "plot_sensor_gps.main.compass.png");
  EXPECT_GT(pixels_of(compass, kTruth), 500u);
  EXPECT_GT(pixels_of(compass, kReading), 500u);
  const Png fixes = read_png(out_ / "plot_sensor_gps.main.gps.png");
  EXPECT_GT(pixels_of(fixes, kTruth), 500u);
  EXPECT_GT(pixels_of(fixes, kReading), 100u);
}

TEST_F(Plots, TheBumperCollidedWithTheCrate) {
  const Json s = Json::parse(read_file(out_ / "summary.json"));
  ASSERT_FALSE(s["collision_events"].empty());
  EXPECT_EQ(s["collision_events"][0]["robot"], "bumper");
  EXPECT_EQ(s["collision_events"][0]["other"], "crate");
}

TEST(PlotRunner, AMissingInterpreterIsOneWarningLine) {
  TempDir dir;
  setenv("SEAR_PYTHON", "/nonexistent/python3", 1);
  ::testing::internal::CaptureStderr();
  const bool plotted = write_plots(dir.path().string());
  const std::string err = ::testing::internal::GetCapturedStderr();
  unsetenv("SEAR_PYTHON");
  EXPECT_FALSE(plotted);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("sear: warning: no plots: cannot start /nonexistent/python3"), std::string::npos) << err;
}

TEST(PlotRunner, APlotterWithoutMatplotlibIsOneWarningLineNamingThePackage) {
  // Debian's python3 with a matplotlib that fails to import put first on its path.
  TempDir dir;
  dir.write("fake/matplotlib/__init__.py", "raise ImportError('not installed here')\n");
  const std::string python = dir.write("python_without_matplotlib", "#!/bin/sh\nPYTHONPATH='" +
                                                                      (dir.path() / "fake").string() +
                                                                      "' exec /usr/bin/python3 \"$@\"\n");
  fs::permissions(python, fs::perms::owner_all);
  setenv("SEAR_PYTHON", python.c_str(), 1);
  ::testing::internal::CaptureStderr();
  const bool plotted = write_plots(dir.path().string());
  const std::string err = ::testing::internal::GetCapturedStderr();
  unsetenv("SEAR_PYTHON");
  EXPECT_FALSE(plotted);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("python3-matplotlib"), std::string::npos) << err;
}

// `sear run` itself: a run whose interpreter is missing exits 0 with one warning line; a run
// draws its plots, and --no-plots draws none.
TEST(PlotsOfSearRun, AMissingInterpreterLeavesTheRunsExitCodeAlone) {
  TempDir dir;
  // The suite turns plots off for every other test (SEAR_NO_PLOTS=1, tests/CMakeLists.txt); here
  // they are what is checked.
  unsetenv("SEAR_NO_PLOTS");
  setenv("SEAR_PYTHON", "/nonexistent/python3", 1);
  const auto run = run_sear(dir, rover_project("", "", 0.2));
  unsetenv("SEAR_PYTHON");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_NE(run.err.find("no plots"), std::string::npos) << run.err;
  EXPECT_TRUE(fs::exists(run.dir / "world.json"));

  const auto plotted = run_sear(dir, rover_project("", "", 0.2));
  EXPECT_EQ(plotted.exit_code, 0) << plotted.err;
  wait_for_plotter(plotted.dir);  // drawn in the background, after `sear run` exited
  EXPECT_TRUE(fs::exists(plotted.dir / "plot_trajectory_rover.png")) << plotted.err;
  EXPECT_FALSE(fs::exists(plotted.dir / "plots.log"));  // nothing to say
  fs::remove_all(plotted.dir);
  const auto skipped = run_sear(dir, rover_project("", "", 0.2), "--no-plots");
  EXPECT_EQ(skipped.exit_code, 0) << skipped.err;
  EXPECT_FALSE(fs::exists(skipped.dir / "plot_trajectory_rover.png"));
  setenv("SEAR_NO_PLOTS", "1", 1);
}

// A run into a folder whose previous run's plotter still draws waits for it (it reads the files
// the new run rewrites), then removes its plots: none of them is taken for the new run's. Were
// the wait or the removal missing, the first run's plots would be in the folder at the end.
TEST(PlotsOfSearRun, ANewRunWaitsForTheLastPlotterAndRemovesItsPlots) {
  TempDir dir;
  unsetenv("SEAR_NO_PLOTS");
  const auto plotted = run_sear(dir, rover_project("", "", 0.2));
  setenv("SEAR_NO_PLOTS", "1", 1);
  EXPECT_EQ(plotted.exit_code, 0) << plotted.err;
  const auto next = run_sear(dir, rover_project("", "", 0.2), "--quiet");
  EXPECT_EQ(next.exit_code, 0) << next.err;
  wait_for_plotter(next.dir);
  EXPECT_EQ(plots_in(next.dir), std::vector<std::string>{});
}

// An HC-SR04 that hears nothing drops ECHO after its 38 ms time-out, which a firmware reads as
// 6.55 m, beyond the part's 4 m: the plot shows those readings as "no echo" marks and a gap, not
// as a line at 6.55 m. A synthetic run: 2 m for its first second, then no echo for a second.
TEST(PlotRunner, AnEchoTimeOutIsDrawnAsNoEchoNotAsARange) {
  TempDir dir;
  dir.write("world.json", R"({"robots": [{"name": "r", "mcus": [{"name": "m", "avcc_v": 5, "devices": [
      {"name": "sonar", "element": "hcsr04", "wires": {"trig": 24, "echo": 10}, "params": {}}]}]}]})");
  dir.write("trace_r.csv", "time_s,x_m,y_m\n0,0,0\n2,0.5,0\n");
  std::string csv = "time_s,mcu,device,quantity,unit,value,source\n";
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.02 * i;
    const bool echo = t < 1.0;
    csv += fmt::format("{:.9f},m,sonar,distance,m,{},truth\n", t, echo ? "2.0" : "inf");
    // 2 m: 2 x 58 us per cm x 200 cm = 11.6 ms; no echo: the 38 ms time-out, read as 6.5517 m.
    csv += fmt::format("{:.9f},m,sonar,echo_width,s,{},reading\n", t, echo ? 0.0116 : 0.038);
    csv += fmt::format("{:.9f},m,sonar,distance,m,{},reading\n", t, echo ? 2.0 : 0.038 / 58e-6 / 100);
  }
  dir.write("sensors_r.csv", csv);
  ::testing::internal::CaptureStderr();
  const bool plotted = write_plots(dir.path().string());
  const std::string err = ::testing::internal::GetCapturedStderr();
  ASSERT_TRUE(plotted) << err << read_file(dir.path() / "plots.log");
  const Png png = read_png(dir.path() / "plot_sensor_r.m.sonar.png");
  ASSERT_EQ(png.height, kPlotHeight);
  // The distance panel, the upper of two: plot_run.py's margins put it from 10 % of the height
  // (top = 0.9) down to 46 % (two panels in 0.83 of the height, 0.3 of one between them).
  const int top = kPlotHeight / 10, bottom = kPlotHeight * 46 / 100;
  // The valid second is drawn (a 2 m line half the panel wide, ~500 px), the time-outs are marked...
  EXPECT_GT(pixels_in_rows(png, kReading, top, bottom), 300u);
  EXPECT_GT(pixels_in_rows(png, kNoEcho, top, bottom), 500u);  // 50 marks; ~10 grey pixels of antialiased text without
  // ...and no reading is drawn in the panel's top fifth, where a 6.55 m line at the top of a
  // range scaled to it would run (the 2 m line sits mid-panel on a range fitted to 2 m).
  EXPECT_EQ(pixels_in_rows(png, kReading, top + 8, top + (bottom - top) / 5), 0u);
}

}  // namespace
}  // namespace sear::test
