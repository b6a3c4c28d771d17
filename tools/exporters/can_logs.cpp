#include "exporters/can_logs.hpp"

namespace sear {

CanLogs::CanLogs(const std::string& out_dir, const std::vector<CanBusDesc>& buses, std::uint64_t max_file_bytes) {
  // A bus's name is a project name (letters, digits, '_' and '-'); candump's interface field
  // holds 15 characters, so a longer name is cut there in the lines, not in the file name.
  for (const auto& bus : buses)
    logs_.push_back(std::make_unique<CandumpLog>(out_dir + "/" + bus.name + ".candump.log", bus.name.substr(0, 15),
                                                 max_file_bytes));
}

void CanLogs::flush() {
  for (auto& log : logs_) log->flush();
}

std::vector<const BoundedFile*> CanLogs::outputs() const {
  std::vector<const BoundedFile*> files;
  for (const auto& log : logs_) files.push_back(&log->file());
  return files;
}

}  // namespace sear
