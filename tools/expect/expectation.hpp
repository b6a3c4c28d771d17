// What a headless run is expected to do, as a scenario's <expect> element describes it: console
// lines, regions reached, collisions, pin levels, UART traffic, MCUs that keep running.
// Times are integer nanoseconds of simulated time; positions are world x east, y north, in metres.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <variant>
#include <vector>

#include "scene/description.hpp"

namespace sear {

// <console mcu=... matches=... before=...> or <console mcu=... never=...>: an ECMAScript regular
// expression searched for in each whole console line (as console.log holds it: no '\r', no '\n').
struct ConsoleExpect {
  std::string pattern;
  std::shared_ptr<const std::regex> regex;  // compiled once by the loader
  bool never = false;
};

// <region robot=... shape="circle|box" ...>: the chassis origin inside, at some step's end.
struct RegionExpect {
  enum class Shape { Circle, Box } shape = Shape::Circle;
  Eigen::Vector2d center_m{0, 0};
  double radius_m = 0;
  Eigen::Vector2d min_m{0, 0};
  Eigen::Vector2d max_m{0, 0};
};

// <no_collision robot=... with=...>: the robot never starts touching `with` (empty: anything).
struct CollisionExpect {
  std::string with;
};

// <pin mcu=... pin=... level=... at=...> or from=... to=...: the MCU drives `level` on the pin at
// that instant, or over the whole closed interval (at: from_ns == to_ns).
struct PinExpect {
  int pin = 0;
  int level = 0;
  std::int64_t from_ns = 0;
  std::int64_t to_ns = 0;
};

// <uart mcu=... port=... direction="tx|rx" at_least=N | contains="text" | hex="B5 62">: bytes on
// the line of that port, sent by the MCU (tx) or arriving at its RX pin (rx).
struct UartExpect {
  int port = 0;
  bool tx = true;
  std::uint64_t at_least = 0;  // 0: `pattern` is looked for instead
  std::string pattern;         // the bytes in a row, from `contains` or `hex`
  bool hex = false;            // how `pattern` was written, for messages
};

// <mcu_running mcu=...>: the firmware never stops (no crash, exit, hang or refusal).
struct RunningExpect {};

struct Expectation {
  std::string name;  // the JUnit test case's name: given, or describe()'s text
  SourceRef source;
  std::string mcu;    // "robot.mcu": console, pin, uart, mcu_running
  std::string robot;  // region, no_collision
  // "before": by this sim time, inclusive (console matches, region, uart); none: the timeout.
  std::optional<std::int64_t> before_ns;
  std::variant<ConsoleExpect, RegionExpect, CollisionExpect, PinExpect, UartExpect, RunningExpect> what;
};

// A readable description, the default name: `console rover.main matches "wp 4/4" before 50 s`.
std::string describe(const Expectation& e);

// A run to check: a project, optionally with its own seed and timeout, and what must happen.
struct Scenario {
  std::string file;          // the scenario file, or the project file whose <expect> was read
  std::string name;          // <scenario name>, else the project's name or the file's stem
  std::string project_file;  // absolute
  std::optional<std::uint64_t> seed;       // overrides the project's <run seed>
  std::optional<std::int64_t> timeout_ns;  // pending expectations fail here; none: the run's end
  std::vector<Expectation> expectations;
};

// Sim time as "12.400 s", the form every verdict and message uses.
std::string seconds_text(std::int64_t ns);

}  // namespace sear
