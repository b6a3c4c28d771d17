// The per-robot CSV trace of a run: pose, velocities, wheel speeds and actuator commands,
// sampled at the trace rate, one file per robot.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "exporters/bounded_file.hpp"
#include "runtime/simulation.hpp"

namespace sear {

// One column of the trace, or one per wheel, motor or servo (`{}` in its name stands for the
// part's name; a part's columns stand together). The one list the header is written from;
// docs/outputs.md's description of the file is generated from it too (trace_columns_markdown) and a
// test holds that page to it.
enum class TracePer { Robot, Wheel, Motor, Servo, Joint };
struct TraceColumn {
  const char* name;
  TracePer per;
  const char* meaning;  // Markdown; empty: the same as the column before
};
const std::vector<TraceColumn>& trace_columns();
std::string trace_columns_markdown();

class TraceCsv {
 public:
  // Opens `folder`/trace_<robot>.csv for every robot and writes the header lines; no file grows
  // past max_file_bytes.
  TraceCsv(const std::string& folder, const Simulation& sim, std::uint64_t max_file_bytes);
  void write_row(const Simulation& sim);
  // Pushes the rows written to the files; a full disk is an error, not a silently short trace.
  void flush();
  // Its files, one per robot, for listing and for reporting those cut short.
  std::vector<const BoundedFile*> outputs() const;

 private:
  std::vector<std::unique_ptr<BoundedFile>> files_;
};

}  // namespace sear
