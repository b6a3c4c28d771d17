#include "exporters/candump_log.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace sear {

namespace {

void check_iface(const std::string& iface) {
  bool blank = false;
  for (char c : iface) blank = blank || c == ' ' || c == '\t' || c == '\n' || c == '\r';
  if (iface.empty() || iface.size() > 15 || blank)
    throw std::invalid_argument("candump interface name '" + iface + "' must be 1 to 15 characters without blanks");
}

}  // namespace

CandumpLog::CandumpLog(std::string path, std::string iface, std::uint64_t max_file_bytes, bool acked_only)
    : file_(std::move(path), max_file_bytes, text_truncation_note(max_file_bytes)),
      iface_(std::move(iface)),
      acked_only_(acked_only) {
  check_iface(iface_);
}

std::string CandumpLog::line(const std::string& iface, const CanTransfer& t) {
  const CanFrame& f = t.frame;
  std::string out =
      fmt::format("({:010d}.{:06d}) {} ", t.end_ns / 1'000'000'000, t.end_ns % 1'000'000'000 / 1000, iface);
  out += f.extended ? fmt::format("{:08X}#", f.id & 0x1FFFFFFFu) : fmt::format("{:03X}#", f.id & 0x7FFu);
  if (f.remote) {
    out += 'R';
    if (f.dlc > 0 && f.dlc <= 8) out += fmt::format("{:X}", f.dlc);
  } else {
    for (std::size_t i = 0; i < f.dlc && i < 8; ++i) out += fmt::format("{:02X}", f.data[i]);
  }
  out += '\n';
  return out;
}

void CandumpLog::write(const CanTransfer& transfer) {
  if (acked_only_ && !transfer.acked) return;
  file_.write(line(iface_, transfer));
}

}  // namespace sear
