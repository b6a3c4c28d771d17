// Every CAN bus of a run recorded as OUT/<bus>.candump.log (candump -l's format, sim time), as a
// tap on the run: written as frames are decided, flushed when the run flushes its files.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "exporters/candump_log.hpp"
#include "runtime/run_tap.hpp"
#include "scene/description.hpp"

namespace sear {

class CanLogs final : public RunTap {
 public:
  CanLogs(const std::string& out_dir, const std::vector<CanBusDesc>& buses, std::uint64_t max_file_bytes);
  void on_can_frame(std::size_t bus, const CanTransfer& transfer) override { logs_[bus]->write(transfer); }
  void flush();
  std::vector<const BoundedFile*> outputs() const;

 private:
  std::vector<std::unique_ptr<CandumpLog>> logs_;
};

}  // namespace sear
