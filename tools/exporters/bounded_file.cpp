#include "exporters/bounded_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sear {

std::string text_truncation_note(std::uint64_t limit_bytes) {
  return fmt::format("# truncated: this file reached its limit of {} bytes (sear run --max-file-mb); the rest of the run "
                     "is not in it\n",
                     limit_bytes);
}

std::string vcd_truncation_note(std::uint64_t limit_bytes) {
  return fmt::format("$comment truncated: this file reached its limit of {} bytes (sear run --max-file-mb); the rest "
                     "of the run is not in it $end\n",
                     limit_bytes);
}

BoundedFile::BoundedFile(std::string path, std::uint64_t limit_bytes, std::string note)
    : path_(std::move(path)), limit_(limit_bytes), note_(std::move(note)) {
  file_ = std::fopen(path_.c_str(), "wb");
  if (!file_) throw std::runtime_error(fmt::format("{}: error: cannot write: {}", path_, std::strerror(errno)));
  // The run flushes on a wall-clock period (FlushClock); between flushes a busy file (a VCD takes
  // megabytes a simulated second) fills a 64 KiB buffer before it costs a write(2), not 4 KiB.
  // (glibc ignores the size unless it is given the buffer.)
  buffer_ = std::make_unique<char[]>(kBufferBytes);
  std::setvbuf(file_, buffer_.get(), _IOFBF, kBufferBytes);
}

BoundedFile::~BoundedFile() {
  if (file_) std::fclose(file_);
}

void BoundedFile::write(std::string_view bytes) {
  if (dropped_ > 0) {
    dropped_ += bytes.size();
    return;
  }
  // Room is kept for the note, so that the file with its note stays within the limit.
  const std::uint64_t room = limit_ > note_.size() ? limit_ - note_.size() : 0;
  if (written_ + bytes.size() <= room) {
    // One thread writes each file; a UART capture calls this for every byte.
    fwrite_unlocked(bytes.data(), 1, bytes.size(), file_);
    written_ += bytes.size();
    return;
  }
  std::fwrite(note_.data(), 1, note_.size(), file_);
  written_ += note_.size();
  dropped_ = bytes.size();
}

void BoundedFile::flush() {
  if (std::fflush(file_) != 0 || std::ferror(file_))
    throw std::runtime_error(fmt::format("{}: error: write failed: {}", path_, std::strerror(errno)));
}

}  // namespace sear
