// `sear run --cross-check`: the same project, scenario and seed on both engines (native, then
// the AVR engine), each into its own folder, and where they part: console lines that differ,
// bytes sent that differ, final poses further apart than a stated bound, each with its likely
// cause. The native engine charges every HAL call a fixed cost (<mcu hal_call_cycles>) where the
// chip takes its real cycles, so times differ by design; what a firmware says and sends should not.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "expect/scenario_loader.hpp"
#include "sear/commands.hpp"
#include "sear/run_folder.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;

// A final position further apart than this is a difference: a few centimetres is what a turn
// decided a few milliseconds apart (the engines' timing) moves a small rover in 20 s.
constexpr double kPoseBound_m = 0.1;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ConsoleLine {
  double time_s;
  std::string text;
};

// A console log's lines: "12.345 text" (the time the line ended, as the capture writes it).
std::vector<ConsoleLine> console_lines(const fs::path& path) {
  std::vector<ConsoleLine> lines;
  std::istringstream in(read_text(path));
  for (std::string line; std::getline(in, line);) {
    const auto space = line.find(' ');
    double t = 0;
    try {
      t = std::stod(line.substr(0, space));
    } catch (...) {
      continue;
    }
    lines.push_back({t, space == std::string::npos ? "" : line.substr(space + 1)});
  }
  return lines;
}

}  // namespace

int cross_check_command(const RunOptions& given) {
  RunOptions options = given;
  // Both runs in one folder, a run's folder like any other (sear-out/SCENARIO by default).
  const bool default_folder = options.out_dir.empty();
  if (default_folder) {
    Diagnostics diagnostics;
    const auto scenario = load_scenario(resolve_project_path(options.project), diagnostics);
    if (!scenario) {
      fmt::print(stderr, "{}", diagnostics.joined());
      return 1;
    }
    options.out_dir = default_run_folder(scenario->name, false);
  }
  try {
    prepare_run_folder(options.out_dir);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  if (default_folder) point_latest_at(options.out_dir);
  const std::string engines[2] = {"native", "avr"};
  int codes[2] = {0, 0};
  for (int e = 0; e < 2; ++e) {
    RunOptions o = options;
    o.cross_check = false;
    o.eeprom_copies = true;
    o.engine = engines[e];
    o.out_dir = (fs::path(options.out_dir) / engines[e]).string();
    codes[e] = run_command(o);
    // 0: completed, 5: an expectation failed; anything else ended the run early (bad input, an MCU
    // stopped): that is the first difference worth knowing.
    if (codes[e] != 0 && codes[e] != kExpectationFailedExitCode) {
      fmt::print(stderr, "sear: cross-check: the run on the {} engine ended with code {}; see {}\n", engines[e], codes[e],
                 o.out_dir);
      return codes[e];
    }
  }
  const fs::path native = fs::path(options.out_dir) / "native", avr = fs::path(options.out_dir) / "avr";
  nlohmann::ordered_json report;
  report["pose_bound_m"] = kPoseBound_m;
  report["differences"] = nlohmann::ordered_json::array();
  const auto differ = [&](const std::string& what, const std::string& detail, const std::string& cause) {
    report["differences"].push_back({{"what", what}, {"detail", detail}, {"likely_cause", cause}});
  };
  if (codes[0] != codes[1])
    differ("exit code", fmt::format("native {}, avr {}", codes[0], codes[1]),
           "an expectation decided differently: see the differences below");

  const auto a = nlohmann::json::parse(read_text(native / "summary.json"), nullptr, false);
  const auto b = nlohmann::json::parse(read_text(avr / "summary.json"), nullptr, false);
  if (a.is_discarded() || b.is_discarded()) {
    fmt::print(stderr, "sear: cross-check: a run left no summary.json\n");
    return 1;
  }
  for (std::size_t r = 0; r < a["robots"].size() && r < b["robots"].size(); ++r) {
    const auto& pa = a["robots"][r]["final_position_m"];
    const auto& pb = b["robots"][r]["final_position_m"];
    const double d = std::hypot(pa[0].get<double>() - pb[0].get<double>(), pa[1].get<double>() - pb[1].get<double>());
    report["robots"][a["robots"][r]["name"].get<std::string>()] = {{"final_distance_m", d}};
    if (d > kPoseBound_m)
      differ(fmt::format("robot {} final position", a["robots"][r]["name"].get<std::string>()),
             fmt::format("{:.3f} m apart (bound {:.3f} m)", d, kPoseBound_m),
             "the firmware decided at different times: the native engine's fixed HAL call cost against the chip's real "
             "cycles, and ADC, PWM and UART timing from the chip's registers");
  }

  for (const auto& entry : fs::directory_iterator(native)) {
    const std::string name = entry.path().filename().string();
    const auto ends_with = [&](const std::string& tail) {
      return name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
    };
    if (ends_with(".console.log")) {
      const auto la = console_lines(entry.path()), lb = console_lines(avr / name);
      double worst_dt = 0;
      std::size_t same = 0;
      while (same < la.size() && same < lb.size() && la[same].text == lb[same].text) {
        worst_dt = std::max(worst_dt, std::fabs(la[same].time_s - lb[same].time_s));
        ++same;
      }
      report["consoles"][name] = {{"lines_native", la.size()}, {"lines_avr", lb.size()}, {"lines_alike", same},
                                  {"worst_time_difference_s", worst_dt}};
      if (same < la.size() || same < lb.size())
        differ(name, fmt::format("line {} differs: native \"{}\", avr \"{}\"", same + 1,
                                 same < la.size() ? la[same].text : "(none)", same < lb.size() ? lb[same].text : "(none)"),
               "a decision or a reading taken at a different time (the HAL's cost model against real cycles), or a "
               "number the chip computes differently (16-bit int, float printf support in avr-libc)");
    } else if (ends_with(".tx.bin")) {
      const std::string ta = read_text(entry.path()), tb = read_text(avr / name);
      report["uart_bytes"][name] = {{"native", ta.size()}, {"avr", tb.size()}};
      if (ta != tb) {
        std::size_t at = 0;
        while (at < ta.size() && at < tb.size() && ta[at] == tb[at]) ++at;
        differ(name, fmt::format("{} and {} bytes sent, first difference at byte {}", ta.size(), tb.size(), at),
               "what the console lines differ by, or a byte cut off by the run's end on one engine");
      }
    }
  }
  const std::string json = report.dump(2) + "\n";
  std::ofstream(fs::path(options.out_dir) / "cross_check.json") << json;
  if (!options.quiet) {
    fmt::print("sear: cross-check of native and avr: {} difference(s); {}/cross_check.json\n",
               report["differences"].size(), options.out_dir);
    for (const auto& d : report["differences"])
      fmt::print("  {}: {}\n    likely cause: {}\n", d["what"].get<std::string>(), d["detail"].get<std::string>(),
                 d["likely_cause"].get<std::string>());
  }
  return report["differences"].empty() ? 0 : kExpectationFailedExitCode;
}

}  // namespace sear
