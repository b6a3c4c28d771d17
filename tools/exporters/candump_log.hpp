// A simulated CAN bus's traffic as can-utils' `candump -l` writes it, stamped with sim time, so
// log2long, canplayer and the usual log tools read a run's bus as they read a real one.
#pragma once

#include <cstdint>
#include <string>

#include "exporters/bounded_file.hpp"
#include "runtime/can_bus.hpp"

namespace sear {

class CandumpLog {
 public:
  // `iface` names the bus in every line (canplayer maps it to an interface): 1 to 15 characters
  // (IFNAMSIZ - 1) without blanks, or std::invalid_argument. With `acked_only` a frame nobody
  // acked is left out: a candump on a real bus is a receiving node, which would have acked it.
  CandumpLog(std::string path, std::string iface, std::uint64_t max_file_bytes, bool acked_only = true);

  // Writes one line, stamped with the transfer's end (when receivers take the frame): transfers
  // come in the bus's order, which is the order of their ends.
  void write(const CanTransfer& transfer);
  // Call once per step, so that a killed run has lost nothing already written.
  void flush() { file_.flush(); }
  const BoundedFile& file() const { return file_; }

  // "(0000000001.000250) can0 123#DEADBEEF": seconds.microseconds (truncated), the ID as 3 or 8
  // uppercase hex digits, the data as uppercase hex pairs; a remote frame is "ID#R" followed by
  // its DLC when that is not 0, as can-utils 2020.11's sprint_canframe prints classical frames.
  static std::string line(const std::string& iface, const CanTransfer& transfer);

 private:
  BoundedFile file_;
  std::string iface_;
  bool acked_only_;
};

}  // namespace sear
